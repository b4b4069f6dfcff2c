/* algo_depthpeel.c — depth peeling, the reference for transparency
 * (SPEC §6.4, [ZP] §6.3 and its ref. [11]).
 *
 *   for layer j = 0 … L−1, into its own target A_j:
 *       "visibility j": pbr2p1's pass 1 (z = d_f + ε_t, LESS, depth write),
 *       "blend j":      pbr2p1's pass 2 (LEQUAL, add (w·c, w) and w·α),
 *       both dropping every fragment with d_f ≤ Z_{j−1} = d(A_{j−1}) + ε_t
 *       (the depth mask of the layer before: the fragments beyond it);
 *       C_j = nearest(A_j): (c, α) = (Σ w·c / Σ w, Σ w·α / Σ w), depth d(A_j)
 *   composite "peel": back to front, c = α_j·c_j + (1 − α_j)·c over the
 *   background, for the layers that have a fragment at the pixel.
 * Every layer is a full pbr2p1 image, so a frame reads the data 2·L times.
 */
#include "spr_algo.h"

#include <stdlib.h>

#define SPR__PEEL_MAX 64

spr_result spr__algo_depthpeel(spr__run *run, int *final_target)
{
    const int L = run->desc->layers > 0 ? run->desc->layers : 8;
    if (L > SPR__PEEL_MAX) return spr__fail(run->err, SPR_E_ARG, "depthpeel: %d layers, at most %d", L, SPR__PEEL_MAX);
    int *T = malloc((size_t)(2 * L + 1) * sizeof *T);
    if (!T) return spr__fail(run->err, SPR_E_NOMEM, "depthpeel: out of memory");
    int *A = T, *C = T + L; /* C[L] = the image */
    spr_result r = SPR_OK;
    for (int j = 0; j < L && !r; j++) r = spr__run_target(run, SPR_PLANES_OPAQUE | SPR_PLANE_BIT(SPR_PLANE_OPACITY), &A[j]);
    for (int j = 0; j <= L && !r; j++) r = spr__run_target(run, SPR_PLANES_IMAGE, &C[j]);
    for (int j = 0; j < L && !r; j++) {
        spr_draw_desc d = {.cloud = run->cloud, .alpha = run->desc->alpha, .depth_mask = j > 0, .mask_target = j > 0 ? A[j - 1] : 0};
        spr_pass_state_defaults(&d.state);
        d.state.kernel = run->desc->kernel;
        d.state.eps_t = run->eps_t;
        d.state.depth_value = SPR_DEPTH_EPS_OFFSET;
        d.state.depth_func = SPR_FUNC_LESS;
        d.state.depth_write = 1;
        d.state.write_mask = SPR_WRITE_DEPTH | SPR_WRITE_ID;
        if ((r = spr__run_draw(run, "visibility", j, A[j], &d))) break;
        d.state.depth_value = SPR_DEPTH_PLAIN;
        d.state.depth_func = SPR_FUNC_LEQUAL;
        d.state.depth_write = 0;
        spr_pass_state_blend(&d.state, SPR_BLEND_ADD);
        d.state.write_mask = SPR_WRITE_COLOR | SPR_WRITE_COUNT | SPR_WRITE_OPACITY;
        if ((r = spr__run_draw(run, "blend", j, A[j], &d))) break;
        spr_composite_desc c = spr__run_comp(run, SPR_COMP_NEAREST, &A[j], 1, C[j]);
        r = spr__run_composite(run, "layer", &c);
    }
    if (!r) r = spr__run_finish(run, SPR_COMP_PEEL, C, L, final_target);
    free(T);
    return r;
}
