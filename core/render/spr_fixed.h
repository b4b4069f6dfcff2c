/* spr_fixed.h — GL's fixed-function stages as the reference performs them:
 * the depth comparison and blending (SPEC §3.3, §3.4).  These are not
 * shader arithmetic (GL does them in hardware), so they are not part of
 * the shared arithmetic; they mirror GL's factor arithmetic src·sf + dst·df, measured
 * identical on llvmpipe (PARITY.md "Fixed-function stages").  The CPU
 * backend (swrast/sw_fixed.h) and the pixel history's replay
 * (core/inspect/history.c) both use them.
 */
#ifndef SPR_FIXED_H
#define SPR_FIXED_H

#include "spr_backend.h"

static inline int spr_depth_passes(spr_depth_func f, float z, float zbuf)
{
    switch (f) {
    case SPR_FUNC_LEQUAL: return z <= zbuf;
    case SPR_FUNC_ALWAYS: return 1;
    case SPR_FUNC_LESS:
    default: return z < zbuf;
    }
}

/* One channel: replace dst = src; add dst = src + dst; over with a = the
 * source's fourth channel: t1 = src·a, t2 = dst·(1 − a), dst = t1 + t2;
 * premultiplied over: dst = src + dst·(1 − a). */
static inline float spr_blend1(spr_blend b, float src, float dst, float a)
{
    switch (b) {
    case SPR_BLEND_ADD: return src + dst;
    case SPR_BLEND_SUB: return dst - src; /* GL_FUNC_REVERSE_SUBTRACT with (ONE, ONE) */
    case SPR_BLEND_PREMUL: { /* (ONE, ONE_MINUS_SRC_ALPHA): src·1 is src, t2 = dst·(1 − a), dst = src + t2 */
        float oma = 1.0f - a;
        float t2 = dst * oma;
        return src + t2;
    }
    case SPR_BLEND_OVER: {
        float oma = 1.0f - a;
        float t1 = src * a, t2 = dst * oma;
        return t1 + t2;
    }
    case SPR_BLEND_REPLACE:
    default: return src;
    }
}

/* rgb under s->blend, alpha under s->blend_alpha (GL's separate blend). */
static inline void spr_blend4(const spr_pass_state *s, const float src[4], float dst[4])
{
    float a = src[3];
    for (int c = 0; c < 3; c++) dst[c] = spr_blend1(s->blend, src[c], dst[c], a);
    dst[3] = spr_blend1(s->blend_alpha, src[3], dst[3], a);
}

/* A target's planes as the stages below address them: base arrays, NULL
 * where the target lacks the plane; pixel pix is at [pix · channels]. */
typedef struct spr_fixed_planes {
    float *color, *depth, *test, *opacity, *normal;
    uint32_t *id, *count;
} spr_fixed_planes;

/* The depth test of a fragment with test value z at pixel pix and the test
 * plane's write; 1 when it passes (always, as in GL, without a test plane). */
static inline int spr_fixed_depth(const spr_pass_state *s, const spr_fixed_planes *pl, size_t pix, float z)
{
    if (!pl->test) return 1;
    if (!spr_depth_passes(s->depth_func, z, pl->test[pix])) return 0;
    if (s->depth_write) pl->test[pix] = z;
    return 1;
}

/* The writes after a passed depth test, as s->write_mask says: stored
 * depth t, colour src under the blends, id, count; for splats also the
 * opacity (replace or add) and (w·n, w) under the rgb blend (NULL: none). */
static inline void spr_fixed_writes(const spr_pass_state *s, const spr_fixed_planes *pl, size_t pix, float t, const float src[4], uint32_t id,
                                    const float *opacity, const float *nw)
{
    const unsigned mask = s->write_mask;
    if (mask & SPR_WRITE_DEPTH) pl->depth[pix] = t;
    if (mask & SPR_WRITE_COLOR) spr_blend4(s, src, pl->color + 4 * pix);
    if (mask & SPR_WRITE_ID) pl->id[pix] = id;
    if (mask & SPR_WRITE_COUNT) pl->count[pix]++;
    if ((mask & SPR_WRITE_OPACITY) && opacity) pl->opacity[pix] = spr_blend1(s->blend_alpha, *opacity, pl->opacity[pix], 1.0f);
    if ((mask & SPR_WRITE_NORMAL) && nw)
        for (int ch = 0; ch < 4; ch++) pl->normal[4 * pix + ch] = spr_blend1(s->blend, nw[ch], pl->normal[4 * pix + ch], 1.0f);
}

#endif
