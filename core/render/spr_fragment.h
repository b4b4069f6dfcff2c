/* spr_fragment.h — the shared per-pixel arithmetic (core/render/arith/) seen from C.
 *
 * Convenience wrappers that take the host's structures (spr_view,
 * spr_pass_state) and pass their float bits to the shared functions; they
 * add no arithmetic of their own.  The pixel centre x + 0.5 is exact in
 * float, as gl_FragCoord.x is in GL.
 */
#ifndef SPR_FRAGMENT_H
#define SPR_FRAGMENT_H

#include "spr_arith_c.h"

/* Ray of pixel (px, py): o0 on the near plane, d = o1 − o0 (SPEC §2). */
static inline void spr_pixel_ray(const spr_view *v, int px, int py, float o0[3], float d[3])
{
    spr_ray_of_pixel(v->M, v->ndc_sx, v->ndc_sy, (float)px + 0.5f, (float)py + 0.5f, o0, d);
}

/* Test value of a fragment for the pass state (SPEC §3.3). */
static inline float spr_test_value(const spr_pass_state *s, float d_f, float rho)
{
    const spr_lowres *L = &s->lowres;
    return spr_test_depth((int)s->depth_value, s->eps_t, L->d_min, L->d_max, L->n, L->inv_n, d_f, rho);
}

#endif
