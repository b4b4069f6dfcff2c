/* sw_fixed.h — the fixed-function stages of core/render/spr_fixed.h
 * applied to the CPU backend's targets: the depth stage and the plane
 * writes after it.
 */
#ifndef SW_FIXED_H
#define SW_FIXED_H

#include "sw_internal.h"
#include "spr_fixed.h"

/* The depth test of a fragment with test value z at pixel pix and the test
 * plane's write; 1 when it passes. */
static inline int sw_depth_stage(const spr_pass_state *s, float *test, size_t pix, float z)
{
    if (!spr_depth_passes(s->depth_func, z, test[pix])) return 0;
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
    if (mask & SPR_WRITE_COLOR) spr_blend4(s, src, SW_F(tg, COLOR) + 4 * pix);
    if (mask & SPR_WRITE_ID) SW_U(tg, ID)[pix] = id;
    if (mask & SPR_WRITE_COUNT) SW_U(tg, COUNT)[pix]++;
}

#endif
