/* algo_transparent1.c — transparent surfaces, Algorithm-1 of [ZP] §3.3
 * (SPEC §6.1), one geometry pass and one compositing pass.
 *
 *   order  = every splat back to front for the view (BSP traversal, or
 *            sorting the centres by view depth), computed on the host
 *   for each group k = 0 … K−1:
 *       clear I_k to (background, 0)
 *       draw S_k in that order (radii r̃ = scale_k·r_i when the groups carry
 *       them), fragment (c, α), depth test LESS on z̃ with depth write on
 *       ([ZP] Eq. 10, SPEC §5.4: in one surface layer only the first
 *       fragment in back-to-front order passes), blend `over` on all four
 *       channels: dst = src·α + dst·(1 − α)
 *   composite: I = (1/K) Σ_k I_k (the `average` op; [ZP]'s I = ½(I_A + I_B))
 */
#include "spr_algo.h"
#include "spr_bsp.h"

#include <stdlib.h>
#include <string.h>

typedef struct depth_key { double depth; uint32_t id; } depth_key;
static int far_first(const void *a, const void *b)
{
    const depth_key *x = a, *y = b;
    if (x->depth != y->depth) return x->depth > y->depth ? -1 : 1;
    return (x->id > y->id) - (x->id < y->id);
}

/* Every splat id, farthest first: view depth −z_eye of the centre, in double. */
static spr_result back_to_front(spr__run *run, const spr_view *v, uint32_t *out)
{
    const spr_cloud *c = run->cloud;
    if (run->desc->order == SPR_ORDER_BSP) {
        const spr_bsp *kept = run->desc->bsp; /* the kept tree: only the traversal is per frame */
        if (kept && kept->n != c->n)
            return spr__fail(run->err, SPR_E_ARG, "render: the BSP tree is for %zu splats, the model has %zu", kept->n, c->n);
        spr_bsp t;
        spr_result r = kept ? SPR_OK : spr__bsp_build_threads(c, run->b->host_threads, &t, run->err);
        if (r) return r;
        if (spr__bsp_back_to_front_threads(kept ? kept : &t, c, v, run->b->host_threads, out)) r = spr__fail(run->err, SPR_E_NOMEM, "%s: out of memory", spr_algo_name(run->desc->algo));
        if (!kept) spr_bsp_free(&t);
        return r;
    }
    depth_key *k = malloc((c->n ? c->n : 1) * sizeof *k);
    if (!k) return spr__fail(run->err, SPR_E_NOMEM, "transparent1: out of memory");
    for (size_t i = 0; i < c->n; i++) {
        const float *p = c->pos + 3 * i;
        k[i].depth = -(((v->V[8] * p[0] + v->V[9] * p[1]) + v->V[10] * p[2]) + v->V[11]);
        k[i].id = (uint32_t)i;
    }
    qsort(k, c->n, sizeof *k, far_first);
    for (size_t i = 0; i < c->n; i++) out[i] = k[i].id;
    free(k);
    return SPR_OK;
}

/* The back-to-front pass into O[0 … K−1] (created by the caller), cleared
 * here to (background, 0); with mask ≥ 0, fragments within the nearest
 * layer of target `mask` (d_f ≤ its depth + ε_t) are dropped (SPEC §6.2
 * step 2), the alpha channel adds (α_total, SPEC §6.3) and, with
 * environment effects, the colour starts from 0 instead of the background
 * (the environment seen through the layers is added by the composite). */
spr_result spr__transparent_geometry(spr__run *run, const int *O, int mask)
{
    const spr_cloud *cl = run->cloud;
    const spr_groups *g = run->desc->groups;
    const int K = g ? g->K : 1;
    const size_t n = cl->n;
    const size_t total = g ? g->start[K] : n; /* memberships (splats in several groups with duplication) */
    uint32_t *order = malloc((n ? n : 1) * sizeof *order), *members = malloc((total ? total : 1) * sizeof *members);
    uint32_t *first = g ? calloc(n + 1, sizeof *first) : NULL, *of = g ? malloc((total ? total : 1) * sizeof *of) : NULL;
    uint32_t *fill = g ? malloc((size_t)K * sizeof *fill) : NULL, *pos = g ? malloc((n ? n : 1) * sizeof *pos) : NULL;
    spr_result r = SPR_OK;
    if (!order || !members || (g && (!first || !of || !fill || !pos))) {
        r = spr__fail(run->err, SPR_E_NOMEM, "%s: out of memory", spr_algo_name(run->desc->algo));
        goto done;
    }
    if ((r = back_to_front(run, &run->b->view, order))) goto done;
    const int zero_bg = mask >= 0 && run->prm[SPR_PRM_ENV] != 0.0f;
    const float bg[4] = {zero_bg ? 0.0f : run->desc->background[0], zero_bg ? 0.0f : run->desc->background[1],
                         zero_bg ? 0.0f : run->desc->background[2], 0.0f};
    for (int k = 0; k < K && !r; k++)
        if ((r = spr_backend_clear(run->b, O[k], bg))) spr__fail(run->err, r, "%s: %s", spr_algo_name(run->desc->algo), run->b->err.msg);
    if (r) goto done;
    spr_draw_desc d = {.cloud = cl, .alpha = run->desc->alpha, .depth_mask = mask >= 0, .mask_target = mask};
    spr_pass_state_defaults(&d.state);
    d.state.output = SPR_OUT_ALPHA;
    d.state.depth_value = SPR_DEPTH_LOWRES;
    d.state.lowres = run->lowres;
    d.state.eps_t = run->eps_t;
    d.state.depth_func = SPR_FUNC_LESS;
    d.state.depth_write = 1;
    spr_pass_state_blend(&d.state, SPR_BLEND_OVER);
    if (mask >= 0) d.state.blend_alpha = SPR_BLEND_ADD;
    d.state.write_mask = SPR_WRITE_ALL;
    /* Every S_k in back-to-front order from one walk of the global order:
     * each splat's groups (a table from the memberships), and each splat met
     * appended to its groups' lists, which then follow the order. */
    if (g) {
        /* of[first[s] … first[s+1]): the groups of splat s, ascending */
        for (uint32_t e = 0; e < g->start[K]; e++) first[g->members[e] + 1]++;
        for (size_t i = 0; i < n; i++) first[i + 1] += first[i];
        memcpy(pos, first, n * sizeof *pos);
        for (int k = 0; k < K; k++)
            for (uint32_t e = g->start[k]; e < g->start[k + 1]; e++) of[pos[g->members[e]]++] = (uint32_t)k;
        for (int k = 0; k < K; k++) fill[k] = g->start[k];
        for (size_t i = 0; i < n; i++) {
            const uint32_t sid = order[i];
            for (uint32_t q = first[sid]; q < first[sid + 1]; q++) members[fill[of[q]]++] = sid;
        }
    } else {
        memcpy(members, order, n * sizeof *members);
    }
    for (int k = 0; k < K; k++) {
        const size_t m = g ? g->start[k + 1] - g->start[k] : n;
        d.indices = members + (g ? g->start[k] : 0);
        d.count = m;
        d.radius_scale = spr__group_radius_scale(g, k);
        if ((r = spr__run_draw(run, mask >= 0 ? "other layers" : "geometry", k, O[k], &d))) goto done;
    }
done:
    free(order);
    free(first);
    free(of);
    free(fill);
    free(pos);
    free(members);
    return r;
}

spr_result spr__algo_transparent1(spr__run *run, int *final_target)
{
    const spr_groups *g = run->desc->groups;
    const int K = g ? g->K : 1;
    int *I = malloc((size_t)(K + 1) * sizeof *I);
    if (!I) return spr__fail(run->err, SPR_E_NOMEM, "transparent1: out of memory");
    spr_result r = SPR_OK;
    for (int k = 0; k < K && !r; k++) r = spr__run_target(run, SPR_PLANES_OPAQUE, &I[k]);
    if (!r) r = spr__run_target(run, SPR_PLANES_IMAGE, &I[K]);
    if (!r) r = spr__transparent_geometry(run, I, -1);
    if (!r) r = spr__run_finish(run, SPR_COMP_AVERAGE, I, K, final_target);
    free(I);
    return r;
}
