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
#include "spr__group.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <omp.h>
#include <time.h>

float *spr_wgc_weights(const spr_cloud *c, const spr_overlap_graph *og)
{
    const spr_graph *g = &og->g;
    float *w = spr__big_alloc((g->start[c->n] ? g->start[c->n] : 1) * sizeof(float));
    uint64_t *cursor = spr__big_alloc((c->n ? c->n : 1) * sizeof *cursor);
    if (!w || !cursor) {
        free(w);
        free(cursor);
        return NULL;
    }
    /* The reverse edge (j, i) of every edge: rows are ascending and i is
     * visited in ascending order, so each row's entries are met in order and
     * a cursor per row finds them without a search. */
    memcpy(cursor, g->start, c->n * sizeof *cursor);
    for (size_t i = 0; i < c->n; i++)
        for (uint64_t e = g->start[i]; e < g->start[i + 1]; e++) {
            uint32_t j = g->adj[e];
            uint64_t back = cursor[j];
            while (back < g->start[j + 1] && g->adj[back] < (uint32_t)i) back++; /* none in a symmetric graph */
            const double a_back = back < g->start[j + 1] && g->adj[back] == (uint32_t)i ? og->A[back] : 0.0;
            cursor[j] = back + 1;
            const float *ni = c->nrm + 3 * i, *nj = c->nrm + 3 * (size_t)j;
            double nn = (double)ni[0] * nj[0] + (double)ni[1] * nj[1] + (double)ni[2] * nj[2];
            w[e] = (float)(((double)og->A[e] + a_back) * (1.0 - nn));
        }
    free(cursor);
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

/* A key whose unsigned order is w descending (−0 and +0 equal, as the
 * float comparison has them). */
static uint32_t desc_key(float w)
{
    if (w == 0.0f) w = 0.0f;
    uint32_t u;
    memcpy(&u, &w, 4);
    u = (u & 0x80000000u) ? ~u : u | 0x80000000u; /* ascending in w */
    return ~u;
}

/* Edges by w descending, ties by (i, j): they are made in (i, j) order, so a
 * stable sort by w alone gives it.  LSD radix sort on the 32-bit key in
 * digits of 11, 11 and 10 bits, every digit's histogram from one pass
 * first, a digit all keys share skipped (glibc's qsort with a comparison
 * callback took most of this phase; no Debian C library offers a radix
 * sort of records). */
static int sort_edges(edge_rec *e, size_t n)
{
    enum { DIGITS = 3 };
    static const int shift[DIGITS] = {0, 11, 22}, bits[DIGITS] = {11, 11, 10};
    size_t *count = calloc(DIGITS * 2049, sizeof *count);
    edge_rec *tmp = spr__big_alloc((n ? n : 1) * sizeof *tmp);
    if (!count || !tmp) { free(count); free(tmp); return -1; }
    for (size_t k = 0; k < n; k++) {
        const uint32_t key = desc_key(e[k].w);
        for (int d = 0; d < DIGITS; d++) count[d * 2049 + ((key >> shift[d]) & ((1u << bits[d]) - 1)) + 1]++;
    }
    edge_rec *src = e, *dst = tmp;
    for (int d = 0; d < DIGITS; d++) {
        size_t *c = count + d * 2049;
        const uint32_t mask = (1u << bits[d]) - 1;
        int shared = 0; /* every key in one bucket: the pass would not move anything */
        for (uint32_t b = 0; b <= mask && !shared; b++) shared = c[b + 1] == n;
        if (shared) continue;
        for (uint32_t b = 0; b < mask + 1; b++) c[b + 1] += c[b];
        for (size_t k = 0; k < n; k++) dst[c[(desc_key(src[k].w) >> shift[d]) & mask]++] = src[k];
        edge_rec *t = src;
        src = dst;
        dst = t;
    }
    if (src != e) memcpy(e, src, n * sizeof *e);
    free(tmp);
    free(count);
    return 0;
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
    float *w = NULL;
    spr_result r = spr__overlap_graph_weights(c, d.eps, d.threads, &d.progress, &og, &w, err);
    if (r) return r;
    const spr_graph *g = &og.g;
    uint32_t *ver = spr__big_calloc(c->n, sizeof *ver);
    size_t ne = 0;
    for (size_t i = 0; i < c->n; i++)
        for (uint64_t e = g->start[i]; e < g->start[i + 1]; e++) ne += g->adj[e] > i;
    edge_rec *edges = spr__big_alloc((ne ? ne : 1) * sizeof *edges);
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
    if (sort_edges(edges, ne)) { r = spr__fail(err, SPR_E_NOMEM, "wgc: out of memory"); goto done; } /* total order: no ties left */
    for (size_t i = 0; i < c->n; i++) label[i] = -1;
    for (size_t e = 0; e < ne; e++) {
        if ((e & 0xFFFFF) == 0) spr_progress_report(&d.progress, "colouring", e, ne);
        /* edges by weight visit the graph at random: hints, no arithmetic,
         * for the labels 16 edges ahead and the rows of the uncoloured
         * ends 8 ahead */
        if (e + 16 < ne) {
            __builtin_prefetch(label + edges[e + 16].i);
            __builtin_prefetch(label + edges[e + 16].j);
            __builtin_prefetch(g->start + edges[e + 16].i);
            __builtin_prefetch(g->start + edges[e + 16].j);
        }
        if (e + 8 < ne)
            for (int end = 0; end < 2; end++) {
                const uint32_t v = end ? edges[e + 8].i : edges[e + 8].j;
                if (label[v] < 0) {
                    __builtin_prefetch(g->adj + g->start[v]);
                    __builtin_prefetch(og.A + g->start[v]);
                }
            }
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
