/* spr_fixed.h — GL's fixed-function stages as the reference performs them:
 * the depth comparison and blending (SPEC §3.3, §3.4).  These are not
 * shader arithmetic (GL does them in hardware), so they are not part of
 * spr_arith.h; they mirror GL's factor arithmetic src·sf + dst·df, measured
 * identical on llvmpipe (PARITY.md "Fixed-function stages").  The CPU
 * backend (swrast/sw_fixed.h) and the pixel history's replay
 * (core/render/history.c) both use them.
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
 * source's fourth channel: t1 = src·a, t2 = dst·(1 − a), dst = t1 + t2. */
static inline float spr_blend1(spr_blend b, float src, float dst, float a)
{
    switch (b) {
    case SPR_BLEND_ADD: return src + dst;
    case SPR_BLEND_SUB: return dst - src; /* GL_FUNC_REVERSE_SUBTRACT with (ONE, ONE) */
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

#endif
