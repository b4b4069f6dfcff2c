/* spr_backend.h — the interface every backend implements (SPEC §3, STYLE 1).
 *
 * A backend owns render targets of the view's size and executes three kinds
 * of work, always in call order: clears, splat draws under a pass state, and
 * full-screen composite operations.  Algorithms (the registry of spr_algo.h)
 * are written once as sequences of these calls; the CPU backend (swrast/)
 * and the GL backend (glbackend/) implement them with the one float
 * sequence of the shared arithmetic (core/render/arith/).
 *
 * Targets are built from the plane table below: each target holds the set
 * of planes it was created with (a mask of SPR_PLANE_BIT), and a draw or
 * composite writes only the planes its target has.
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

/* How a plane stores its values and how fragments reach it. */
typedef enum spr_plane_type {
    SPR_PLANE_F32 = 0,  /* float per channel, blended as the pass says (colour) or replaced */
    SPR_PLANE_ZTEST,    /* float: the value the depth test compares and writes */
    SPR_PLANE_U32,      /* uint32, replaced, never blended */
    SPR_PLANE_COUNTER,  /* uint32, +1 per fragment that passes the depth test */
    SPR_PLANE_F32_IMAGE, /* float written per pixel by the Gaussian rasterizers, never by a fragment (GL: an image) */
    SPR_PLANE_U32_IMAGE  /* the same, uint32 */
} spr_plane_type;
/* Planes of unsigned integers (ids, counts, contributors). */
static inline int spr_plane_type_uint(spr_plane_type t) { return t == SPR_PLANE_U32 || t == SPR_PLANE_COUNTER || t == SPR_PLANE_U32_IMAGE; }

/* The plane table (SPEC §3.2): X(ENUM, name, channels, type, clear value).
 * A new plane is one row here; draws and composites that produce it say so
 * in their write masks (docs/architecture.md, "add a plane"). */
#define SPR_PLANE_LIST(X)                                                                      \
    X(COLOR, "color", 4, SPR_PLANE_F32, 0.0)      /* Σ w·c and Σ w, or c and α; clear: caller */ \
    X(DEPTH, "depth", 1, SPR_PLANE_F32, 1.0)      /* stored depth d_f of the last write */       \
    X(TEST, "test", 1, SPR_PLANE_ZTEST, 1.0)      /* test depth z */                             \
    X(ID, "id", 1, SPR_PLANE_U32, 4294967295.0)   /* splat id of the last write, ~0 = none */    \
    X(COUNT, "count", 1, SPR_PLANE_COUNTER, 0.0)  /* fragments that passed the depth test */   \
    X(OPACITY, "opacity", 1, SPR_PLANE_F32, 0.0)  /* w·α or α (SPEC 6.2): replace or add */     \
    X(NORMAL, "normal", 4, SPR_PLANE_F32, 0.0)    /* Σ w·n and Σ w (SPEC 4.3): under the rgb blend; gauss2d: Σ n·α·T, 1 − T */ \
    X(TRANS, "transmittance", 1, SPR_PLANE_F32_IMAGE, 1.0) /* T when the front-to-back loop ends (SPEC 10.4) */ \
    X(CONTRIB, "contrib", 1, SPR_PLANE_U32_IMAGE, 0.0)     /* the last contributor: the training code's n_contrib */ \
    X(INVDEPTH, "invdepth", 1, SPR_PLANE_F32_IMAGE, 0.0)   /* gauss3d: Σ (1/t.z)·α·T */ \
    X(SURFDEPTH, "surfdepth", 1, SPR_PLANE_F32_IMAGE, 0.0) /* gauss2d: Σ depth·α·T (SPEC 10.5) */

typedef enum spr_plane {
#define SPR__PLANE_ENUM(e, name, ch, type, clear) SPR_PLANE_##e,
    SPR_PLANE_LIST(SPR__PLANE_ENUM)
#undef SPR__PLANE_ENUM
    SPR_PLANE__COUNT
} spr_plane;
#define SPR_PLANE_BIT(p) (1u << (p))
#define SPR_PLANES_ALL ((1u << SPR_PLANE__COUNT) - 1u)
/* The planes of an opaque geometry target: colour, depth, test, id, count. */
#define SPR_PLANES_OPAQUE (SPR_PLANE_BIT(SPR_PLANE_COLOR) | SPR_PLANE_BIT(SPR_PLANE_DEPTH) | SPR_PLANE_BIT(SPR_PLANE_TEST) | \
                           SPR_PLANE_BIT(SPR_PLANE_ID) | SPR_PLANE_BIT(SPR_PLANE_COUNT))
/* The planes of a Gaussian rasterizer's target (SPEC §10.4, §10.5). */
#define SPR_PLANES_GAUSS3D (SPR_PLANE_BIT(SPR_PLANE_COLOR) | SPR_PLANE_BIT(SPR_PLANE_TRANS) | SPR_PLANE_BIT(SPR_PLANE_CONTRIB) | \
                            SPR_PLANE_BIT(SPR_PLANE_INVDEPTH))
#define SPR_PLANES_GAUSS2D (SPR_PLANE_BIT(SPR_PLANE_COLOR) | SPR_PLANE_BIT(SPR_PLANE_TRANS) | SPR_PLANE_BIT(SPR_PLANE_CONTRIB) | \
                            SPR_PLANE_BIT(SPR_PLANE_SURFDEPTH) | SPR_PLANE_BIT(SPR_PLANE_NORMAL))
/* The planes of a composite output: colour, depth, test. */
#define SPR_PLANES_IMAGE (SPR_PLANE_BIT(SPR_PLANE_COLOR) | SPR_PLANE_BIT(SPR_PLANE_DEPTH) | SPR_PLANE_BIT(SPR_PLANE_TEST))

typedef struct spr_plane_info {
    const char *name;
    int channels;
    spr_plane_type type;
    double clear;        /* every plane but COLOR is cleared to this */
} spr_plane_info;
/* The row of plane p (NULL when p is not a plane). */
const spr_plane_info *spr_plane_info_of(spr_plane p);
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
    SPR_BLEND_SUB,         /* dst = dst − src (colour of rectangle draws only: soft dark back faces, SPEC 7.7) */
    SPR_BLEND_PREMUL,      /* dst = src + dst·(1 − a), a = the source's 4th channel: premultiplied `over` (SPEC 10.7) */
    SPR_BLEND__COUNT
} spr_blend;

/* What a fragment outputs to the colour plane. */
typedef enum spr_frag_output {
    SPR_OUT_WEIGHTED = 0,  /* (w·c, w): kernel-weighted colour and weight */
    SPR_OUT_ALPHA,         /* (c, α): material colour and opacity (transparency) */
    SPR_OUT__COUNT
} spr_frag_output;

/* Which planes a draw writes when its fragment passes: plane bits (the
 * test depth is governed by depth_write alone). */
enum {
    SPR_WRITE_COLOR = SPR_PLANE_BIT(SPR_PLANE_COLOR),
    SPR_WRITE_DEPTH = SPR_PLANE_BIT(SPR_PLANE_DEPTH),  /* stored depth d_f, always replaced */
    SPR_WRITE_ID    = SPR_PLANE_BIT(SPR_PLANE_ID),
    SPR_WRITE_COUNT = SPR_PLANE_BIT(SPR_PLANE_COUNT),
    SPR_WRITE_OPACITY = SPR_PLANE_BIT(SPR_PLANE_OPACITY), /* under blend_alpha: replace or add (not over) */
    SPR_WRITE_NORMAL = SPR_PLANE_BIT(SPR_PLANE_NORMAL),   /* (w·n, w) under blend: replace or add (not over) */
    SPR_WRITE_ALL   = SPR_PLANES_OPAQUE & ~SPR_PLANE_BIT(SPR_PLANE_TEST)  /* the opaque planes */
};

/* Per-draw state; zero = defaults (gauss, plain, LESS, no depth write,
 * replace on every channel, weighted output, write mask from
 * spr_pass_state_defaults()). */
typedef struct spr_pass_state {
    spr_kernel kernel;
    spr_depth_value depth_value;
    spr_depth_func depth_func;
    int depth_write;
    spr_blend blend;        /* colour channels rgb */
    spr_blend blend_alpha;  /* the fourth channel (SPEC §6.3: rgb `over`, alpha `add`) */
    spr_frag_output output;
    unsigned write_mask;
    int cull_backfaces;     /* drop fragments with den > 0 */
    float eps_t;            /* for SPR_DEPTH_EPS_OFFSET and the depth mask */
    spr_lowres lowres;      /* for SPR_DEPTH_LOWRES / VORONOI */
} spr_pass_state;
void spr_pass_state_defaults(spr_pass_state *s);
/* Set one blend for all four channels. */
void spr_pass_state_blend(spr_pass_state *s, spr_blend b);

/* One draw: splats of `cloud` in the order of `indices` (all splats in input
 * order when NULL), optionally with every radius scaled (the enlarged radii
 * of a group, [ZP] §4.4.2: spr_draw_radius), and one opacity replacing
 * cloud->alpha (`--alpha`).  A streamed cloud is drawn chunk by
 * chunk: `cloud` is the chunk and id_base/seq_base place it in the whole.  With a depth mask,
 * the draw reads the stored depth z_near of target mask_target (read-only,
 * not the target drawn into) and drops every fragment with
 * d_f ≤ z_near + ε_t (spr_depth_masked, SPEC §6.2 step 2). */
typedef struct spr_draw_desc {
    const spr_cloud *cloud;
    const uint32_t *indices;
    size_t count;
    float radius_scale;     /* > 0: radii times this (rounded to float once, on the host); 0 = cloud->radius */
    float alpha;            /* > 0: one opacity for every splat of the draw (`--alpha`); 0 = cloud->alpha */
    int depth_mask;         /* 0 = none */
    int mask_target;
    spr_pass_state state;
    uint32_t id_base;       /* added to the splat index in the id plane (a streamed chunk's first splat) */
    uint32_t seq_base;      /* added to the submission position (pixel history) */
} spr_draw_desc;
/* The radius splat sid of a draw is drawn with (both backends, on the host). */
static inline float spr_draw_radius(const spr_draw_desc *d, uint32_t sid)
{
    const float r = d->cloud->radius[sid];
    return d->radius_scale > 0.0f ? d->radius_scale * r : r;
}
/* The scale of ρ² under the gauss kernel of a draw: 1, or (C/3)² for a
 * Gaussian capture cut at C σ (C < 3), so that the kernel, exp(−4.5·ρ²)
 * with ρ = 1 at the cut, is the capture's own exp(−x²/2σ²) (docs/formats.md). */
static inline float spr_draw_kernel_scale(const spr_draw_desc *d)
{
    const double C = d->cloud->gauss_cut;
    return C > 0.0 && C != 3.0 ? (float)((C / 3.0) * (C / 3.0)) : 1.0f;
}
/* The ellipse e = (u, r_v) splat sid is drawn with, r its spr_draw_radius
 * (spr_ray_ellipse): (0, 0, 0, r) for a circular splat, the minor radius
 * scaled as the radius is (both backends, on the host). */
static inline void spr_draw_ellipse(const spr_draw_desc *d, uint32_t sid, float r, float e[4])
{
    const float *ce = d->cloud->ell ? d->cloud->ell + 4 * (size_t)sid : NULL;
    if (!ce || ce[3] == d->cloud->radius[sid]) {
        e[0] = e[1] = e[2] = 0.0f;
        e[3] = r;
        return;
    }
    e[0] = ce[0];
    e[1] = ce[1];
    e[2] = ce[2];
    e[3] = d->radius_scale > 0.0f ? d->radius_scale * ce[3] : ce[3];
}

typedef struct spr_draw_stats {
    uint64_t splats;      /* splats submitted */
    uint64_t generated;   /* fragments covering a pixel (passed the disk test) */
    uint64_t passed;      /* fragments that passed the depth test */
} spr_draw_stats;

/* The composite table: X(ENUM, function, most inputs, planes read from each
 * input, planes written, summary).  Each op is one per-pixel function
 * spr_comp_<function> of arith/composite.h; it reads its inputs through
 * spr_in_color/spr_in_depth/spr_in_opacity/spr_in_normal and gives the
 * output colour, depth and normal (a test plane, when the output has one,
 * receives the depth too, as gl_FragDepth does; a normal plane, when the
 * output has one, receives the normal).  Ops read the normal plane of their
 * inputs only when the shading parameters ask for it (spr_shade_reads).  The
 * CPU backend loops it over pixels, the GL backend runs it as a full-screen
 * pass.  A new op is one function and one row (docs/architecture.md, "add a
 * composite op"). */
#define SPR_MAX_COMPOSITE_INPUTS SPR_MAX_GROUPS
#define SPR_PLANES_CD (SPR_PLANE_BIT(SPR_PLANE_COLOR) | SPR_PLANE_BIT(SPR_PLANE_DEPTH))
#define SPR_COMPOSITE_LIST(X)                                                                                           \
    X(NORMALIZE, normalize, 1, SPR_PLANES_CD, SPR_PLANES_CD,                                                              \
      "c = rgb/a where a > 0, else background; depth copied; Phong when shading (SPEC 4.1 step 3, 4.3)")               \
    X(DEFERRED, deferred, SPR_MAX_COMPOSITE_INPUTS, SPR_PLANES_CD, SPR_PLANES_CD,                                         \
      "eps-composite of the inputs in order, then normalise; Phong when shading (SPEC 4.2, 4.3)")                      \
    X(AVERAGE, average, SPR_MAX_COMPOSITE_INPUTS, SPR_PLANES_CD, SPR_PLANES_CD,                                           \
      "(1/K) sum of the inputs, every channel; nearest depth (SPEC 6.1)")                                                \
    X(NEAREST, nearest, SPR_MAX_COMPOSITE_INPUTS, SPR_PLANES_CD | SPR_PLANE_BIT(SPR_PLANE_OPACITY), SPR_PLANES_CD,        \
      "eps-composite of colour, opacity and normal: (C_F, alpha_F, n_F) of the nearest layer (SPEC 6.2)")               \
    X(TRANSPARENT2, transparent2, 2, SPR_PLANES_CD, SPR_PLANES_CD,                                                        \
      "alpha_F*C_F + (1-alpha_F)*C_O, with shading and environment effects when asked (SPEC 6.2, 6.3)")                 \
    X(PEEL, peel, SPR_MAX_COMPOSITE_INPUTS, SPR_PLANES_CD, SPR_PLANES_CD,                                                 \
      "layers (c, alpha) blended back to front over the background, input 0 nearest (SPEC 6.4)")                        \
    X(DOMAINSUM, domainsum, 1, SPR_PLANES_CD, SPR_PLANES_CD,                                                              \
      "summed (alpha*c, alpha) of domain primitives over the background: rgb + (1 - min(alpha, 1))*bg (SPEC 7.7)")      \
    X(CLAMP, clamp, 1, SPR_PLANES_CD, SPR_PLANES_CD,                                                                      \
      "rgb clamped below at 0, alpha and depth copied: after soft dark back faces (SPEC 7.7)")                          \
    X(PREFIX, prefix, 1, 0, SPR_PLANES_CD,                                                                                \
      "the input's fragment lists sorted by (depth, primitive): front-most plus its neighbours summed (SPEC 7.7)")

typedef enum spr_composite_op {
#define SPR__COMP_ENUM(e, fn, max_in, reads, writes, summary) SPR_COMP_##e,
    SPR_COMPOSITE_LIST(SPR__COMP_ENUM)
#undef SPR__COMP_ENUM
    SPR_COMP__COUNT
} spr_composite_op;
typedef struct spr_composite_info {
    const char *name;
    int max_inputs;
    unsigned reads;      /* planes each input must have */
    unsigned writes;     /* planes the output must have (its test plane, if any, also gets the depth) */
    const char *summary;
} spr_composite_info;
const spr_composite_info *spr_composite_info_of(spr_composite_op op);

/* Parameters of the shading and environment effects (SPEC §4.3, §6.3), one
 * float array filled on the host (core/render/shade.c) and given unchanged
 * to both backends: X(NAME, floats).  Index SPR_PRM_<NAME> is the offset of
 * the first float; the GL backend emits the same offsets into its programs. */
#define SPR_PARAM_LIST(X)                                                                                     \
    X(M, 16)        /* inverse of P·V, as spr_view.M: the pixel's ray */                                    \
    X(SX, 1) X(SY, 1) /* 2/W and 2/H */                                                                     \
    X(SHADE, 1)     /* 0: none; 1: Phong with the composited normal */                                      \
    X(LIGHT, 3)     /* unit vector towards the light, world space */                                          \
    X(KA, 1) X(KD, 1) X(KS, 1) /* ambient, diffuse, specular coefficients */                                \
    X(EXP, 1)       /* integer specular exponent, 1 … 1024 */                                               \
    X(ENV, 1)       /* 0: none; 1: environment cube map (reflection, refraction, Fresnel) */                 \
    X(ENV_SIZE, 1)  /* texels per cube face side */                                                          \
    X(ETA, 3)       /* refraction ratio n_outside/n_inside per channel (three: dispersion) */                \
    X(MULTI, 1)     /* 1: multi-layer refraction eta^(l+1); 0: one interface */                              \
    X(ALPHA, 1)     /* material opacity for the layer count l = round(alpha_total/alpha) */

enum {
#define SPR__PRM_SIZE(name, n) SPR_PRM__SIZE_##name = (n),
    SPR_PARAM_LIST(SPR__PRM_SIZE)
#undef SPR__PRM_SIZE
};
enum {
#define SPR__PRM_OFF(name, n) SPR_PRM_##name, SPR_PRM__END_##name = SPR_PRM_##name + (n) - 1,
    SPR_PARAM_LIST(SPR__PRM_OFF)
#undef SPR__PRM_OFF
    SPR_PRM_COUNT
};

/* An environment cube map: six square faces of size·size RGBA float texels
 * in GL's face order +x, −x, +y, −y, +z, −z, each face row by row from its
 * top row (the GL cube map convention), looked up by nearest texel. */
typedef struct spr_envmap {
    int size;
    float *texels;   /* 6·size·size·4 */
} spr_envmap;

typedef struct spr_composite_desc {
    spr_composite_op op;
    const int *inputs;
    int n_inputs;
    int output;
    float eps_t;
    float background[3];
    const float *params;     /* SPR_PRM_COUNT floats, or NULL: no shading, no environment */
    const spr_envmap *env;   /* required when params[SPR_PRM_ENV] != 0 */
    const struct spr_rects *rects; /* the prefix op: the rectangles the input's lists came from (neighbours) */
} spr_composite_desc;

/* Planes input `input` of op must have beyond the table's `reads` under these
 * parameters: the normal plane where shading or environment effects use it. */
unsigned spr_composite_extra_reads(spr_composite_op op, const float *params, int input);


/* ---- textured rectangles: domain primitives (SPEC §7.4, §7.5, §7.7) ----
 * A rectangle is a float record (SPR_RECT_LIST: X(NAME, floats), offsets
 * SPR_RECT_<NAME>) and an integer record of SPR_RECTI_COUNT values; both go
 * unchanged to both backends, and arith/rect.h reads the floats.  The
 * rectangle is {c + s·u + w·v : umin ≤ s ≤ umax, vmin ≤ w ≤ vmax} in the
 * plane through c with normal n; its texture has tw × th square texels of
 * side h, texel (x, y) centred at (umin + (x + ½)h, vmin + (y + ½)h), RGBA
 * = colour and alpha (the basis function), row by row from y = 0. */
#define SPR_RECT_LIST(X) X(C, 3) X(N, 3) X(U, 3) X(V, 3) X(UMIN, 1) X(UMAX, 1) X(VMIN, 1) X(VMAX, 1) X(TEXEL, 1)
enum {
#define SPR__RECT_OFF(name, n) SPR_RECT_##name, SPR_RECT__END_##name = SPR_RECT_##name + (n) - 1,
    SPR_RECT_LIST(SPR__RECT_OFF)
#undef SPR__RECT_OFF
    SPR_RECT_FLOATS
};
enum { SPR_RECTI_TW = 0, SPR_RECTI_TH, SPR_RECTI_OFF, SPR_RECTI_DOMAIN, SPR_RECTI_COUNT };
/* A per-pixel fragment list keeps at most this many fragments, the front-most
 * by (depth, primitive) (the prefix op). */
#define SPR_LIST_MAX 64

typedef struct spr_rects {
    size_t n;
    float *f;          /* n·SPR_RECT_FLOATS */
    uint32_t *i;       /* n·SPR_RECTI_COUNT: texels along u and v, first texel, domain number */
    float *texels;     /* RGBA, n_texels·4 */
    size_t n_texels;
    uint32_t *nbr;     /* neighbour bits: primitive b is a neighbour of a when bit b of row a is set,
                          rows of spr_rects_words(n) words; symmetric, a is its own neighbour */
    uint64_t serial;   /* different for every set made (spr_rects_alloc): GL keeps uploads by it */
} spr_rects;
static inline size_t spr_rects_words(size_t n) { return (n + 31) / 32; }
/* Is b a neighbour of a?  Make a and b neighbours (both ways). */
static inline int spr_rects_neighbours(const uint32_t *nbr, size_t words, size_t a, size_t b)
{
    return (int)(nbr[a * words + b / 32] >> (b % 32) & 1u);
}
static inline void spr_rects_link(spr_rects *r, size_t a, size_t b)
{
    const size_t words = spr_rects_words(r->n);
    r->nbr[a * words + b / 32] |= 1u << (b % 32);
    r->nbr[b * words + a / 32] |= 1u << (a % 32);
}
/* Arrays for n rectangles and n_texels texels, zeroed, with a new serial. */
spr_result spr_rects_alloc(spr_rects *r, size_t n, size_t n_texels, spr_error *err);
void spr_rects_free(spr_rects *r);
/* The textures of r in one RGBA image (*img, w × h, row 0 = texture row 0):
 * shelves at most max_w texels wide, each texture in a block with a
 * one-texel border repeating its edge (what clamp-to-edge reads);
 * org[2k], org[2k+1] = corner of rectangle k's block, its texel (0, 0) at
 * org + (1, 1).  Used by GL's Tier B atlas and by `domains --dump`. */
spr_result spr_rects_atlas(const spr_rects *r, int max_w, float **img, int *w, int *h, int32_t *org, spr_error *err);

/* What a rectangle fragment offers the colour plane, from its texel (c, α). */
typedef enum spr_rect_output {
    SPR_ROUT_WEIGHTED = 0, /* (α·c, α): summed, the partition of unity blends (SPEC 7.7) */
    SPR_ROUT_COLOR,        /* (c, 1): opaque (noblend) */
    SPR_ROUT_BLACK,        /* (0, 0, 0, 1): hard dark back face */
    SPR_ROUT_LUMINANCE,    /* (α, α, α, 0): soft dark back face, under SPR_BLEND_SUB */
    SPR_ROUT__COUNT
} spr_rect_output;
typedef enum spr_sampling {
    SPR_SAMPLE_NEAREST = 0, /* the texel containing the hit point */
    SPR_SAMPLE_LINEAR,      /* bilinear, weights computed in the shared arithmetic (Tier A) */
    SPR_SAMPLE_HARDWARE,    /* GL's own texture() bilinear filter (Tier B, PARITY.md); the CPU does LINEAR */
    SPR_SAMPLE__COUNT
} spr_sampling;

/* One draw of rectangles in the order of `indices` (all when NULL): the
 * pixel's ray meets the plane at 0 ≤ t ≤ 1 inside the rectangle, the texel
 * sampled there has α > 0 and α ≥ alpha_ref; then the test value (plain or
 * eps-offset, from state), depth test, and the planes of state.write_mask
 * (colour as `output` says, stored depth t, id = the rectangle's index,
 * count).  With list = 1 nothing is tested or written: the draw makes the
 * target's per-pixel fragment lists (t, index, (α·c, α)) from its
 * fragments alone, for the prefix op. */
typedef struct spr_rect_draw_desc {
    const spr_rects *rects;
    const uint32_t *indices;
    size_t count;
    spr_rect_output output;
    spr_sampling sampling;
    float alpha_ref;
    int list;
    spr_pass_state state;   /* depth_value PLAIN or EPS_OFFSET, eps_t, depth func/write, blends, write mask */
} spr_rect_draw_desc;
/* Pixel rectangle a rectangle may cover (host, double, one pixel of slack);
 * 0 when it is off screen.  Both backends use it, so coverage is decided
 * per pixel by the shared arithmetic alone. */
int spr_rect_pixel_rect(const spr_view *v, const float *f, int *x0, int *y0, int *x1, int *y1);

/* ---- Gaussian splatting references (SPEC §10) ----
 * A frame's parameters are one float array (SPR_GPRM_LIST: X(NAME, floats),
 * offsets SPR_GPRM_<NAME>), filled on the host from the view and the
 * algorithm's options (core/algo/gauss.c) and given unchanged to both
 * backends; a Gaussian's preprocessed values are one float record
 * (SPR_GREC_LIST), made by the backend's preprocessing (arith/gauss.h) and
 * read by its rasterizer. */
#define SPR_GPRM_LIST(X)                                                                                          \
    X(R, 9) X(T, 3)          /* world-to-camera, OpenCV axes (SPEC 10.2) */                                     \
    X(FX, 1) X(FY, 1)        /* focal lengths, pixels */                                                        \
    X(CX, 1) X(CY, 1)        /* principal point in pixel-index coordinates: cx − 0.5, cy − 0.5 */             \
    X(LX, 1) X(LY, 1)        /* the Jacobian's tangent clamp, positive side: 1.3·tan(fov/2) (SPEC 10.3 step 3) */  \
    X(LXN, 1) X(LYN, 1)      /* its negative side's magnitude (inria: LX, LY; gsplat: from the principal point) */ \
    X(W, 1) X(H, 1)          /* image size */                                                                   \
    X(GX, 1) X(GY, 1)        /* 16×16 tiles across and down */                                                  \
    X(NEAR, 1)               /* the near test (profile rule 1: 0.2; gsplat 0.01) */                              \
    X(NEAR_LT, 1)            /* 1: culled when t.z < NEAR (gsplat); 0: when t.z ≤ NEAR */                       \
    X(CLIP_K, 1)             /* > 0: culled when |x/w| or |y/w| > CLIP_K in clip space (the viewers' frustum) */  \
    X(NDC, 4)                /* clip x/w = (t.x/t.z)·NDC0 + NDC1, y/w = (t.y/t.z)·NDC2 + NDC3 (host, double) */   \
    X(TCLAMP, 1)             /* rule 2: 1 the Jacobian's tangents clamped at LX, LY; 0 not */                    \
    X(EPS2D, 1)              /* rule 3: the dilation, 0.3 */                                                    \
    X(DET_LE, 1)             /* 1: culled when det ≤ 0 (gsplat); 0: when det == 0 */                            \
    X(AA, 1) X(AA_MIN, 1)    /* compensation on (--gauss-aa, or the profile's always) with its floor f */         \
    X(AA_FORM, 1)            /* 0: o·sqrt(max(f, det₀/det)); 1: o·max(f, sqrt(det₀/det)) */                     \
    X(EXT, 1)                /* rule 4: SPR_GEXT_* (square, per axis, quad) */                                  \
    X(EXT_K, 1)              /* the extent's k: r = k·sqrt(…) (3; gsplat 3.33; the viewers' quad sqrt(8)) */      \
    X(EXT_CAP, 1)            /* quad: the longest half-axis in pixels (0: none) */                              \
    X(EXT_MIN, 1)            /* the floor under the eigenvalues' sqrt, 0.1 */                                   \
    X(MIN_PX, 1)             /* quad: dropped when both half-axes are shorter (0: never) */                     \
    X(CUT, 1)                /* gauss-blend: cut where power < −CUT (k²/2: 4.5 for 3σ, 4 for sqrt(8)σ) */        \
    X(FALLOFF, 1)            /* 1: α from (e^power − e^−CUT)/(1 − e^−CUT), 0 at the cut (PlayCanvas) */         \
    X(STRAIGHT, 1)           /* gauss-blend: 1 the fragment is (c, α) for straight blending; 0 (c·α, α) */       \
    X(EXT2D_MIN, 1)          /* gauss2d: the box's floor under the sqrt, 1e-4 */                                \
    X(R2D_MIN, 1)            /* gauss2d: the radius's floor, 3·FilterSize */                                    \
    X(CAP, 1)                /* rule 5: α cap (0.99; gsplat 1.5 0.999; 1: none) */                              \
    X(ALPHA_MIN, 1)          /* skipped below (the float 1/255; 0: never) */                                    \
    X(POWER_MIN, 1)          /* power below which o·exp(power) < ALPHA_MIN for every o ≤ 1: skipped without exp */ \
    X(T_MIN, 1)              /* rule 6: stop when T·(1 − α) falls below, 1e-4 (0: no stop) */                   \
    X(STOP_LE, 1)            /* 1: stop at T·(1 − α) ≤ T_MIN too (gsplat) */                                    \
    X(MODE, 1)               /* SPR_GMODE_3D (gauss3d, gauss-blend) or SPR_GMODE_2D (gauss2d) */              \
    X(GATE, 1)               /* backward (SPEC 10.10): 1 no gradient through a capped α (gsplat); 0 as uncapped (inria) */ \
    X(TCLAMP_BWD, 1)         /* backward: 0 the clamped tangent's exact derivative; 1 inria's (u held, J's t.z term ×2) */ \
    X(EXT_PAD, 1)            /* SPR_GEXT_BOX: the pixel box's margin, whole pixels (OpenSplat: 2) */            \
    X(CAP_BWD, 1)            /* backward: > 0 its own α cap, α_b = min(CAP_BWD, α) (OpenSplat 0.99); 0 the forward's α */ \
    X(TDIV, 1)               /* backward: 1 T recovered back to front, T·(1/(1 − α_b)) from the final T; 0 the forward's T */ \
    X(HALF_B, 1)             /* backward: 1 ∂L/∂B (the conic's off-diagonal) halved per pixel (OpenSplat) */
enum {
#define SPR__GPRM_OFF(name, n) SPR_GPRM_##name, SPR_GPRM__END_##name = SPR_GPRM_##name + (n) - 1,
    SPR_GPRM_LIST(SPR__GPRM_OFF)
#undef SPR__GPRM_OFF
    SPR_GPRM_COUNT
};
#define SPR_GREC_LIST(X)                                                                                          \
    X(M, 2)          /* centre, pixel-index coordinates (2D: the centre of the disk's screen box) */            \
    X(CONIC, 3)      /* A, B, C of the dilated inverse covariance (3D) */                                       \
    X(OPACITY, 1)    /* o, after --gauss-aa */                                                                  \
    X(DEPTH, 1)      /* t.z: the sort key */                                                                    \
    X(INVZ, 1)       /* 1/t.z */                                                                                \
    X(RADIUS, 2)     /* r across and down (square extent: both r; 0: culled) */                                                                        \
    X(RECT, 4)       /* tiles x0, y0, x1, y1 (x1, y1 exclusive; empty: not in any tile) */                      \
    X(BOX, 4)        /* gauss-blend's pixels i0, j0, i1, j1 (inclusive; empty when i1 < i0 or j1 < j0) */        \
    X(COLOR, 3)      /* SPEC 10.3 step 9 (host) */                                                              \
    X(TU, 3) X(TV, 3) X(TW, 3) /* 2D: the rows of H = K·[σ_u u | σ_v v | t] */                                 \
    X(NORMAL, 3)     /* 2D: the disk's normal in camera space, facing the camera */                             \
    X(CULL, 1)       /* SPR_GCULL_* */
enum {
#define SPR__GREC_OFF(name, n) SPR_GREC_##name, SPR_GREC__END_##name = SPR_GREC_##name + (n) - 1,
    SPR_GREC_LIST(SPR__GREC_OFF)
#undef SPR__GREC_OFF
    SPR_GREC_FLOATS
};
/* The backward pass of gauss3d (SPEC 10.10): the gradient terms a list entry
 * (a Gaussian in a tile) gathers from its tile's pixels (16 floats, the last
 * three zero: GL reads them four a texel, and a texel must not straddle two
 * tiles' entries), and the per-Gaussian values the chain of
 * spr_gauss_preprocess3d_bwd gives from their sums. */
#define SPR_GPART_LIST(X)                                                                                         \
    X(COLOR, 3)      /* ∂L/∂c, the record's colour */                                                           \
    X(INVZ, 1)       /* ∂L/∂(1/t.z), from ∂L/∂D */                                                              \
    X(OPACITY, 1)    /* ∂L/∂o, the record's opacity */                                                          \
    X(CONIC, 3)      /* ∂L/∂(A, B, C) */                                                                         \
    X(M, 2)          /* ∂L/∂m, the centre in pixels */                                                          \
    X(ABS, 2)        /* Σ |∂L/∂m| per axis over pixels (absgrad) */                                             \
    X(COUNT, 1)      /* pixels that blended it */                                                               \
    X(PAD, 3)
enum {
#define SPR__GPART_OFF(name, n) SPR_GPART_##name, SPR_GPART__END_##name = SPR_GPART_##name + (n) - 1,
    SPR_GPART_LIST(SPR__GPART_OFF)
#undef SPR__GPART_OFF
    SPR_GPART_FLOATS
};
#define SPR_GOUT_LIST(X) X(MEANS, 3) X(QUATS, 4) X(SCALES, 3) X(OPACITY, 1)
enum {
#define SPR__GOUT_OFF(name, n) SPR_GOUT_##name, SPR_GOUT__END_##name = SPR_GOUT_##name + (n) - 1,
    SPR_GOUT_LIST(SPR__GOUT_OFF)
#undef SPR__GOUT_OFF
    SPR_GOUT_FLOATS
};
/* The forward loop of one pixel between calls (spr_gauss_pixel_run; SPEC 10.4, 10.5): the CPU runs a pixel in one
 * call, a GL fragment resumes it draw after draw when a list is longer than llvmpipe's loop budget lets it walk. */
#define SPR_GFS_LIST(X)                                                                                           \
    X(K, 1)          /* list entries visited */                                                                 \
    X(T, 1)          /* the transmittance */                                                                    \
    X(C, 3)          /* the colour, Σ c·α·T */                                                                  \
    X(N, 3)          /* 2D: the normal, Σ n·α·T */                                                              \
    X(D, 1)          /* the depth sum */                                                                        \
    X(LAST, 1)       /* the last contributor (its rank) */                                                      \
    X(BLENDED, 1)    /* Gaussians blended */                                                                    \
    X(DONE, 1)       /* 1: the list's end or the stop reached */                                                \
    X(PAD, 4)
enum {
#define SPR__GFS_OFF(name, n) SPR_GFS_##name, SPR_GFS__END_##name = SPR_GFS_##name + (n) - 1,
    SPR_GFS_LIST(SPR__GFS_OFF)
#undef SPR__GFS_OFF
    SPR_GFS_FLOATS
};
/* gauss3d's backward over one tile, resumable (spr_gauss_tile_bwd; SPEC 10.10, docs/gradients.md "per pixel"):
 * the walk's state between calls, 32 bits a value, ints held by their bits.  The CPU runs a tile in one call; a GL
 * fragment resumes it draw after draw, each within llvmpipe's loop budget, so no list is too long for it.  A pixel's
 * blended Gaussians are held, SPR_GBWD_HOLD at most: every profile that trains skips α < 1/255 and stops below
 * T = 1e-4, so a pixel blends at most 2,345 ((254/255)^2,345 < 1e-4). */
#define SPR_GBWD_HOLD 2560
#define SPR_GBS_LIST(X)                                                                                           \
    X(PIX, 1)        /* the tile's pixel reached (row-major from the top row) */                                \
    X(PHASE, 1)      /* SPR_GBWD_*: where that pixel's backward stands */                                        \
    X(E, 1)          /* the walk's next list entry */                                                           \
    X(T, 1)          /* the transmittance there */                                                              \
    X(N, 1)          /* Gaussians blended by the walk */                                                        \
    X(K, 1)          /* the next of them to walk back */                                                        \
    X(TF, 1)         /* the final transmittance */                                                              \
    X(TB, 1)         /* T recovered by division (the profile's TDIV) */                                         \
    X(OVER, 1)       /* 0, or 1 + the first pixel that blended more than SPR_GBWD_HOLD (it is skipped) */         \
    X(ACC, 4)        /* spr_gauss_blend_bwd's acc and behind */                                                 \
    X(BEHIND, 5)                                                                                                \
    X(PAD, 1)                                                                                                   \
    X(SE, SPR_GBWD_HOLD) /* the blended Gaussians: their list entries, α and T */                                \
    X(SA, SPR_GBWD_HOLD)                                                                                        \
    X(ST, SPR_GBWD_HOLD)
enum {
#define SPR__GBS_OFF(name, n) SPR_GBS_##name, SPR_GBS__END_##name = SPR_GBS_##name + (n) - 1,
    SPR_GBS_LIST(SPR__GBS_OFF)
#undef SPR__GBS_OFF
    SPR_GBS_FLOATS
};
/* A pixel's phases: not begun, the walk, the walk back. */
#define SPR_GBWD_LIST(X) X(BEGIN) X(WALK) X(BACK)
enum {
#define SPR__GBWD(name) SPR_GBWD_##name,
    SPR_GBWD_LIST(SPR__GBWD)
#undef SPR__GBWD
    SPR_GBWD__COUNT
};

/* Why a record was culled, and the modes (floats: compared with record and parameter values). */
#define SPR_GCULL_NONE 0.0f
#define SPR_GCULL_NEAR 1.0f   /* t.z at or before the near plane */
#define SPR_GCULL_DET 2.0f    /* a degenerate footprint: det of the dilated covariance 0 (3D), or edge-on (2D) */
#define SPR_GCULL_CLIP 3.0f   /* outside the profile's clip box (|x/w| or |y/w| > CLIP_K) */
#define SPR_GCULL_SMALL 4.0f  /* a quad smaller than the profile's MIN_PX on both axes */
#define SPR_GMODE_3D 0.0f
#define SPR_GMODE_2D 1.0f
/* The extent rule's kinds as parameter values (spr_gauss_extent of spr_algo.h, in the same order). */
#define SPR_GEXT_SQUARE_F 0.0f
#define SPR_GEXT_AXES_F 1.0f
#define SPR_GEXT_QUAD_F 2.0f
#define SPR_GEXT_BOX_F 3.0f

/* The Gaussians of a frame, per Gaussian: mean, unit quaternion (w x y z),
 * σ (linear; a 2D Gaussian's third 0), opacity, colour (SPEC §10.3 step 9:
 * evaluated on the host); prm the frame's parameters. */
typedef struct spr_gauss_desc {
    size_t n;
    const float *mu, *q, *s, *opacity, *color;
    float prm[SPR_GPRM_COUNT];
} spr_gauss_desc;

/* One rasterization of sorted tile lists (SPEC §10.4, §10.5): tile t
 * (row-major from the top-left, prm's GX × GY) holds the Gaussians
 * list[range[t]] … list[range[t + 1] − 1], front to back; rec the records
 * (SPR_GREC_FLOATS per Gaussian) the preprocessing made; the target gets
 * colour (C + T·bg, 1 − T) and the planes of SPR_PLANES_GAUSS3D/2D it has. */
typedef struct spr_gauss_raster_desc {
    const float *rec;
    size_t n;
    const uint32_t *range;     /* GX·GY + 1 */
    const uint32_t *list;      /* range[GX·GY] */
    float background[3];
    float prm[SPR_GPRM_COUNT];
} spr_gauss_raster_desc;

/* One draw of gauss-blend (SPEC §10.7): the Gaussians order[0 … count−1]
 * (farthest first) as screen-space ellipses over their BOX, each fragment
 * (c·α, α) under state (blend SPR_BLEND_PREMUL). */
typedef struct spr_gauss_draw_desc {
    const float *rec;
    size_t n;
    const uint32_t *order;
    size_t count;
    spr_pass_state state;
    float prm[SPR_GPRM_COUNT];
} spr_gauss_draw_desc;

/* gauss3d's backward pass (SPEC 10.10): the forward's records and tile lists;
 * csr[csr_start[G] … csr_start[G + 1]) each Gaussian's list entries,
 * ascending (tile order); up the upstream gradient, 5 values a pixel
 * (∂L/∂C rgb, ∂L/∂A, ∂L/∂D; pixel i = y·W + x, row 0 the bottom, as the
 * planes); mu, q, s the preprocessing's inputs.  The backend gives each
 * Gaussian's sums (SPR_GPART_FLOATS: its entries' partials, each summed
 * over its tile's pixels in row-major order from the top row, then added in
 * tile order) and what spr_gauss_preprocess3d_bwd makes of them
 * (SPR_GOUT_FLOATS).  batch > 0: at most that many list entries' partials
 * held at once (tests; 0: the backend's own limit). */
typedef struct spr_gauss_bwd_desc {
    const float *rec;
    size_t n;
    const uint32_t *range, *list;
    const uint32_t *csr_start, *csr;
    const float *up;
    const float *mu, *q, *s;
    float background[3];
    float prm[SPR_GPRM_COUNT];
    size_t batch;
} spr_gauss_bwd_desc;
/* The backward's batches, the same for every backend: whole tiles from t0 while their entries number at most cap (one
 * tile at least); spr_gauss_bwd_batch_end gives the tile after the batch, spr_gauss_bwd_batch_most the most entries a
 * batch of the frame holds (the partials a backend allocates). */
int spr_gauss_bwd_batch_end(const uint32_t *range, int nt, int t0, size_t cap);
size_t spr_gauss_bwd_batch_most(const uint32_t *range, int nt, size_t cap);
/* The refusal of a frame with a pixel that blends more than SPR_GBWD_HOLD Gaussians (SPR_GBS_OVER: pixel p of tile
 * `tile`, gx tiles a row), one line naming the pixel; SPR_E_TOO_LARGE. */
spr_result spr_gauss_bwd_over(spr_error *err, const char *who, int gx, int tile, int p);

/* The tiles [r0, r2) × [r1, r3) item k touches (empty: r2 ≤ r0 or r3 ≤ r1). */
typedef void (*spr__gauss_rect_fn)(const void *user, size_t k, int r[4]);
/* Items 0 … n−1 binned to the gx × gy tiles, each tile's run in item order:
 * tile t's items are list[range[t] … range[t+1]) (core/render/gauss_bin.c;
 * the same lists for any thread count). */
spr_result spr__gauss_bin(size_t n, spr__gauss_rect_fn rect, const void *user, int gx, int gy, int threads, uint32_t **range,
                          uint32_t **list, spr_error *err);

/* ---- the pixel probe: the raw material of pixel history (SPEC §8) ----
 * While b->probe is set, each draw appends every fragment that covers pixel
 * (x, y) — after the coverage test and the depth mask, before the depth
 * test — with the values the backend computed for it, and each composite
 * appends the notes its per-pixel function makes there (SPR_NOTE in
 * the shared arithmetic: each step of the §4.2 loop with its ε decision, …).  The
 * CPU backend records from its rasterizer; the GL backend from a debug
 * variant of the same programs (spr_gl_desc.probe) that appends to a
 * buffer.  The history backend (spr_history.h) arms it and replays the
 * fixed-function stages. */
typedef struct spr_probe_frag {
    uint32_t seq;        /* position in the draw's submission order */
    uint32_t prim;       /* splat id, or rectangle index */
    float t;             /* ray parameter = d_f */
    float rho;           /* ρ (rectangles: 0) */
    float z;             /* the test value */
    float src[4];        /* what it offers the colour plane: (w·c, w), (c, α), … */
    float opacity;       /* what it offers the opacity plane */
} spr_probe_frag;
/* Note tags: what the four values of a note are. */
enum {
    SPR_NOTE_EPS_NEAREST = 1, /* §4.2: d = min_k d_f(k), the limit d + ε_t, ε_t, K */
    SPR_NOTE_EPS_INPUT,       /* §4.2, input k: d_f(k), the limit, 1 included / 0 left out, Σw so far */
    SPR_NOTE_PREFIX_NODE,     /* §7.7, primitive k: t, 1 summed / 0 not a neighbour of the front-most, rank by (t, id), Σα so far */
    /* §10.4, §10.5, one per Gaussian k of the pixel's tile list, in order: power, α, T before, T after */
    SPR_NOTE_GAUSS_TILE,      /* the pixel: tile k, pixel-index i, j, its list's first entry, its length */
    SPR_NOTE_GAUSS_BLEND,     /* blended: power, α, T, T·(1 − α) */
    SPR_NOTE_GAUSS_POWER,     /* skipped, power > 0: power, 0, T, T */
    SPR_NOTE_GAUSS_FAINT,     /* skipped, α below 1/255: power, α, T, T */
    SPR_NOTE_GAUSS_STOP,      /* the loop stops here, T·(1 − α) below the threshold: power, α, T, T·(1 − α) (not blended) */
    SPR_NOTE_GAUSS_PARALLEL,  /* gauss2d, skipped: the ray is parallel to the disk: 0, 0, T, T */
    SPR_NOTE_GAUSS_BEHIND,    /* gauss2d, skipped: the hit lies before the near plane: power, depth, T, T */
    SPR_NOTE_GAUSS_END,       /* the loop's end: k = the last contributor; T, D, Gaussians visited, Gaussians blended */
    SPR_NOTE_GAUSS_OUTSIDE    /* skipped, the pixel lies outside the Gaussian's pixel box (SPR_GEXT_BOX): 0, 0, T, T */
};
typedef struct spr_probe_note {
    int32_t tag;         /* SPR_NOTE_* of spr_backend.h, made by the shared arithmetic */
    int32_t k;           /* the input, node or layer it is about (−1: none) */
    float v[4];
} spr_probe_note;
#define SPR_PROBE_MAX 4096  /* per call; more sets overflow */
typedef struct spr_probe {
    int x, y;
    spr_probe_frag frag[SPR_PROBE_MAX];
    int n_frags;
    spr_probe_note note[SPR_PROBE_MAX];
    int n_notes;
    int overflow;
} spr_probe;
static inline void spr_probe_add_frag(spr_probe *p, const spr_probe_frag *f)
{
    if (p->n_frags < SPR_PROBE_MAX) p->frag[p->n_frags++] = *f;
    else p->overflow = 1;
}
static inline void spr_probe_add_note(spr_probe *p, int tag, int k, float a, float b, float c, float d)
{
    if (p->n_notes >= SPR_PROBE_MAX) { p->overflow = 1; return; }
    spr_probe_note *n = &p->note[p->n_notes++];
    n->tag = tag, n->k = k, n->v[0] = a, n->v[1] = b, n->v[2] = c, n->v[3] = d;
}

/* What a frame asks of a backend's fixed limits, known before anything is drawn (spr_backend_fits). */
typedef struct spr_fit_desc {
    size_t splats;  /* the cloud's */
    int gauss;      /* drawn by a Gaussian algorithm (SPEC §10): one record of SPR_GREC_FLOATS per splat */
} spr_fit_desc;

typedef struct spr_backend spr_backend;
struct spr_backend {
    const char *name;
    spr_result (*set_view)(spr_backend *b, const spr_view *v);
    spr_result (*target_create)(spr_backend *b, unsigned planes, int *out_target);
    void (*target_destroy)(spr_backend *b, int target);
    spr_result (*clear)(spr_backend *b, int target, const float color[4]);
    spr_result (*draw_splats)(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st);
    spr_result (*composite)(spr_backend *b, const spr_composite_desc *c);
    spr_result (*draw_rects)(spr_backend *b, int target, const spr_rect_draw_desc *d, spr_draw_stats *st);
    /* SPEC §10: d->n records (SPR_GREC_FLOATS each) into rec; the tile lists composited; the ellipses drawn */
    spr_result (*gauss_preprocess)(spr_backend *b, const spr_gauss_desc *d, float *rec);
    spr_result (*gauss_raster)(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st);
    spr_result (*gauss_draw)(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st);
    /* SPEC 10.10: d->n Gaussians' sums (SPR_GPART_FLOATS each) and chain values (SPR_GOUT_FLOATS each) */
    spr_result (*gauss_backward)(spr_backend *b, const spr_gauss_bwd_desc *d, float *sums, float *out);
    /* NULL, or SPR_E_TOO_LARGE (naming the limit) for a frame beyond the backend's fixed limits */
    spr_result (*fits)(spr_backend *b, const spr_fit_desc *d);
    /* float planes into float*, id/count planes into uint32_t*; W·H·channels values,
     * row 0 = bottom. */
    spr_result (*read_plane)(spr_backend *b, int target, spr_plane p, void *out);
    void (*destroy)(spr_backend *b);
    spr_view view;     /* set by spr_backend_set_view */
    int n_targets;     /* handles are 0 … n_targets−1 (maintained by the backend) */
    unsigned *target_planes; /* plane mask of each handle; 0 = no such target (free slot) */
    spr_error err;     /* last failure, one line */
    spr_probe *probe;  /* pixel probe (NULL: none); set by the history backend */
    int host_threads;  /* threads for a frame's host work (back-to-front orders, Gaussian tile lists): the CPU
                          backend's own count, so its one-thread frames are one thread throughout; 0 = OpenMP's default */
};

/* Set the view (no target may exist).  A backend may keep what it derived
 * from a draw's splats until the next set_view (swrast keeps the last
 * draw's tile bins for a draw of the same splats, radii and opacity, as
 * pbr2p1's two passes are): the arrays of a cloud drawn in a view must not
 * change until the view is set again. */
spr_result spr_backend_set_view(spr_backend *b, const spr_view *v);
/* A target with the planes of `planes` (SPR_PLANE_BIT mask, or SPR_PLANES_ALL). */
spr_result spr_backend_target_create(spr_backend *b, unsigned planes, int *out_target);
/* Plane mask of a live target (0 when there is no such target). */
unsigned spr_backend_target_planes(const spr_backend *b, int target);
void spr_backend_target_destroy(spr_backend *b, int target);
spr_result spr_backend_clear(spr_backend *b, int target, const float color[4]);
spr_result spr_backend_draw(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st);
spr_result spr_backend_composite(spr_backend *b, const spr_composite_desc *c);
spr_result spr_backend_draw_rects(spr_backend *b, int target, const spr_rect_draw_desc *d, spr_draw_stats *st);
spr_result spr_backend_gauss_preprocess(spr_backend *b, const spr_gauss_desc *d, float *rec);
spr_result spr_backend_gauss_raster(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st);
spr_result spr_backend_gauss_draw(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st);
spr_result spr_backend_gauss_backward(spr_backend *b, const spr_gauss_bwd_desc *d, float *sums, float *out);
spr_result spr_backend_read_plane(spr_backend *b, int target, spr_plane p, void *out);
/* 0 when a frame of d is within b's fixed limits, else the backend's error, one line naming the limit
 * (spr_render_fits asks it for a frame). */
spr_result spr_backend_fits(spr_backend *b, const spr_fit_desc *d);
/* The same, every plane as floats: id and count planes as their integer
 * values, "none" ids as −1 (what --dump, check and step show). */
spr_result spr_backend_read_plane_f(spr_backend *b, int target, spr_plane p, float *out);
void spr_backend_destroy(spr_backend *b);

/* Backends that wrap another (the trace and history backends) start with
 * this: spr__wrap_init forwards every entry point to `inner` (through the
 * validating wrappers; failures carry inner's message) — the wrapper then
 * replaces the entry points it watches, calling spr__wrap_pass_on on what
 * it forwards itself; spr__wrap_release destroys inner. */
typedef struct spr__wrap {
    spr_backend base;
    spr_backend *inner;
    unsigned char *slots;   /* spr__backend_add_target bookkeeping */
    int cap;
} spr__wrap;
void spr__wrap_init(spr__wrap *w, spr_backend *inner, void (*destroy)(spr_backend *));
spr_result spr__wrap_pass_on(spr_backend *b, spr_result r);
/* The forwarded target_create (handles kept in step with inner's). */
spr_result spr__wrap_target_create(spr_backend *b, unsigned mask, int *out);
void spr__wrap_release(spr__wrap *w);

/* Bookkeeping for implementations: take the lowest free handle (set in
 * *out_target at once, so that spr_backend_target_create frees it again if the
 * backend fails later) and make the backend's own per-target array (*slots,
 * *cap entries of slot_size bytes, new entries zeroed) long enough to hold it. */
spr_result spr__backend_add_target(spr_backend *b, unsigned planes, int *out_target, void **slots, int *cap,
                                   size_t slot_size);

#endif
