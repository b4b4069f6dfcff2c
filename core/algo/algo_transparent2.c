/* algo_transparent2.c — transparent surfaces, Algorithm-2 of [ZP] §3.3
 * (SPEC §6.2), two geometry passes and three composite passes.
 *
 *   1. nearest layer: the opaque geometry pass of §4.2 into I_k, writing the
 *      weighted opacity w·α into the opacity plane as well
 *      F = nearest(I_0 … I_{K−1}): C_F = the ε-composite of colour,
 *      α_F = the same composite of the opacity, depth = min_k d_f(k)
 *   2. other layers: the back-to-front pass of §6.1 into O_k, dropping
 *      fragments with d_f ≤ Z, Z = depth(F) + ε_t (the depth mask)
 *      C_O = average(O_0 … O_{K−1})
 *   3. I = α_F·C_F + (1 − α_F)·C_O where F has a fragment, background elsewhere
 * The other layers' alpha channel adds (SPEC §6.3): C_O's fourth channel is
 * the mean α_total, from which the final composite counts the layers for
 * the environment effects.  With deferred shading or environment effects
 * the nearest layer carries (w·n, w) in a normal plane, composited into F.
 */
#include "spr_algo.h"

#include <stdlib.h>

spr_result spr__algo_transparent2(spr__run *run, int *final_target)
{
    const spr_groups *g = run->desc->groups;
    const int K = g ? g->K : 1;
    /* I_0 … I_{K−1}, F, O_0 … O_{K−1}, C_O, the image */
    int *T = malloc((size_t)(2 * K + 3) * sizeof *T);
    if (!T) return spr__fail(run->err, SPR_E_NOMEM, "transparent2: out of memory");
    int *I = T, *O = T + K + 1;
    const int F = K, CO = 2 * K + 1, OUT = 2 * K + 2;
    spr_result r = SPR_OK;
    const unsigned nrm = spr__run_normal_planes(run);
    for (int k = 0; k < K && !r; k++) r = spr__run_target(run, SPR_PLANES_OPAQUE | SPR_PLANE_BIT(SPR_PLANE_OPACITY) | nrm, &I[k]);
    for (int k = 0; k < K && !r; k++) r = spr__run_target(run, SPR_PLANES_OPAQUE, &O[k]);
    if (!r) r = spr__run_target(run, SPR_PLANES_IMAGE | nrm, &T[F]);
    if (!r) r = spr__run_target(run, SPR_PLANES_IMAGE, &T[CO]);
    if (!r) r = spr__run_target(run, SPR_PLANES_IMAGE, &T[OUT]);
    if (r) goto done;
    if ((r = spr__deferred_geometry(run, I, SPR_WRITE_OPACITY))) goto done;
    spr_composite_desc c = spr__run_comp(run, SPR_COMP_NEAREST, I, K, T[F]);
    if ((r = spr__run_composite(run, "nearest layer", &c))) goto done;
    if ((r = spr__transparent_geometry(run, O, T[F]))) goto done;
    c = spr__run_comp(run, SPR_COMP_AVERAGE, O, K, T[CO]);
    if ((r = spr__run_composite(run, "other layers average", &c))) goto done;
    int last[3] = {T[F], T[CO], T[OUT]};
    r = spr__run_finish(run, SPR_COMP_TRANSPARENT2, last, 2, final_target);
done:
    free(T);
    return r;
}
