/* sw_internal.h — private state of the CPU backend, shared by its stages. */
#ifndef SW_INTERNAL_H
#define SW_INTERNAL_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "spr_backend.h"
#include "spr_arith_c.h"
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#define SW_TILE 32

/* A target: one array per plane of the plane table (4-byte values,
 * channels per pixel as the table says); NULL for planes it lacks. */
typedef struct sw_target {
    void *plane[SPR_PLANE__COUNT];
    size_t pixels;    /* size the buffers were allocated for */
    spr_frag_lists lists; /* fragment lists of the last list draw (first == NULL: none) */
    /* A clear is done lazily, tile by tile (SW_TILE² pixels of the tile grid):
     * creation or spr_backend_clear only records the pattern; a splat draw
     * fills the tiles it draws into just before it draws, a composite reads
     * a tile pending the zero clear from the context's zband (and fills
     * those of another clear), and any other use fills every tile still
     * pending (sw__target). */
    int pending;      /* some tile may still be pending */
    int zero_clear;   /* the pending clear is the zero clear (colour 0, every other plane its table value) */
    unsigned planes;  /* the target's planes */
    uint8_t *tpend;   /* per tile of the grid: 1 = not yet filled with pval */
    size_t ntiles;    /* tiles tpend was allocated for */
    uint32_t pval[SPR_PLANE__COUNT][4]; /* the pending clear of every plane, one pixel's words */
} sw_target;
#define SW_F(t, p) ((float *)(t)->plane[SPR_PLANE_##p])
#define SW_U(t, p) ((uint32_t *)(t)->plane[SPR_PLANE_##p])

/* A buffer kept from draw to draw, grown when a draw needs more: a frame's
 * draws reuse the pages of the first (fresh pages cost a fault each). */
typedef struct sw_scratch {
    void *p;
    size_t cap;
} sw_scratch;
/* bytes of s (contents undefined), or NULL when out of memory. */
static inline void *sw_scratch_get(sw_scratch *s, size_t bytes)
{
    if (bytes > s->cap) {
        free(s->p);
        s->cap = bytes + bytes / 4;
        s->p = malloc(s->cap);
        if (!s->p) s->cap = 0;
    }
    return s->p;
}
enum { SW_SCRATCH_RECT, SW_SCRATCH_COUNTS, SW_SCRATCH_BIN_START, SW_SCRATCH_STATS, SW_SCRATCH_BIN, SW_SCRATCH__COUNT };

typedef struct sw_context {
    spr_backend base; /* first: a sw_context is an spr_backend */
    int threads;
    sw_scratch scratch[SW_SCRATCH__COUNT]; /* splat draws' binning (sw_raster.c) */
    /* What the binning in scratch was made for: a draw of the same splats,
     * radii and opacity in the same view (pbr2p1's two passes, say) takes
     * those bins as they are.  Cleared by set_view (the backend contract:
     * a cloud's arrays do not change between a set_view and its draws). */
    struct sw_bins_key {
        int valid;
        const float *pos, *nrm, *radius, *color, *alpha, *ell;
        size_t count;
        int has_indices;
        float radius_scale, alpha_one;
        uint32_t id_base, seq_base;
        uint32_t *indices; /* a copy of the draw's indices */
        size_t cap;
    } bins;
    float *ray;       /* 6 per pixel: o0, d (spr_pixel_ray), computed once per view (sw__rays) */
    float *ray_soa;   /* the same rays as 6 planes (o0 x, y, z, d x, y, z) of H rows of ray_wp floats, for 8 pixels at once */
    int ray_h;        /* rows of ray_soa */
    int scalar;       /* spr_swrast_scalar: disks pixel by pixel, not 8 at a time */
    int ray_wp;       /* row stride of ray_soa: the width rounded up to 8, plus 8 (a block of 8 from any pixel stays in the row) */
    int ray_ok;       /* ray holds this view's rays */
    float ray_key[18];/* the M, ndc_sx and ndc_sy the rays were made from */
    size_t ray_np;    /* and the pixels */
    sw_target *targets;
    int cap;
    /* A band of SW_TILE rows of the zero clear, per plane a composite reads
     * (colour, depth, opacity, normal): a composite reads an input's tile
     * still pending the zero clear from here, not from the input's memory
     * (sw_composite.c); zband_w is the width it was made for. */
    float *zband[SPR_PLANE__COUNT];
    int zband_w;
} sw_context;

/* Target t for a draw, composite or read with every pending tile filled
 * (the planes are written once a frame, not at creation and again at a
 * clear). Call it before a parallel region. */
sw_target *sw__target(sw_context *c, int t);
/* Tile `tile` of tg filled with its pending clear if it is still pending:
 * from the one thread that then draws into or reads that tile. */
void sw__tile_fill(const sw_context *c, sw_target *tg, int tile);
/* Word k of one pixel of plane p cleared with colour `color` (the colour
 * plane) or the plane table's clear value (every other plane). */
static inline uint32_t sw__clear_word(spr_plane p, const float color[4], int k)
{
    const spr_plane_info *pi = spr_plane_info_of(p);
    uint32_t w;
    if (p == SPR_PLANE_COLOR) memcpy(&w, &color[k], 4);
    else if (spr_plane_type_uint(pi->type)) w = (uint32_t)pi->clear;
    else { float f = (float)pi->clear; memcpy(&w, &f, 4); }
    return w;
}
/* Tiles of the view's grid. */
static inline size_t sw__tiles(const spr_view *v)
{
    return (size_t)((v->width + SW_TILE - 1) / SW_TILE) * (size_t)((v->height + SW_TILE - 1) / SW_TILE);
}

/* The pixel rays of the view, computed at the first draw of a view that reads them. */
void sw__rays(sw_context *c);

static inline sw_context *sw_ctx(spr_backend *b) { return (sw_context *)b; }

/* Flush-to-zero / denormals-are-zero for the current thread, restored by sw_fp_leave. */
static inline unsigned sw_fp_enter(void)
{
#if defined(__SSE__)
    unsigned old = _mm_getcsr();
    _mm_setcsr(old | 0x8040u); /* FTZ (bit 15) | DAZ (bit 6) */
    return old;
#else
    return 0;
#endif
}
static inline void sw_fp_leave(unsigned old)
{
#if defined(__SSE__)
    _mm_setcsr(old);
#else
    (void)old;
#endif
}

spr_result sw__draw_splats(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st);
spr_result sw__composite(spr_backend *b, const spr_composite_desc *c);
spr_result sw__draw_rects(spr_backend *b, int target, const spr_rect_draw_desc *d, spr_draw_stats *st);
void sw__lists_free(spr_frag_lists *l);
spr_result sw__gauss_preprocess(spr_backend *b, const spr_gauss_desc *d, float *rec);
spr_result sw__gauss_raster(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st);
spr_result sw__gauss_draw(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st);
spr_result sw__gauss_backward(spr_backend *b, const spr_gauss_bwd_desc *d, float *sums, float *out);

#endif
