/* decompose.c — local analysis (SPEC §7.1) and the multi-scale soft
 * decomposition (§7.2), our own aggregation multigrid:
 *
 *   level graph 0: the symmetric kNN graph of the points, coupling
 *       M_jk = |n_j·n_k|^power / (δ + max(σ_j, σ_k)) (SPEC's example with a
 *       normal term: σ alone cannot tell the two sides of a crease apart,
 *       their points have the same variation), and the count of fine edges (1)
 *   coarsening, level graph t → t+1 (fine to coarse):
 *       τ = strong × the mean fine coupling; an edge (aggregate pair) is
 *       strong when its mean fine coupling (Σ M / count) ≥ τ.  Strong edges,
 *       strongest first (ties: larger Σ M, then lower indices), pair up
 *       unmatched nodes; a node left over joins the aggregate of its strongest
 *       strong neighbour.  A level with no strong edge halves τ first, so
 *       weak edges (across ridges) are crossed only once nothing else is left.
 *       Aggregates are numbered by their lowest node.
 *   prolongation P_t (m × m'), smoothed aggregation with the strong edges:
 *       P[j, agg(j)] += 1 − ω,  P[j, agg(k)] += ω·M_jk / Σ_k M_jk
 *       — entries ≥ 0, rows summing to 1.
 *   basis of the level after t coarsenings: B_t = P_1·P_2·…·P_t (rows sum to
 *       1, so the basis functions form a partition of unity at every point);
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
} lgraph;

static void lgraph_free(lgraph *g)
{
    free(g->ptr);
    free(g->col);
    free(g->w);
    free(g->e);
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

typedef struct cand { double key, w; uint32_t j, k; } cand;
static int strongest_first(const void *x, const void *y)
{
    const cand *p = x, *q = y;
    if (p->key != q->key) return p->key > q->key ? -1 : 1;
    if (p->w != q->w) return p->w > q->w ? -1 : 1;
    if (p->j != q->j) return p->j < q->j ? -1 : 1;
    return (p->k > q->k) - (p->k < q->k);
}

/* One coarsening: agg[j] for the m nodes, the count m' returned (m when no
 * strong edge pairs anything).  An edge pairs or joins only when it is also
 * strong relative to both ends (key ≥ rel × each end's strongest key, as
 * classical AMG's strength of connection), so a node on a ridge waits for
 * its own side instead of pairing across. */
static size_t aggregate(const lgraph *g, double tau, double rel, uint32_t *agg, cand *cs)
{
    double *best = calloc(g->m ? g->m : 1, sizeof *best);
    if (!best) return 0;
    for (size_t j = 0; j < g->m; j++)
        for (size_t p = g->ptr[j]; p < g->ptr[j + 1]; p++)
            if (g->w[p] / g->e[p] > best[j]) best[j] = g->w[p] / g->e[p];
    size_t nc = 0;
    for (size_t j = 0; j < g->m; j++)
        for (size_t p = g->ptr[j]; p < g->ptr[j + 1]; p++) {
            const uint32_t k = g->col[p];
            const double key = g->w[p] / g->e[p];
            if (k > j && key >= tau && key >= rel * best[j] && key >= rel * best[k]) cs[nc++] = (cand){key, g->w[p], (uint32_t)j, k};
        }
    qsort(cs, nc, sizeof *cs, strongest_first);
    const uint32_t none = UINT32_MAX;
    for (size_t j = 0; j < g->m; j++) agg[j] = none;
    uint32_t *mate = malloc((g->m ? g->m : 1) * sizeof *mate);
    if (!mate) { free(best); return 0; }
    for (size_t j = 0; j < g->m; j++) mate[j] = none;
    for (size_t x = 0; x < nc; x++)
        if (mate[cs[x].j] == none && mate[cs[x].k] == none) mate[cs[x].j] = cs[x].k, mate[cs[x].k] = cs[x].j;
    /* leftovers join their strongest strong neighbour that has a mate */
    uint32_t *join = malloc((g->m ? g->m : 1) * sizeof *join);
    if (!join) { free(mate); free(best); return 0; }
    for (size_t j = 0; j < g->m; j++) {
        join[j] = none;
        if (mate[j] != none) continue;
        double bk = -1.0;
        for (size_t p = g->ptr[j]; p < g->ptr[j + 1]; p++) {
            const uint32_t k = g->col[p];
            const double key = g->w[p] / g->e[p];
            if (key >= tau && key >= rel * best[j] && mate[k] != none && key > bk) bk = key, join[j] = k;
        }
    }
    /* number aggregates by their lowest node: scan nodes in order */
    size_t m2 = 0;
    for (size_t j = 0; j < g->m; j++) {
        if (agg[j] != none) continue;
        if (mate[j] != none) {
            agg[j] = agg[mate[j]] = (uint32_t)m2++;
        } else if (join[j] == none) {
            agg[j] = (uint32_t)m2++;
        }
    }
    for (size_t j = 0; j < g->m; j++)
        if (agg[j] == none) agg[j] = agg[join[j]]; /* the node joined has its number now */
    free(mate);
    free(join);
    free(best);
    return m2;
}

/* P (m × m2): (1 − ω) at agg(j), ω·M_jk/Σ M over j's strong edges at agg(k). */
static int prolongation(const lgraph *g, const uint32_t *agg, size_t m2, double tau, double omega, spr_csr *P)
{
    memset(P, 0, sizeof *P);
    P->rows = g->m;
    P->cols = m2;
    size_t cap = g->ptr[g->m] + g->m;
    P->ptr = malloc((g->m + 1) * sizeof *P->ptr);
    P->col = malloc((cap ? cap : 1) * sizeof *P->col);
    P->val = malloc((cap ? cap : 1) * sizeof *P->val);
    if (!P->ptr || !P->col || !P->val) return -1;
    size_t o = 0;
    P->ptr[0] = 0;
    for (size_t j = 0; j < g->m; j++) {
        double D = 0.0;
        for (size_t p = g->ptr[j]; p < g->ptr[j + 1]; p++)
            if (g->w[p] / g->e[p] >= tau) D += g->w[p];
        const size_t row0 = o;
        P->col[o] = agg[j];
        P->val[o++] = D > 0.0 ? 1.0 - omega : 1.0;
        for (size_t p = g->ptr[j]; D > 0.0 && p < g->ptr[j + 1]; p++) {
            if (!(g->w[p] / g->e[p] >= tau)) continue;
            const uint32_t a = agg[g->col[p]];
            const double v = omega * g->w[p] / D;
            size_t x = row0;
            while (x < o && P->col[x] != a) x++;
            if (x < o) P->val[x] += v;
            else P->col[o] = a, P->val[o++] = v;
        }
        for (size_t x = row0 + 1; x < o; x++) { /* ascending columns */
            uint32_t c = P->col[x];
            double v = P->val[x];
            size_t y = x;
            while (y > row0 && P->col[y - 1] > c) P->col[y] = P->col[y - 1], P->val[y] = P->val[y - 1], y--;
            P->col[y] = c, P->val[y] = v;
        }
        P->ptr[j + 1] = o;
    }
    return 0;
}

void spr_decomp_defaults(spr_decomp_desc *d)
{
    memset(d, 0, sizeof *d);
    d->k = 10;
    d->delta = 0.01;
    d->strong = 0.5;
    d->relative = 0.8;
    d->normal_power = 4.0;
    d->omega = 0.5;
    d->drop = 1e-4;
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
    if (!(d.delta > 0.0) || !(d.omega >= 0.0 && d.omega < 1.0) || !(d.strong > 0.0) || !(d.drop >= 0.0 && d.drop < 1.0))
        return spr__fail(err, SPR_E_ARG, "decomposition: delta > 0, 0 <= omega < 1, strong > 0, 0 <= drop < 1 (%g %g %g %g)", d.delta,
                         d.omega, d.strong, d.drop);
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
        if (lgraph_from(t, nt, n, &g)) r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory");
        for (size_t p = 0; !r && p < g.ptr[n]; p++) {
            double dup = g.e[p]; /* 2 when both found each other */
            g.w[p] /= dup;
            g.e[p] = 1.0;
            msum += g.w[p];
        }
    }
    free(t);
    double tau = g.ptr && g.ptr[n] ? d.strong * msum / (double)g.ptr[n] : 0.0;
    spr_csr B = {0}; /* basis of the current level, n × m (owned by out once kept) */
    size_t cap = 0, B_regions = 0, last_kept = 0;
    int B_kept = 0;
    while (!r && g.m > d.min_regions) {
        uint32_t *agg = malloc((g.m ? g.m : 1) * sizeof *agg);
        cand *cs = malloc((g.ptr[g.m] / 2 + 1) * sizeof *cs);
        if (!agg || !cs) { free(agg); free(cs); r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory"); break; }
        size_t m2 = g.m;
        int any_edge = g.ptr[g.m] > 0, lowered = 0;
        while (any_edge) {
            m2 = aggregate(&g, tau, d.relative, agg, cs);
            if (m2 == 0) break; /* out of memory */
            if (m2 < g.m) break;
            tau *= 0.5; /* nothing strong left at this τ: the next weaker edges */
            lowered = 1;
            if (tau < 1e-300) { any_edge = 0; break; }
        }
        free(cs);
        if (m2 == 0) { free(agg); r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory"); break; }
        if (!any_edge || m2 >= g.m || m2 < d.min_regions) { free(agg); break; }
        spr_csr P;
        if (prolongation(&g, agg, m2, tau, d.omega, &P)) { spr_csr_free(&P); free(agg); r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory"); break; }
        /* the coarse graph */
        triple *ct = malloc((g.ptr[g.m] ? g.ptr[g.m] : 1) * sizeof *ct);
        size_t nct = 0;
        lgraph g2 = {0};
        if (ct) {
            for (size_t j = 0; j < g.m; j++)
                for (size_t p = g.ptr[j]; p < g.ptr[j + 1]; p++)
                    if (agg[j] != agg[g.col[p]]) ct[nct++] = (triple){agg[j], agg[g.col[p]], g.w[p], g.e[p]};
        }
        if (!ct || lgraph_from(ct, nct, m2, &g2)) {
            free(ct);
            free(agg);
            spr_csr_free(&P);
            r = spr__fail(err, SPR_E_NOMEM, "decomposition: out of memory");
            break;
        }
        free(ct);
        free(agg);
        lgraph_free(&g);
        g = g2;
        /* the basis of the new level */
        spr_csr NB;
        if (!B.ptr) NB = P;
        else if ((r = spr_csr_mul(&B, &P, d.drop, &NB, err))) { spr_csr_free(&P); break; }
        if (B.ptr) spr_csr_free(&P);
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
