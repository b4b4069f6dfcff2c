/* decompose.c — local analysis (SPEC §7.1) and the multi-scale soft
 * decomposition (§7.2), our own aggregation multigrid:
 *
 *   level graph 0: the symmetric kNN graph of the points, coupling
 *       M_jk = |n_j·n_k|^power / (δ + max(σ_j, σ_k)) (SPEC's example with a
 *       normal term: σ alone cannot tell the two sides of a crease apart,
 *       their points have the same variation), and the count of fine edges (1)
 *   coarsening, level graph t → t+1 (fine to coarse):
 *       τ = strong × the mean fine coupling; an edge (aggregate pair) is
 *       strong when its mean fine coupling (Σ M / count) ≥ τ and at least
 *       `relative` × the strongest edge of the node choosing.  Nodes, smallest
 *       first, pair with their strongest unmatched strong neighbour; a node
 *       left over stays alone for this level, so aggregates at most double
 *       and none snowballs.  A level with no strong
 *       edge halves τ first, so weak edges (across creases) are crossed only
 *       once nothing else is left.  Aggregates are numbered by their lowest
 *       node.
 *   prolongation P̂_t (m × m'): the tentative, hard one (1 at agg(j)).
 *   basis of the level after t coarsenings: Φ_t = S^q·P̂_1·…·P̂_t with the
 *       smoothing S = (1 − ω)·I + ω·D⁻¹·M on the point graph (q = `smooth`
 *       steps): the regions' hard aggregation made fuzzy in a band of a few
 *       point spacings, weak across creases because M is; S ≥ 0 with rows
 *       summing to 1 and P̂ one-hot, so Φ_t ≥ 0 and every row sums to 1 —
 *       a partition of unity at every point.  (Smoothing every P_t on its
 *       own level instead spreads a coarse region over all its neighbours.)
 *       [R]'s numbering puts the coarsest level at 0.
 */
#include "spr_domain.h"
#include "spr_knn.h"
#include "spr_pca.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void spr_local_free(spr_local *l)
{
    free(l->nb);
    free(l->normal);
    free(l->sigma);
    memset(l, 0, sizeof *l);
}

spr_result spr_local_analysis(const spr_cloud *c, int k, int threads, const spr_progress *prog, spr_local *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    if (c->n < 4) return spr__fail(err, SPR_E_VALUE, "local analysis: %zu points are too few", c->n);
    if (k < 3) return spr__fail(err, SPR_E_ARG, "local analysis: k = %d, at least 3", k);
    if ((size_t)k >= c->n) k = (int)c->n - 1;
    out->n = c->n;
    out->k = k;
    out->nb = malloc(c->n * (size_t)k * sizeof *out->nb);
    out->normal = malloc(c->n * 3 * sizeof *out->normal);
    out->sigma = malloc(c->n * sizeof *out->sigma);
    double *dist = malloc(c->n * (size_t)k * sizeof *dist);
    spr_knn *kn = NULL;
    spr_result r = SPR_OK;
    if (!out->nb || !out->normal || !out->sigma || !dist) r = spr__fail(err, SPR_E_NOMEM, "local analysis: out of memory");
    if (!r) r = spr_knn_build(c->pos, c->n, &kn, err);
    if (!r) r = spr_knn_query_all(kn, k, threads, out->nb, dist, prog, err);
    spr_knn_free(kn);
    free(dist);
    if (r) { spr_local_free(out); return r; }
#pragma omp parallel for num_threads(threads > 0 ? threads : 1) schedule(static)
    for (size_t i = 0; i < c->n; i++) {
        double ev[3], evec[9];
        spr_pca_local(c->pos, i, out->nb + i * (size_t)k, k, ev, evec);
        double s = ev[0] + ev[1] + ev[2];
        out->sigma[i] = s > 0.0 ? (ev[0] > 0.0 ? ev[0] : 0.0) / s : 0.0;
        for (int d = 0; d < 3; d++) out->normal[3 * i + d] = (float)evec[d];
    }
    return SPR_OK;
}

/* A level graph: symmetric, no diagonal; w = Σ of fine couplings, e = their count. */
typedef struct lgraph {
    size_t m;
    size_t *ptr;
    uint32_t *col;
    double *w, *e;
    double *size;  /* fine points in each node */
} lgraph;

static void lgraph_free(lgraph *g)
{
    free(g->ptr);
    free(g->col);
    free(g->w);
    free(g->e);
    free(g->size);
    memset(g, 0, sizeof *g);
}

typedef struct triple { uint32_t a, b; double w, e; } triple;
static int by_ab(const void *x, const void *y)
{
    const triple *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    return (p->b > q->b) - (p->b < q->b);
}

/* A graph from triples (sorted here, duplicates summed). */
static int lgraph_from(triple *t, size_t nt, size_t m, lgraph *g)
{
    qsort(t, nt, sizeof *t, by_ab);
    memset(g, 0, sizeof *g);
    g->m = m;
    g->ptr = calloc(m + 1, sizeof *g->ptr);
    g->col = malloc((nt ? nt : 1) * sizeof *g->col);
    g->w = malloc((nt ? nt : 1) * sizeof *g->w);
    g->e = malloc((nt ? nt : 1) * sizeof *g->e);
    if (!g->ptr || !g->col || !g->w || !g->e) { lgraph_free(g); return -1; }
    size_t o = 0;
    for (size_t x = 0; x < nt; x++) {
        if (o > 0 && g->col[o - 1] == t[x].b && x > 0 && t[x - 1].a == t[x].a) {
            g->w[o - 1] += t[x].w;
            g->e[o - 1] += t[x].e;
            continue;
        }
        g->col[o] = t[x].b;
        g->w[o] = t[x].w;
        g->e[o] = t[x].e;
        o++;
        g->ptr[t[x].a + 1]++;
    }
    for (size_t j = 0; j < m; j++) g->ptr[j + 1] += g->ptr[j];
    return 0;
}

/* One coarsening: agg[j] for the m nodes, the count m' returned (m when no
 * strong edge pairs anything).  Nodes take their turn smallest first (ties:
 * lower index) and pair with their strongest unmatched neighbour over a
 * strong edge — one that is also strong relative to the node's own
 * strongest (key ≥ rel × it, as classical AMG's strength of connection), so
 * a node on a crease waits for its own side instead of pairing across.
 * (Asking it of both ends lets large aggregates refuse small neighbours and
 * pair only with each other: one region then swallows the model.)
 * Small aggregates pair first, so sizes stay balanced and none snowballs. */
typedef struct node_ord { double size; uint32_t j; } node_ord;
static int smallest_first(const void *x, const void *y)
{
    const node_ord *p = x, *q = y;
    if (p->size != q->size) return p->size < q->size ? -1 : 1;
    return (p->j > q->j) - (p->j < q->j);
}

static size_t aggregate(const lgraph *g, double tau, double rel, uint32_t *agg)
{
    const uint32_t none = UINT32_MAX;
    double *best = calloc(g->m ? g->m : 1, sizeof *best);
    uint32_t *mate = malloc((g->m ? g->m : 1) * sizeof *mate);
    node_ord *ord = malloc((g->m ? g->m : 1) * sizeof *ord);
    if (!best || !mate || !ord) { free(best); free(mate); free(ord); return 0; }
    for (size_t j = 0; j < g->m; j++) {
        mate[j] = none;
        ord[j] = (node_ord){g->size[j], (uint32_t)j};
        for (size_t p = g->ptr[j]; p < g->ptr[j + 1]; p++)
            if (g->w[p] / g->e[p] > best[j]) best[j] = g->w[p] / g->e[p];
    }
    qsort(ord, g->m, sizeof *ord, smallest_first);
    for (size_t o = 0; o < g->m; o++) {
        const uint32_t j = ord[o].j;
        if (mate[j] != none) continue;
        uint32_t pick = none;
        double bk = -1.0;
        for (size_t p = g->ptr[j]; p < g->ptr[j + 1]; p++) {
            const uint32_t k = g->col[p];
            const double key = g->w[p] / g->e[p];
            if (mate[k] != none || key < tau || key < rel * best[j]) continue;
            if (key > bk) bk = key, pick = k; /* ascending columns: ties keep the lower index */
        }
        if (pick != none) mate[j] = pick, mate[pick] = j;
    }
    /* pairs only: aggregates at most double per level; a node left unmatched
     * stays on its own and pairs at a later level */
    size_t m2 = 0;
    for (size_t j = 0; j < g->m; j++) {
        if (mate[j] != none && mate[j] < j) { agg[j] = agg[mate[j]]; continue; }
        agg[j] = (uint32_t)m2++;
    }
    free(best);
    free(mate);
    free(ord);
    return m2;
}

/* S (n × n) = (1 − ω)·I + ω·D⁻¹·M over the point graph g (level 0). */
static int smoothing_operator(const lgraph *g, double omega, spr_csr *S)
{
    memset(S, 0, sizeof *S);
    const size_t nnz = g->ptr[g->m] + g->m;
    S->rows = S->cols = g->m;
    S->ptr = malloc((g->m + 1) * sizeof *S->ptr);
    S->col = malloc((nnz ? nnz : 1) * sizeof *S->col);
    S->val = malloc((nnz ? nnz : 1) * sizeof *S->val);
    if (!S->ptr || !S->col || !S->val) { spr_csr_free(S); return -1; }
    size_t o = 0;
    S->ptr[0] = 0;
    for (size_t j = 0; j < g->m; j++) {
        double D = 0.0;
        for (size_t p = g->ptr[j]; p < g->ptr[j + 1]; p++) D += g->w[p];
        int diag = 0;
        for (size_t p = g->ptr[j]; p <= g->ptr[j + 1]; p++) { /* ascending columns, the diagonal in its place */
            if (!diag && (p == g->ptr[j + 1] || g->col[p] > j)) {
                S->col[o] = (uint32_t)j;
                S->val[o++] = D > 0.0 ? 1.0 - omega : 1.0;
                diag = 1;
            }
            if (p < g->ptr[j + 1] && D > 0.0) S->col[o] = g->col[p], S->val[o++] = omega * g->w[p] / D;
        }
        S->ptr[j + 1] = o;
    }
    return 0;
}

/* The basis of a level: one-hot rows (point i in region map[i]) smoothed
 * `steps` times by S. */
static int smooth_basis(const spr_csr *S, const uint32_t *map, size_t n, size_t regions, int steps, spr_csr *B, spr_error *err)
{
    memset(B, 0, sizeof *B);
    B->rows = n;
    B->cols = regions;
    B->ptr = malloc((n + 1) * sizeof *B->ptr);
    B->col = malloc((n ? n : 1) * sizeof *B->col);
    B->val = malloc((n ? n : 1) * sizeof *B->val);
    if (!B->ptr || !B->col || !B->val) { spr_csr_free(B); spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory"); return -1; }
    for (size_t i = 0; i <= n; i++) B->ptr[i] = i;
    for (size_t i = 0; i < n; i++) B->col[i] = map[i], B->val[i] = 1.0;
    for (int s = 0; s < steps; s++) {
        spr_csr NB;
        if (spr_csr_mul(S, B, 0.0, &NB, err)) { spr_csr_free(B); return -1; }
        spr_csr_free(B);
        *B = NB;
    }
    return 0;
}

void spr_decomp_defaults(spr_decomp_desc *d)
{
    memset(d, 0, sizeof *d);
    d->k = 10;
    d->delta = 0.01;
    d->strong = 0.05;
    d->relative = 0.8;
    d->normal_power = 4.0;
    d->omega = 0.5;
    d->smooth = 3;
    d->min_regions = 2;
}

void spr_decomp_free(spr_decomp *d)
{
    for (int l = 0; l < d->levels; l++) spr_csr_free(&d->basis[l]);
    free(d->basis);
    free(d->regions);
    memset(d, 0, sizeof *d);
}

/* Append basis *B (ownership passes to out; *B stays readable). */
static spr_result keep_level(spr_decomp *out, size_t *cap, const spr_csr *B, size_t regions, spr_error *err)
{
    if ((size_t)out->levels == *cap) {
        size_t nc = *cap ? 2 * *cap : 8;
        spr_csr *nbs = realloc(out->basis, nc * sizeof *nbs);
        if (nbs) out->basis = nbs;
        size_t *nr = nbs ? realloc(out->regions, nc * sizeof *nr) : NULL;
        if (nr) out->regions = nr;
        if (!nbs || !nr) return spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory");
        *cap = nc;
    }
    out->basis[out->levels] = *B;
    out->regions[out->levels] = regions;
    out->levels++;
    return SPR_OK;
}

spr_result spr_decompose(const spr_cloud *c, const spr_decomp_desc *din, spr_decomp *out, spr_error *err)
{
    spr_decomp_desc d;
    if (din) d = *din; else spr_decomp_defaults(&d);
    memset(out, 0, sizeof *out);
    if (!(d.delta > 0.0) || !(d.omega >= 0.0 && d.omega < 1.0) || !(d.strong > 0.0) || !(d.relative >= 0.0 && d.relative <= 1.0))
        return spr__fail(err, SPR_E_ARG, "decomposition: delta > 0, 0 <= omega < 1, strong > 0, 0 <= relative <= 1 (%g %g %g %g)", d.delta,
                         d.omega, d.strong, d.relative);
    if (d.min_regions < 1) d.min_regions = 1;
    double t0 = spr_now_ms();
    spr_local la;
    spr_result r = spr_local_analysis(c, d.k, d.threads, &d.progress, &la, err);
    if (r) return r;
    out->ms_analysis = spr_now_ms() - t0;
    t0 = spr_now_ms();
    const size_t n = c->n, K = (size_t)la.k;
    /* level graph 0: the kNN graph made symmetric */
    triple *t = malloc(2 * n * K * sizeof *t);
    lgraph g = {0};
    r = SPR_OK;
    if (!t) r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory");
    size_t nt = 0;
    double msum = 0.0;
    for (size_t i = 0; !r && i < n; i++)
        for (size_t q = 0; q < K; q++) {
            uint32_t j = la.nb[i * K + q];
            if (j == UINT32_MAX || j == i) continue;
            double s = la.sigma[i] > la.sigma[j] ? la.sigma[i] : la.sigma[j], w = 1.0 / (d.delta + s);
            if (d.normal_power > 0.0) { /* weak across creases: |n_i·n_j|^power with the cloud's normals */
                const float *a = c->nrm + 3 * i, *b = c->nrm + 3 * (size_t)j;
                w *= pow(fabs((double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2]), d.normal_power);
            }
            t[nt++] = (triple){(uint32_t)i, j, w, 1.0};
            t[nt++] = (triple){j, (uint32_t)i, w, 1.0};
        }
    spr_local_free(&la);
    if (!r) {
        /* an edge found from both ends counts once: halve the duplicates when merging */
        if (lgraph_from(t, nt, n, &g) || !(g.size = malloc((n ? n : 1) * sizeof *g.size)))
            r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory");
        for (size_t i = 0; !r && i < n; i++) g.size[i] = 1.0;
        for (size_t p = 0; !r && p < g.ptr[n]; p++) {
            double dup = g.e[p]; /* 2 when both found each other */
            g.w[p] /= dup;
            g.e[p] = 1.0;
            msum += g.w[p];
        }
    }
    free(t);
    double tau = g.ptr && g.ptr[n] ? d.strong * msum / (double)g.ptr[n] : 0.0;
    /* S = (1 − ω)·I + ω·D⁻¹·M on the point graph: non-negative, rows sum to 1 */
    spr_csr S = {0};
    if (!r && smoothing_operator(&g, d.omega, &S)) r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory");
    spr_csr B = {0}; /* basis of the current level, n × m (owned by out once kept) */
    uint32_t *map = r ? NULL : malloc((n ? n : 1) * sizeof *map), *agg_map = NULL; /* point → node of the current level graph */
    if (!r && !map) r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory");
    for (size_t i = 0; !r && i < n; i++) map[i] = (uint32_t)i;
    size_t cap = 0, B_regions = 0, last_kept = 0;
    int B_kept = 0;
    while (!r && g.m > d.min_regions) {
        uint32_t *agg = malloc((g.m ? g.m : 1) * sizeof *agg);
        if (!agg) { r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory"); break; }
        size_t m2 = g.m;
        int any_edge = g.ptr[g.m] > 0, lowered = 0;
        while (any_edge) {
            m2 = aggregate(&g, tau, d.relative, agg);
            if (m2 == 0) break; /* out of memory */
            if (m2 < g.m) break;
            tau *= 0.5; /* nothing strong left at this τ: the next weaker edges */
            lowered = 1;
            if (tau < 1e-300) { any_edge = 0; break; }
        }
        if (m2 == 0) { free(agg); r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory"); break; }
        if (!any_edge || m2 >= g.m || m2 < d.min_regions) { free(agg); break; }
        /* the coarse graph */
        triple *ct = malloc((g.ptr[g.m] ? g.ptr[g.m] : 1) * sizeof *ct);
        size_t nct = 0;
        lgraph g2 = {0};
        if (ct) {
            for (size_t j = 0; j < g.m; j++)
                for (size_t p = g.ptr[j]; p < g.ptr[j + 1]; p++)
                    if (agg[j] != agg[g.col[p]]) ct[nct++] = (triple){agg[j], agg[g.col[p]], g.w[p], g.e[p]};
        }
        if (!ct || lgraph_from(ct, nct, m2, &g2) || !(g2.size = calloc(m2 ? m2 : 1, sizeof *g2.size))) {
            lgraph_free(&g2);
            free(ct);
            free(agg);
            r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory");
            break;
        }
        for (size_t j = 0; j < g.m; j++) g2.size[agg[j]] += g.size[j];
        free(ct);
        agg_map = agg; /* freed once the points are mapped below */
        lgraph_free(&g);
        g = g2;
        /* the basis of the new level: the hard aggregation of the points,
         * then `smooth` steps of S on the point graph (SPEC §7.2's smoothing
         * made at the finest scale, so neighbouring regions overlap in a
         * band of a few point spacings at every level) */
        for (size_t i = 0; i < n; i++) map[i] = agg_map[map[i]];
        free(agg_map);
        agg_map = NULL;
        spr_csr NB;
        if (smooth_basis(&S, map, n, m2, d.smooth, &NB, err)) { r = err->code ? err->code : SPR_E_NOMEM; break; }
        /* Levels kept: the one before a step that had to cross weaker edges
         * (everything strong was joined: faces between creases), and any
         * that has at most 0.7× the regions of the last kept one; the many
         * small steps of a strong phase in between are folded together. */
        if (B.ptr && !B_kept && lowered) {
            if ((r = keep_level(out, &cap, &B, B_regions, err))) { spr_csr_free(&NB); break; }
            B_kept = 1;
            last_kept = B_regions;
        }
        if (B.ptr && !B_kept) spr_csr_free(&B);
        B = NB;
        B_regions = m2;
        B_kept = 0;
        if (!last_kept || (double)m2 <= 0.7 * (double)last_kept) {
            if ((r = keep_level(out, &cap, &B, m2, err))) break;
            B_kept = 1;
            last_kept = m2;
        }
        spr_progress_report(&d.progress, "decomposition", n - m2, n);
    }
    if (!r && B.ptr && !B_kept) {
        if (!(r = keep_level(out, &cap, &B, B_regions, err))) B_kept = 1;
    }
    if (B.ptr && !B_kept) spr_csr_free(&B);
    free(map);
    free(agg_map);
    spr_csr_free(&S);
    lgraph_free(&g);
    out->n = n;
    out->ms_coarsen = spr_now_ms() - t0;
    if (r) { spr_decomp_free(out); return r; }
    /* coarsest first ([R]'s numbering) */
    for (int a = 0, b = out->levels - 1; a < b; a++, b--) {
        spr_csr tb = out->basis[a];
        out->basis[a] = out->basis[b];
        out->basis[b] = tb;
        size_t tr = out->regions[a];
        out->regions[a] = out->regions[b];
        out->regions[b] = tr;
    }
    return SPR_OK;
}
