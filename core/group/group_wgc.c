/* group_wgc.c — weighted graph colouring with K colours ([ZP] §4.2, SPEC §5.2).
 *
 *   A_ij   = area of disk i within ε of plane j projecting into disk j (Eq. 8)
 *   w_ij   = (A_ij + A_ji)(1 − n_i·n_j)                                 (Eq. 7)
 *   L(G,K) = Σ_{(i,j) ∈ E, c_i = c_j} w_ij                              (Eq. 6)
 *   1. edges by w descending (ties (i,j)): colour j, then i, if uncoloured,
 *      by MinimizeOverlap; isolated vertices get (index mod K)
 *   2. max-heap of vertices by S(v) = Σ w_vj over same-coloured neighbours:
 *      pop the largest, recolour by MinimizeOverlap, re-insert while
 *      S(v) ≥ τ_w; stop when empty or after 10·n pops
 * [decision] a recolouring is applied only when it does not raise S(v):
 * MinimizeOverlap minimises Σ A while L weighs w, and without the guard a
 * step could raise L.  Every applied step lowers L by S_old − S_new ≥ 0.
 */
#include "spr_util.h"
#include "spr_group.h"
#include "spr_overlap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <omp.h>
#include <time.h>

/* Position of j in i's (ascending) adjacency list. */
static uint64_t edge_of(const spr_graph *g, size_t i, uint32_t j)
{
    uint64_t lo = g->start[i], hi = g->start[i + 1];
    while (lo < hi) {
        uint64_t mid = lo + (hi - lo) / 2;
        if (g->adj[mid] < j) lo = mid + 1; else hi = mid;
    }
    return lo;
}

float *spr_wgc_weights(const spr_cloud *c, const spr_overlap_graph *og)
{
    const spr_graph *g = &og->g;
    float *w = malloc((g->start[c->n] ? g->start[c->n] : 1) * sizeof(float));
    if (!w) return NULL;
    for (size_t i = 0; i < c->n; i++)
        for (uint64_t e = g->start[i]; e < g->start[i + 1]; e++) {
            uint32_t j = g->adj[e];
            const float *ni = c->nrm + 3 * i, *nj = c->nrm + 3 * (size_t)j;
            double nn = (double)ni[0] * nj[0] + (double)ni[1] * nj[1] + (double)ni[2] * nj[2];
            w[e] = (float)(((double)og->A[e] + og->A[edge_of(g, j, (uint32_t)i)]) * (1.0 - nn));
        }
    return w;
}

double spr_wgc_cost(const spr_overlap_graph *og, const float *w, const int32_t *label)
{
    const spr_graph *g = &og->g;
    double L = 0.0;
    for (size_t i = 0; i < g->n; i++)
        for (uint64_t e = g->start[i]; e < g->start[i + 1]; e++)
            if (g->adj[e] > i && label[i] == label[g->adj[e]]) L += w[e];
    return L;
}

int spr_minimize_overlap(const spr_overlap_graph *og, size_t v, const int32_t *label, int K)
{
    double sum[SPR_MAX_GROUPS];
    for (int k = 0; k < K; k++) sum[k] = 0.0;
    for (uint64_t e = og->g.start[v]; e < og->g.start[v + 1]; e++) {
        int32_t l = label[og->g.adj[e]];
        if (l >= 0) sum[l] += og->A[e];
    }
    int best = 0;
    for (int k = 1; k < K; k++)
        if (sum[k] < sum[best]) best = k;
    return best;
}

/* Σ w over neighbours that would share colour k with v. */
static double same_sum(const spr_overlap_graph *og, const float *w, size_t v, const int32_t *label, int k)
{
    double s = 0.0;
    for (uint64_t e = og->g.start[v]; e < og->g.start[v + 1]; e++)
        if (label[og->g.adj[e]] == k) s += w[e];
    return s;
}

typedef struct edge_rec { float w; uint32_t i, j; } edge_rec;
static int by_weight(const void *a, const void *b)
{
    const edge_rec *x = a, *y = b;
    if (x->w != y->w) return x->w < y->w ? 1 : -1;
    if (x->i != y->i) return x->i < y->i ? -1 : 1;
    return (x->j > y->j) - (x->j < y->j);
}

void spr_wgc_defaults(spr_wgc_desc *d)
{
    memset(d, 0, sizeof *d);
    d->K = 8;
}

spr_result spr_group_wgc(const spr_cloud *c, const spr_wgc_desc *din, int32_t *label, spr_group_stats *st, spr_error *err)
{
    spr_wgc_desc d = *din;
    if (d.K < 1 || d.K > SPR_MAX_GROUPS) return spr__fail(err, SPR_E_ARG, "wgc: --k %d outside 1..%d", d.K, SPR_MAX_GROUPS);
    if (!(d.eps > 0.0)) d.eps = spr_cloud_default_eps(c);
    if (!d.max_pops) d.max_pops = 10 * c->n;
    memset(st, 0, sizeof *st);
    double t0 = spr_now_ms();
    spr_overlap_graph og;
    spr_result r = spr_overlap_graph_build(c, d.eps, d.threads, &d.progress, &og, err);
    if (r) return r;
    const spr_graph *g = &og.g;
    float *w = spr_wgc_weights(c, &og);
    uint32_t *ver = calloc(c->n, sizeof *ver);
    size_t ne = 0;
    for (size_t i = 0; i < c->n; i++)
        for (uint64_t e = g->start[i]; e < g->start[i + 1]; e++) ne += g->adj[e] > i;
    edge_rec *edges = malloc((ne ? ne : 1) * sizeof *edges);
    spr__heap h = {.max = 1}; /* by S(v) descending, ties: smaller v */
    if (!w || !ver || !edges) { r = spr__fail(err, SPR_E_NOMEM, "wgc: out of memory"); goto done; }
    st->ms_graph = spr_now_ms() - t0;
    t0 = spr_now_ms();
    /* 1. initialisation in edge-weight order */
    size_t k = 0;
    for (size_t i = 0; i < c->n; i++)
        for (uint64_t e = g->start[i]; e < g->start[i + 1]; e++)
            if (g->adj[e] > i) edges[k++] = (edge_rec){w[e], (uint32_t)i, g->adj[e]};
    spr_progress_report(&d.progress, "sorting edges", 0, 1);
    qsort(edges, ne, sizeof *edges, by_weight); /* total order: no ties left */
    for (size_t i = 0; i < c->n; i++) label[i] = -1;
    for (size_t e = 0; e < ne; e++) {
        if ((e & 0xFFFFF) == 0) spr_progress_report(&d.progress, "colouring", e, ne);
        if (label[edges[e].j] < 0) label[edges[e].j] = spr_minimize_overlap(&og, edges[e].j, label, d.K);
        if (label[edges[e].i] < 0) label[edges[e].i] = spr_minimize_overlap(&og, edges[e].i, label, d.K);
    }
    for (size_t i = 0; i < c->n; i++)
        if (label[i] < 0) label[i] = (int32_t)(i % (size_t)d.K);
    spr_progress_report(&d.progress, "colouring", ne, ne);
    st->cost_before = spr_wgc_cost(&og, w, label);
    st->ms_color = spr_now_ms() - t0;
    t0 = spr_now_ms();
    /* 2. optimisation */
    for (size_t v = 0; v < c->n; v++) {
        double s = same_sum(&og, w, v, label, label[v]);
        if (s > 0.0 && s >= d.tau_w && spr__heap_push(&h, (spr__heap_item){s, (uint32_t)v, 0})) { r = spr__fail(err, SPR_E_NOMEM, "wgc: out of memory"); goto done; }
    }
    while (h.n && st->pops < d.max_pops) {
        spr__heap_item it = spr__heap_pop(&h);
        if (it.ver != ver[it.id]) continue; /* superseded entry */
        st->pops++;
        if ((st->pops & 0xFFFF) == 0) spr_progress_report(&d.progress, "optimisation", st->pops, d.max_pops);
        size_t v = it.id;
        int best = spr_minimize_overlap(&og, v, label, d.K);
        double s_old = same_sum(&og, w, v, label, label[v]), s_new = same_sum(&og, w, v, label, best);
        ver[v]++;
        if (best == label[v] || s_new > s_old) continue; /* nothing better: out of the queue */
        label[v] = best;
        if (s_new > 0.0 && s_new >= d.tau_w) spr__heap_push(&h, (spr__heap_item){s_new, (uint32_t)v, ver[v]});
        for (uint64_t e = g->start[v]; e < g->start[v + 1]; e++) { /* the neighbours' sums changed */
            uint32_t u = g->adj[e];
            double su = same_sum(&og, w, u, label, label[u]);
            ver[u]++;
            if (su > 0.0 && su >= d.tau_w && spr__heap_push(&h, (spr__heap_item){su, u, ver[u]})) { r = spr__fail(err, SPR_E_NOMEM, "wgc: out of memory"); goto done; }
        }
    }
    spr_progress_report(&d.progress, "optimisation", d.max_pops, d.max_pops);
    st->cost_after = spr_wgc_cost(&og, w, label);
    st->ms_optimise = spr_now_ms() - t0;
    st->K = d.K;
    st->edges = ne;
    for (size_t i = 0; i < c->n; i++) {
        int deg = (int)(g->start[i + 1] - g->start[i]);
        if (deg > st->max_degree) st->max_degree = deg;
    }
    st->avg_degree = c->n ? 2.0 * (double)ne / (double)c->n : 0.0;
done:
    spr__heap_free(&h);
    free(edges);
    free(ver);
    free(w);
    if (!r && d.graph_out) *d.graph_out = og; /* handed over for the caller's metrics */
    else spr_overlap_graph_free(&og);
    return r;
}

double spr_overlap_factor(const spr_cloud *c, const spr_graph *g, const int32_t *label)
{
    double total = 0.0;
    for (size_t i = 0; i < c->n; i++) {
        double f = 0.0;
        for (uint64_t e = g->start[i]; e < g->start[i + 1]; e++) {
            size_t k = g->adj[e];
            if (label[k] != label[i]) continue;
            double d2 = 0.0;
            for (int a = 0; a < 3; a++) {
                double q = (double)c->pos[3 * i + a] - c->pos[3 * k + a];
                d2 += q * q;
            }
            double over = (double)c->radius[i] + c->radius[k] - sqrt(d2);
            if (over > 0.0) f += over / c->radius[i];
        }
        total += f;
    }
    return c->n ? total / (double)c->n : 0.0;
}
