/* overlap_graph.c — the neighbour graphs of grouping (SPEC §5): all pairs
 * with |p_i − p_j| < f·(r_i + r_j) found with FLANN, and the overlap graph
 * (f = 1) with the areas A_ij of [ZP] Eq. 8 on every directed edge, shared
 * by WGC, hash collision handling, extended grouping and the metrics. */
#include "spr_group.h"
#include "spr_overlap.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

void spr_overlap_graph_free(spr_overlap_graph *og)
{
    spr_graph_free(&og->g);
    free(og->A);
    memset(og, 0, sizeof *og);
}

/* Neighbour graph with |p_i − p_j| < f·(r_i + r_j). */
spr_result spr__pair_graph(const spr_cloud *c, double f, int threads, const spr_progress *prog, spr_graph *g, spr_error *err)
{
    return spr__pair_graph_rows(c, f, NULL, 0, threads, prog, g, err);
}

spr_result spr__pair_graph_rows(const spr_cloud *c, double f, const unsigned char *row, unsigned char want, int threads,
                                const spr_progress *prog, spr_graph *g, spr_error *err)
{
    spr_bounds b;
    spr_cloud_bounds(c, &b);
    spr_knn *kn;
    spr_result r = spr_knn_build(c->pos, c->n, &kn, err);
    if (r) return r;
    r = spr_knn_radius_graph_rows(kn, c->radius, f, b.max_radius, row, want, threads, g, prog, err);
    spr_knn_free(kn);
    if (r) return r;
    uint64_t w = 0;
    for (size_t i = 0; i < c->n; i++) {
        uint64_t s = g->start[i], e = g->start[i + 1];
        g->start[i] = w;
        for (uint64_t k = s; k < e; k++) {
            size_t j = g->adj[k];
            double d2 = 0.0;
            for (int a = 0; a < 3; a++) {
                double q = (double)c->pos[3 * i + a] - c->pos[3 * j + a];
                d2 += q * q;
            }
            double lim = f * ((double)c->radius[i] + c->radius[j]);
            if (d2 < lim * lim) g->adj[w++] = g->adj[k];
        }
    }
    g->start[c->n] = w;
    return SPR_OK;
}

spr_result spr_overlap_graph_build(const spr_cloud *c, double eps, int threads, const spr_progress *prog,
                                   spr_overlap_graph *og, spr_error *err)
{
    return spr_overlap_graph_build_rows(c, eps, NULL, 0, threads, prog, og, err);
}

spr_result spr_overlap_graph_build_rows(const spr_cloud *c, double eps, const unsigned char *row, unsigned char want, int threads,
                                        const spr_progress *prog, spr_overlap_graph *og, spr_error *err)
{
    return spr_overlap_graph_build_rows_need(c, eps, row, want, threads, prog, NULL, NULL, og, err);
}

spr_result spr_overlap_graph_build_rows_need(const spr_cloud *c, double eps, const unsigned char *row, unsigned char want, int threads,
                                             const spr_progress *prog, spr_area_need need, const void *need_user, spr_overlap_graph *og,
                                             spr_error *err)
{
    memset(og, 0, sizeof *og);
    og->eps = eps;
    spr_result r = spr__pair_graph_rows(c, 1.0, row, want, threads, prog, &og->g, err);
    if (r) return r;
    const spr_graph *g = &og->g;
    const uint64_t w = g->start[c->n];
    og->A = malloc((w ? w : 1) * sizeof(float));
    if (!og->A) { spr_overlap_graph_free(og); return spr__fail(err, SPR_E_NOMEM, "groups: out of memory for overlap areas"); }
    const long n = (long)c->n;
    uint64_t max_deg = 0;
    for (long i = 0; need && i < n; i++)
        if (g->start[i + 1] - g->start[i] > max_deg) max_deg = g->start[i + 1] - g->start[i];
    int failed = 0;
#pragma omp parallel num_threads(threads > 0 ? threads : 1) reduction(| : failed)
    {
        uint32_t *js = need ? malloc((max_deg ? max_deg : 1) * sizeof *js) : NULL; /* the needed neighbours of a row */
        float *as = need ? malloc((max_deg ? max_deg : 1) * sizeof *as) : NULL;
        failed |= need && (!js || !as);
#pragma omp for schedule(dynamic, 256)
        for (long i = 0; i < n; i++) {
            if ((i & 0x3FFF) == 0 && omp_get_thread_num() == 0) spr_progress_report(prog, "overlap areas", (size_t)i, (size_t)n);
            const uint32_t *adj = g->adj + g->start[i];
            const size_t deg = (size_t)(g->start[i + 1] - g->start[i]);
            float *A = og->A + g->start[i];
            if (!need) {
                spr_overlap_areas(c, (size_t)i, adj, deg, eps, A);
                continue;
            }
            if (!js || !as) continue;
            size_t m = 0;
            for (size_t k = 0; k < deg; k++) {
                A[k] = -1.0f;
                if (need(need_user, (size_t)i, adj[k])) js[m++] = adj[k];
            }
            spr_overlap_areas(c, (size_t)i, js, m, eps, as); /* per edge: the same arithmetic as the whole row */
            for (size_t k = 0, q = 0; k < deg && q < m; k++)
                if (adj[k] == js[q]) A[k] = as[q++];
        }
        free(js);
        free(as);
    }
    if (failed) { spr_overlap_graph_free(og); return spr__fail(err, SPR_E_NOMEM, "groups: out of memory for overlap areas"); }
    spr_progress_report(prog, "overlap areas", c->n, c->n);
    return SPR_OK;
}

