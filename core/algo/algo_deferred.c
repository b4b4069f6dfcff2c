/* algo_deferred.c — 1+1-pass deferred blending (SPEC §4.2, [ZP] §3.2, Fig. 6, 11).
 *
 *   geometry pass, for k = 0 … K−1:
 *       clear I_k; draw S_k with depth test LESS and depth write on,
 *       test value z = d_f, or z̃ + ρ/n with Voronoi depth ([ZP] Eq. 14);
 *       each surviving fragment replaces the pixel with (w·c, w) and d_f (Eq. 4)
 *       (with enlarged radii r̃ = scale_k·r_i when the groups carry them, [ZP] §4.4.2)
 *   compositing pass (one full-screen operation over I_0 … I_{K−1}):
 *       d = min_k d_f(k); sum the I_k with d_f(k) ≤ d + ε_t; normalise
 *   with deferred shading (SPEC §4.3) the geometry pass also writes (w·n, w)
 *   to a normal plane, composited like colour, and the composite shades.
 */
#include "spr_algo.h"

#include <stdlib.h>

/* The geometry pass into I[0 … K−1] (created by the caller); `extra`
 * adds planes to the write mask (transparent2 writes the opacity w·α too). */
spr_result spr__deferred_geometry(spr__run *run, const int *I, unsigned extra)
{
    const spr_groups *g = run->desc->groups;
    const int K = g ? g->K : 1;
    spr_draw_desc d = {.cloud = run->cloud};
    spr_pass_state_defaults(&d.state);
    d.state.kernel = run->desc->kernel;
    d.state.depth_value = run->desc->voronoi ? SPR_DEPTH_VORONOI : SPR_DEPTH_PLAIN;
    d.state.lowres = run->lowres;
    d.state.eps_t = run->eps_t;
    d.state.depth_func = SPR_FUNC_LESS;
    d.state.depth_write = 1;
    spr_pass_state_blend(&d.state, SPR_BLEND_REPLACE);
    d.state.write_mask = SPR_WRITE_ALL | extra | spr__run_normal_planes(run);
    d.alpha = run->desc->alpha;
    spr_result r = SPR_OK;
    /* S_k: the memberships of group k, in submission order, into I_k */
    spr_draw_desc *dk = malloc((size_t)K * sizeof *dk);
    int *group = malloc((size_t)K * sizeof *group);
    if (!dk || !group) r = spr__fail(run->err, SPR_E_NOMEM, "%s: out of memory", spr_algo_name(run->desc->algo));
    for (int k = 0; k < K && !r; k++) {
        dk[k] = d;
        dk[k].indices = g ? g->members + g->start[k] : NULL;
        dk[k].count = g ? g->start[k + 1] - g->start[k] : run->cloud->n;
        dk[k].radius_scale = spr__group_radius_scale(g, k); /* enlarged radii (extension, [ZP] §4.4.2) */
        group[k] = k;
    }
    if (!r) r = spr__run_draws(run, "geometry", group, I, dk, K);
    free(dk);
    free(group);
    return r;
}

spr_result spr__algo_deferred(spr__run *run, int *final_target)
{
    const spr_groups *g = run->desc->groups;
    int K = g ? g->K : 1;
    int *I = malloc((size_t)(K + 1) * sizeof(int));
    if (!I) return spr__fail(run->err, SPR_E_NOMEM, "deferred: out of memory");
    spr_result r = SPR_OK;
    for (int k = 0; k < K && !r; k++) r = spr__run_target(run, SPR_PLANES_OPAQUE | spr__run_normal_planes(run), &I[k]);
    if (!r) r = spr__run_target(run, SPR_PLANES_IMAGE, &I[K]);
    if (!r) r = spr__deferred_geometry(run, I, 0);
    if (!r) r = spr__run_finish(run, SPR_COMP_DEFERRED, I, K, final_target);
    free(I);
    return r;
}
