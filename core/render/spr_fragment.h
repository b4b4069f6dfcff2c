/* spr_fragment.h — per-pixel arithmetic shared by every backend (SPEC §2, §3.3).
 *
 * This is the normative float sequence.  The CPU backend calls these
 * functions; the GL backend's shader writes the same operations in the same
 * order with `precise` (PARITY.md rules 1–4).  Sums are explicit and
 * parenthesised left to right; nothing here may use fma, dot products of a
 * library or transcendentals.  Build with -ffp-contract=off.
 */
#ifndef SPR_FRAGMENT_H
#define SPR_FRAGMENT_H

#include <math.h>
#include "spr_backend.h"

/* unproject(ndc, z): M·(x, y, z, 1) with explicit sums, then divide by w. */
static inline void spr_unproject(const float M[16], float x, float y, float z, float out[3])
{
    float hx = ((M[0] * x + M[1] * y) + M[2] * z) + M[3];
    float hy = ((M[4] * x + M[5] * y) + M[6] * z) + M[7];
    float hz = ((M[8] * x + M[9] * y) + M[10] * z) + M[11];
    float hw = ((M[12] * x + M[13] * y) + M[14] * z) + M[15];
    out[0] = hx / hw;
    out[1] = hy / hw;
    out[2] = hz / hw;
}

/* Ray of pixel (px, py): o0 on the near plane, d = o1 − o0 (SPEC §2). */
static inline void spr_pixel_ray(const spr_view *v, int px, int py, float o0[3], float d[3])
{
    float nx = ((float)px + 0.5f) * v->ndc_sx - 1.0f;
    float ny = ((float)py + 0.5f) * v->ndc_sy - 1.0f;
    float o1[3];
    spr_unproject(v->M, nx, ny, -1.0f, o0);
    spr_unproject(v->M, nx, ny, 1.0f, o1);
    d[0] = o1[0] - o0[0];
    d[1] = o1[1] - o0[1];
    d[2] = o1[2] - o0[2];
}

/* Ray–disk intersection.  Returns 1 when the closed disk covers the pixel
 * (0 ≤ t ≤ 1, ρ² ≤ 1), with t, ρ² and den (den > 0: back-facing). */
static inline int spr_ray_disk(const float o0[3], const float d[3], const float p[3], const float n[3],
                               float r, float *t_out, float *rho2_out, float *den_out)
{
    float den = (d[0] * n[0] + d[1] * n[1]) + d[2] * n[2];
    *den_out = den;
    if (den == 0.0f) return 0;
    float a0 = p[0] - o0[0], a1 = p[1] - o0[1], a2 = p[2] - o0[2];
    float num = (a0 * n[0] + a1 * n[1]) + a2 * n[2];
    float t = num / den;
    if (!(t >= 0.0f && t <= 1.0f)) return 0;
    float q0 = (o0[0] + t * d[0]) - p[0];
    float q1 = (o0[1] + t * d[1]) - p[1];
    float q2 = (o0[2] + t * d[2]) - p[2];
    float qq = (q0 * q0 + q1 * q1) + q2 * q2;
    float rho2 = qq / (r * r);
    if (!(rho2 <= 1.0f)) return 0;
    *t_out = t;
    *rho2_out = rho2;
    return 1;
}

/* z̃ of [ZP] Eq. 10, all in float. */
static inline float spr_z_lowres(const spr_lowres *L, float d_f)
{
    return floorf(((d_f - L->d_min) / (L->d_max - L->d_min)) * L->n) * L->inv_n;
}

/* Test value of a fragment for the pass state (SPEC §3.3), clamped to [0,1]
 * as GL clamps gl_FragDepth to the depth range. */
static inline float spr_test_value(const spr_pass_state *s, float d_f, float rho)
{
    float z;
    switch (s->depth_value) {
    case SPR_DEPTH_EPS_OFFSET: z = d_f + s->eps_t; break;
    case SPR_DEPTH_LOWRES: z = spr_z_lowres(&s->lowres, d_f); break;
    case SPR_DEPTH_VORONOI: z = spr_z_lowres(&s->lowres, d_f) + rho * s->lowres.inv_n; break;
    case SPR_DEPTH_PLAIN:
    default: z = d_f; break;
    }
    if (z < 0.0f) z = 0.0f;
    if (z > 1.0f) z = 1.0f;
    return z;
}

static inline int spr_depth_passes(spr_depth_func f, float z, float zbuf)
{
    switch (f) {
    case SPR_FUNC_LEQUAL: return z <= zbuf;
    case SPR_FUNC_ALWAYS: return 1;
    case SPR_FUNC_LESS:
    default: return z < zbuf;
    }
}

/* Blend src into dst (4 channels), GL's factor arithmetic: src·sf + dst·df
 * with sf = a, df = 1 − a for `over` (measured identical on llvmpipe,
 * PARITY.md "Fixed-function stages"). */
static inline void spr_blend4(spr_blend b, const float src[4], float dst[4])
{
    switch (b) {
    case SPR_BLEND_ADD:
        for (int c = 0; c < 4; c++) dst[c] = src[c] + dst[c];
        break;
    case SPR_BLEND_OVER: {
        float a = src[3], oma = 1.0f - a;
        for (int c = 0; c < 4; c++) {
            float t1 = src[c] * a, t2 = dst[c] * oma;
            dst[c] = t1 + t2;
        }
        break;
    }
    case SPR_BLEND_REPLACE:
    default:
        for (int c = 0; c < 4; c++) dst[c] = src[c];
        break;
    }
}

#endif
