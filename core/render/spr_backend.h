/* spr_backend.h — the interface every backend implements (SPEC §3, STYLE 1).
 *
 * A backend owns render targets of the view's size and executes three kinds
 * of work, always in call order: clears, splat draws under a pass state, and
 * full-screen compositing operations.  Algorithms (algo_*.c) are written once
 * as sequences of these calls; the CPU backend (swrast/) and the GL backend
 * (glbackend/) implement them with identical float arithmetic.
 *
 * A target has these planes (SPEC §3.2):
 *   SPR_PLANE_COLOR  4 floats: weighted colour sum (rgb) and weight sum (a)
 *   SPR_PLANE_DEPTH  1 float : stored depth d_f, cleared to 1 (far)
 *   SPR_PLANE_TEST   1 float : test depth z used by the depth test, cleared to 1
 *   SPR_PLANE_ID     1 uint32: id of the last splat written, cleared to ~0
 *   SPR_PLANE_COUNT  1 uint32: fragments that passed the depth test
 *
 * Call the spr_backend_* wrappers, not the function pointers: they validate
 * the arguments in core/ so both backends reject the same inputs the same way.
 */
#ifndef SPR_BACKEND_H
#define SPR_BACKEND_H

#include <stddef.h>
#include <stdint.h>
#include "spr_camera.h"
#include "spr_cloud.h"
#include "spr_kernel.h"
#include "spr_result.h"

typedef enum spr_plane {
    SPR_PLANE_COLOR = 0,
    SPR_PLANE_DEPTH,
    SPR_PLANE_TEST,
    SPR_PLANE_ID,
    SPR_PLANE_COUNT,
    SPR_PLANE__COUNT
} spr_plane;
/* Channels of a plane (4 for colour, 1 otherwise) and its name for dumps. */
int spr_plane_channels(spr_plane p);
const char *spr_plane_name(spr_plane p);

/* Test value of a fragment (SPEC §3.3). */
typedef enum spr_depth_value {
    SPR_DEPTH_PLAIN = 0,   /* z = d_f */
    SPR_DEPTH_EPS_OFFSET,  /* z = d_f + ε_t */
    SPR_DEPTH_LOWRES,      /* z = z̃, [ZP] Eq. 10 */
    SPR_DEPTH_VORONOI,     /* z = z̃ + ρ·(1/n), [ZP] Eq. 14 */
    SPR_DEPTH__COUNT
} spr_depth_value;

typedef enum spr_depth_func {
    SPR_FUNC_LESS = 0,
    SPR_FUNC_LEQUAL,
    SPR_FUNC_ALWAYS,
    SPR_FUNC__COUNT
} spr_depth_func;

typedef enum spr_blend {
    SPR_BLEND_REPLACE = 0, /* dst = src */
    SPR_BLEND_ADD,         /* dst = src + dst */
    SPR_BLEND_OVER,        /* dst = src·a + dst·(1 − a), a = the source's 4th channel */
    SPR_BLEND__COUNT
} spr_blend;

/* What a fragment outputs to the colour plane. */
typedef enum spr_frag_output {
    SPR_OUT_WEIGHTED = 0,  /* (w·c, w): kernel-weighted colour and weight */
    SPR_OUT_ALPHA,         /* (c, α): material colour and opacity (transparency) */
    SPR_OUT__COUNT
} spr_frag_output;

/* Which planes a draw writes when its fragment passes (test depth is governed
 * by depth_write alone). */
enum {
    SPR_WRITE_COLOR = 1u << 0,
    SPR_WRITE_DEPTH = 1u << 1,  /* stored depth d_f, always replaced */
    SPR_WRITE_ID    = 1u << 2,
    SPR_WRITE_COUNT = 1u << 3,
    SPR_WRITE_ALL   = 0xFu
};

/* Per-draw state; zero = defaults (gauss, plain, LESS, no depth write,
 * replace, weighted output, write mask from spr_pass_state_defaults()). */
typedef struct spr_pass_state {
    spr_kernel kernel;
    spr_depth_value depth_value;
    spr_depth_func depth_func;
    int depth_write;
    spr_blend blend;
    spr_frag_output output;
    unsigned write_mask;
    int cull_backfaces;     /* drop fragments with den > 0 */
    float eps_t;            /* for SPR_DEPTH_EPS_OFFSET */
    spr_lowres lowres;      /* for SPR_DEPTH_LOWRES / VORONOI */
} spr_pass_state;
void spr_pass_state_defaults(spr_pass_state *s);

/* One draw: splats of `cloud` in the order of `indices` (all splats in input
 * order when NULL), optionally with per-splat radii replacing cloud->radius
 * (indexed by splat id: enlarged radii of [ZP] §4.4.2). */
typedef struct spr_draw_desc {
    const spr_cloud *cloud;
    const uint32_t *indices;
    size_t count;
    const float *radius_override;
    spr_pass_state state;
} spr_draw_desc;

typedef struct spr_draw_stats {
    uint64_t splats;      /* splats submitted */
    uint64_t generated;   /* fragments covering a pixel (passed the disk test) */
    uint64_t passed;      /* fragments that passed the depth test */
} spr_draw_stats;

/* Full-screen operations (SPEC §4.1 step 3, §4.2 compositing). */
typedef enum spr_composite_op {
    SPR_COMP_NORMALIZE = 0, /* out = a > 0 ? (rgb/a, 1) : (background, 0); depth copied */
    SPR_COMP_DEFERRED,      /* §4.2: ε-composite of inputs in order, then normalise */
    SPR_COMP__COUNT
} spr_composite_op;

#define SPR_MAX_COMPOSITE_INPUTS SPR_MAX_GROUPS
typedef struct spr_composite_desc {
    spr_composite_op op;
    const int *inputs;
    int n_inputs;
    int output;
    float eps_t;
    float background[3];
} spr_composite_desc;

typedef struct spr_backend spr_backend;
struct spr_backend {
    const char *name;
    spr_result (*set_view)(spr_backend *b, const spr_view *v);
    spr_result (*target_create)(spr_backend *b, int *out_target);
    void (*target_destroy)(spr_backend *b, int target);
    spr_result (*clear)(spr_backend *b, int target, const float color[4]);
    spr_result (*draw_splats)(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st);
    spr_result (*composite)(spr_backend *b, const spr_composite_desc *c);
    /* float planes into float*, id/count planes into uint32_t*; W·H·channels values,
     * row 0 = bottom. */
    spr_result (*read_plane)(spr_backend *b, int target, spr_plane p, void *out);
    void (*destroy)(spr_backend *b);
    spr_view view;     /* set by spr_backend_set_view */
    int n_targets;     /* handles are 0 … n_targets−1 (maintained by the backend) */
    unsigned char *target_live;
    spr_error err;     /* last failure, one line */
};

spr_result spr_backend_set_view(spr_backend *b, const spr_view *v);
spr_result spr_backend_target_create(spr_backend *b, int *out_target);
void spr_backend_target_destroy(spr_backend *b, int target);
spr_result spr_backend_clear(spr_backend *b, int target, const float color[4]);
spr_result spr_backend_draw(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st);
spr_result spr_backend_composite(spr_backend *b, const spr_composite_desc *c);
spr_result spr_backend_read_plane(spr_backend *b, int target, spr_plane p, void *out);
void spr_backend_destroy(spr_backend *b);

/* Bookkeeping for implementations: take the lowest free handle and make the
 * backend's own per-target array (*slots, *cap entries of slot_size bytes,
 * new entries zeroed) long enough to hold it. */
spr_result spr__backend_add_target(spr_backend *b, int *out_target, void **slots, int *cap, size_t slot_size);

#endif
