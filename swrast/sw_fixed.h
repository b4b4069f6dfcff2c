/* sw_fixed.h — GL's fixed-function stages as the CPU backend performs them:
 * the depth comparison and blending (SPEC §3.3, §3.4).  These are not
 * shader arithmetic (GL does them in hardware), so they are not part of
 * spr_arith.h; they mirror GL's factor arithmetic src·sf + dst·df, measured
 * identical on llvmpipe (PARITY.md "Fixed-function stages").
 */
#ifndef SW_FIXED_H
#define SW_FIXED_H

#include "sw_internal.h"

static inline int sw_depth_passes(spr_depth_func f, float z, float zbuf)
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
static inline float sw_blend1(spr_blend b, float src, float dst, float a)
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
static inline void sw_blend4(const spr_pass_state *s, const float src[4], float dst[4])
{
    float a = src[3];
    for (int c = 0; c < 3; c++) dst[c] = sw_blend1(s->blend, src[c], dst[c], a);
    dst[3] = sw_blend1(s->blend_alpha, src[3], dst[3], a);
}

/* The depth test of a fragment with test value z at pixel pix and the test
 * plane's write; 1 when it passes. */
static inline int sw_depth_stage(const spr_pass_state *s, float *test, size_t pix, float z)
{
    if (!sw_depth_passes(s->depth_func, z, test[pix])) return 0;
    if (s->depth_write) test[pix] = z;
    return 1;
}

/* The writes every draw makes after the depth test, as s->write_mask says:
 * stored depth t, colour src under the blend, id, count (splats add the
 * opacity and normal planes themselves). */
static inline void sw_plane_writes(const spr_pass_state *s, sw_target *tg, size_t pix, float t, const float src[4], uint32_t id)
{
    const unsigned mask = s->write_mask;
    if (mask & SPR_WRITE_DEPTH) SW_F(tg, DEPTH)[pix] = t;
    if (mask & SPR_WRITE_COLOR) sw_blend4(s, src, SW_F(tg, COLOR) + 4 * pix);
    if (mask & SPR_WRITE_ID) SW_U(tg, ID)[pix] = id;
    if (mask & SPR_WRITE_COUNT) SW_U(tg, COUNT)[pix]++;
}

#endif
