/* spr_arith_c.h — the shared arithmetic (core/render/arith/) compiled as C.
 *
 * Gives the macros of the shared arithmetic their C meaning (see the table
 * at the top of arith/base.h), defines how the CPU side fetches a pixel's
 * input targets, and includes the shared text.  Build with
 * -ffp-contract=off: C then evaluates exactly the written operations.
 */
#ifndef SPR_ARITH_C_H
#define SPR_ARITH_C_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "spr_backend.h"
#include "spr_kernel.h"

#define SPR_FN static inline
#define SPR_FN_INLINE static inline __attribute__((always_inline)) /* a step of a hot loop, called from more than one place */
#define SPR_PRECISE
#define SPR_CARR const float
#define SPR_OARR float
#define SPR_IOARR float
#define SPR_OUT float *
#define SPR_SET(x) (*(x))
#define SPR_REF(x) (&(x))
#define SPR_FLOAT(i) ((float)(i))
#define SPR_INT(x) ((int)(x))
#define SPR_PIXEL const spr_pixel_in *
#define spr_floor floorf
#define spr_ceil ceilf
#define spr_sqrt sqrtf
#define spr_ldexp spr__ldexp_c

/* x·2^n, exact for a normal result as GLSL's ldexp: 2^n built from its bits
 * and one multiply while 2^n is a normal float (libm's ldexpf, a tenth of
 * gauss3d's raster time, only outside that range).  The two differ only
 * where the product is subnormal and the CPU's FTZ flushes it; spr_exp's
 * results stay above 2^-126 (SPEC 10.6). */
static inline float spr__ldexp_c(float x, int n)
{
    if (n < -126 || n > 127) return ldexpf(x, n);
    union { uint32_t u; float f; } p = {(uint32_t)(n + 127) << 23};
    return x * p.f;
}

/* A pixel's inputs on the CPU: plane arrays of the input targets, pixel i. */
typedef struct spr_pixel_in {
    const float *const *color; /* color[k]: input k's colour plane, 4 per pixel */
    const float *const *depth; /* depth[k]: input k's stored depth plane */
    const float *const *opacity; /* opacity[k]: input k's opacity plane (ops that read it) */
    const float *const *normal; /* normal[k]: input k's normal plane, 4 per pixel (when shading) */
    const spr_envmap *env;     /* the cube map (environment effects) */
    const float *texels;       /* the rectangles' texels, 4 per texel (rectangle draws) */
    const struct spr_frag_lists *lists; /* input 0's fragment lists (the prefix op) */
    const uint32_t *nbr;       /* neighbour bits of the rectangles (spr_rects.nbr) */
    size_t nbr_words;
    const float *grec;         /* Gaussian records, SPR_GREC_FLOATS each (SPEC 10) */
    const uint32_t *granges;   /* first list entry of each tile, GX·GY + 1 */
    const uint32_t *glist;     /* the tiles' sorted lists */
    const float *gup;          /* gauss3d's backward: the upstream gradient, 5 per pixel (∂L/∂C, ∂L/∂A, ∂L/∂D) */
    float *gpart;              /* its list entries' partials, SPR_GPART_FLOATS each, from entry gpart_base */
    size_t gpart_base;
    const uint32_t *gcsr;      /* each Gaussian's list entries, ascending */
    uint32_t *gbs;             /* gauss3d's backward: a tile's walk state (SPR_GBS_FLOATS, spr_gauss_tile_bwd) */
    size_t i;
    int x, y;                  /* the pixel: i = y·W + x */
    spr_probe *probe;          /* set at the probed pixel only (pixel history) */
} spr_pixel_in;
/* A note of the per-pixel functions, kept only at the probed pixel. */
#define SPR_NOTE(px, tag, k, a, b, c, d) \
    do { \
        if ((px)->probe) spr_probe_add_note((px)->probe, (tag), (k), (a), (b), (c), (d)); \
    } while (0)
static inline float spr_in_depth(const spr_pixel_in *px, int k) { return px->depth[k][px->i]; }
static inline float spr_in_color(const spr_pixel_in *px, int k, int ch) { return px->color[k][4 * px->i + (size_t)ch]; }
static inline float spr_in_opacity(const spr_pixel_in *px, int k) { return px->opacity[k][px->i]; }
static inline float spr_in_normal(const spr_pixel_in *px, int k, int ch) { return px->normal[k][4 * px->i + (size_t)ch]; }
static inline float spr_px_cx(const spr_pixel_in *px) { return (float)px->x + 0.5f; }
static inline int spr_px_x(const spr_pixel_in *px) { return px->x; }
static inline int spr_px_y(const spr_pixel_in *px) { return px->y; }
static inline int spr_gtile_first(const spr_pixel_in *px, int tile) { return (int)px->granges[tile]; }
static inline int spr_gtile_end(const spr_pixel_in *px, int tile) { return (int)px->granges[tile + 1]; }
static inline int spr_glist(const spr_pixel_in *px, int e) { return (int)px->glist[e]; }
static inline float spr_grec(const spr_pixel_in *px, int G, int f) { return px->grec[(size_t)G * SPR_GREC_FLOATS + (size_t)f]; }
static inline float spr_in_grad_i(const spr_pixel_in *px, int i, int k) { return px->gup[5 * (size_t)i + (size_t)k]; }
static inline float spr_gbs(const spr_pixel_in *px, int k)
{
    float v;
    memcpy(&v, &px->gbs[k], sizeof v);
    return v;
}
static inline void spr_gbs_set(const spr_pixel_in *px, int k, float v) { memcpy(&px->gbs[k], &v, sizeof v); }
static inline int spr_gbs_i(const spr_pixel_in *px, int k) { return (int)px->gbs[k]; }
static inline void spr_gbs_seti(const spr_pixel_in *px, int k, int v) { px->gbs[k] = (uint32_t)v; }
static inline float spr_gpart(const spr_pixel_in *px, int e, int f) { return px->gpart[((size_t)e - px->gpart_base) * SPR_GPART_FLOATS + (size_t)f]; }
static inline void spr_gpart_set(const spr_pixel_in *px, int e, int f, float v) { px->gpart[((size_t)e - px->gpart_base) * SPR_GPART_FLOATS + (size_t)f] = v; }
static inline int spr_gcsr(const spr_pixel_in *px, int k) { return (int)px->gcsr[k]; }
static inline float spr_px_cy(const spr_pixel_in *px) { return (float)px->y + 0.5f; }
static inline float spr_in_env(const spr_pixel_in *px, int face, int i, int j, int ch)
{
    const size_t S = (size_t)px->env->size;
    return px->env->texels[(((size_t)face * S + (size_t)j) * S + (size_t)i) * 4 + (size_t)ch];
}

/* Fragment lists on the CPU: the nodes of pixel i are first[i] … first[i+1]−1
 * (made by counting, then filling: sw_rect.c). */
typedef struct spr_frag_lists {
    uint32_t *first;   /* W·H + 1 */
    float *t;          /* per node: ray parameter */
    uint32_t *prim;    /* per node: rectangle index */
    float *src;        /* per node: 4 colour channels */
    size_t n, cap;
} spr_frag_lists;
static inline float spr_in_texel(const spr_pixel_in *px, int k, int ch) { return px->texels[4 * (size_t)k + (size_t)ch]; }
static inline int spr_list_first(const spr_pixel_in *px)
{
    return px->lists->first[px->i] < px->lists->first[px->i + 1] ? (int)px->lists->first[px->i] : -1;
}
static inline int spr_list_next(const spr_pixel_in *px, int node)
{
    return (uint32_t)node + 1 < px->lists->first[px->i + 1] ? node + 1 : -1;
}
static inline float spr_list_t(const spr_pixel_in *px, int node) { return px->lists->t[node]; }
static inline int spr_list_prim(const spr_pixel_in *px, int node) { return (int)px->lists->prim[node]; }
static inline float spr_list_src(const spr_pixel_in *px, int node, int ch) { return px->lists->src[4 * (size_t)node + (size_t)ch]; }
static inline int spr_neighbour(const spr_pixel_in *px, int a, int b)
{
    return spr_rects_neighbours(px->nbr, px->nbr_words, (size_t)a, (size_t)b);
}

/* core/render/arith/, in the order of its ORDER file; GLSL compiles the same
 * text, where a parameter some functions leave unused cannot be cast away */
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#endif
#include "spr_arith_parts.h"
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#endif
