/* spr_bsp.h — axis-aligned BSP (kd) tree over splat centres (SPEC §5.6).
 *
 * Split at the median of the longest extent until ≤ 64 splats per leaf;
 * each leaf stores its average normal (used by hash grouping for the axis).
 * Back-to-front order for a view: at every split, the child on the far side
 * of the plane from the eye first; inside a leaf, centres by decreasing view
 * depth (ties: index).
 */
#ifndef SPR_BSP_H
#define SPR_BSP_H

#include <stdint.h>
#include "spr_camera.h"
#include "spr_cloud.h"

#define SPR_BSP_LEAF 64

typedef struct spr_bsp_node {
    int axis;            /* −1 for a leaf */
    float split;         /* left: coordinate < split (by position in the sorted order) */
    int32_t left, right; /* child nodes */
    uint32_t first, count; /* leaf: order[first … first+count) */
    float normal[3];     /* leaf: normalised average normal */
} spr_bsp_node;

typedef struct spr_bsp {
    spr_bsp_node *nodes;
    size_t n_nodes;
    uint32_t *order;     /* splat ids, leaf by leaf */
    uint32_t *leaf_of;   /* node index of each splat's leaf */
    size_t n;
} spr_bsp;

spr_result spr_bsp_build(const spr_cloud *c, spr_bsp *t, spr_error *err);
/* The same tree on at most `threads` threads (0: OpenMP's default). */
spr_result spr__bsp_build_threads(const spr_cloud *c, int threads, spr_bsp *t, spr_error *err);
void spr_bsp_free(spr_bsp *t);
/* Back-to-front splat order for the view (out: n ids). */
int spr_bsp_back_to_front(const spr_bsp *t, const spr_cloud *c, const spr_view *v, uint32_t *out); /* −1: out of memory */
/* The same order on at most `threads` threads (0: OpenMP's default). */
int spr__bsp_back_to_front_threads(const spr_bsp *t, const spr_cloud *c, const spr_view *v, int threads, uint32_t *out);

#endif
