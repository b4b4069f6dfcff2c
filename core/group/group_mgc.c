/* group_mgc.c — minimal graph colouring, largest-first ([ZP] §4.1, SPEC §5.1).
 *
 *   E = { (i,j) : |p_i − p_j| < c·(r_i + r_j)             (overlap, relaxation 3)
 *                 and not (n_i·n_j ≥ cos θ_c and coplanar) (relaxation 1)
 *                 and not (n_i·n_j < 0) }                  (relaxation 2)
 *   order vertices by degree, descending (ties: index)
 *   colour(v) = smallest colour not used by an already coloured neighbour
 *
 * [decision] relaxation 1 is asymmetric in SPEC (|(p_j − p_i)·n_i| ≤ τ·r_i);
 * we drop the edge only when it holds from both ends, so the graph stays
 * undirected and the relaxation never removes a visible overlap
 * (docs/grouping.md, "Where the code reads SPEC differently").
 */
#include "spr_util.h"
#include "spr_group.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void spr_mgc_defaults(spr_mgc_desc *d)
{
    memset(d, 0, sizeof *d);
    d->c = 1.0;
    d->relax_coplanar = 1;
    d->relax_opposite = 1;
    d->coplanar_deg = 5.0;
    d->coplanar_tau = 0.05;
}

static double dot3(const float *a, const float *b) { return (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2]; }

static int conflict_cos(const spr_cloud *c, const spr_mgc_desc *d, double cos_c, size_t i, size_t j);

int spr_mgc_conflict(const spr_cloud *c, const spr_mgc_desc *d, size_t i, size_t j)
{
    return conflict_cos(c, d, cos(d->coplanar_deg * M_PI / 180.0), i, j);
}

static int conflict_cos(const spr_cloud *c, const spr_mgc_desc *d, double cos_c, size_t i, size_t j)
{
    if (i == j) return 0;
    const float *pi = c->pos + 3 * i, *pj = c->pos + 3 * j, *ni = c->nrm + 3 * i, *nj = c->nrm + 3 * j;
    double q[3] = {(double)pj[0] - pi[0], (double)pj[1] - pi[1], (double)pj[2] - pi[2]};
    double dist = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    if (!(dist < d->c * ((double)c->radius[i] + (double)c->radius[j]))) return 0;
    double nn = dot3(ni, nj);
    if (d->relax_opposite && nn < 0.0) return 0;
    if (d->relax_coplanar && nn >= cos_c) {
        double hi = fabs(q[0] * ni[0] + q[1] * ni[1] + q[2] * ni[2]);
        double hj = fabs(q[0] * nj[0] + q[1] * nj[1] + q[2] * nj[2]);
        if (hi <= d->coplanar_tau * c->radius[i] && hj <= d->coplanar_tau * c->radius[j]) return 0;
    }
    return 1;
}

typedef struct mgc_keep { const spr_cloud *c; const spr_mgc_desc *d; double cos_c; } mgc_keep;
/* The conflict test is symmetric in i and j (each relaxation is). */
static int keep_conflict(const void *user, size_t i, size_t j)
{
    const mgc_keep *k = user;
    return conflict_cos(k->c, k->d, k->cos_c, i, j);
}

typedef struct { uint32_t deg, idx; } vdeg;
static int by_degree(const void *a, const void *b)
{
    const vdeg *x = a, *y = b;
    if (x->deg != y->deg) return x->deg < y->deg ? 1 : -1;
    return (x->idx > y->idx) - (x->idx < y->idx);
}

spr_result spr_group_mgc(const spr_cloud *c, const spr_mgc_desc *din, int32_t *label, spr_group_stats *st, spr_error *err)
{
    spr_mgc_desc d = *din;
    if (!(d.c >= 0.0 && d.c <= 1.0)) return spr__fail(err, SPR_E_ARG, "mgc: --c %g outside [0, 1]", d.c);
    memset(st, 0, sizeof *st);
    double t0 = spr_now_ms();
    spr_graph g; /* |p_i − p_j| < c·(r_i + r_j): relaxation 3 applied by the search */
    spr_result r = SPR_OK;
    const double cos_c = cos(d.coplanar_deg * M_PI / 180.0);
    mgc_keep mk = {c, &d, cos_c};
    if (d.c > 0.0) { /* relaxations 1 and 2 decided once per pair, inside the search */
        r = spr__pair_graph_keep(c, d.c, d.threads, &d.progress, keep_conflict, &mk, &g, err);
    } else { /* c = 0: no pair is closer than 0, so no edge (SPEC §5.1 allows c ∈ [0, 1]) */
        g.n = c->n;
        g.adj = NULL;
        if (!(g.start = calloc(c->n + 1, sizeof *g.start))) r = spr__fail(err, SPR_E_NOMEM, "mgc: out of memory");
    }
    if (r) return r;
    const uint64_t w = g.start[c->n];
    st->ms_graph = spr_now_ms() - t0;
    t0 = spr_now_ms();
    vdeg *order = malloc(c->n * sizeof *order);
    uint32_t *stamp = NULL;
    if (!order) { spr_graph_free(&g); return spr__fail(err, SPR_E_NOMEM, "mgc: out of memory"); }
    uint32_t maxdeg = 0;
    for (size_t i = 0; i < c->n; i++) {
        order[i].deg = (uint32_t)(g.start[i + 1] - g.start[i]);
        order[i].idx = (uint32_t)i;
        if (order[i].deg > maxdeg) maxdeg = order[i].deg;
    }
    qsort(order, c->n, sizeof *order, by_degree); /* total order: (degree desc, index asc) */
    stamp = calloc((size_t)maxdeg + 2, sizeof *stamp);
    if (!stamp) { free(order); spr_graph_free(&g); return spr__fail(err, SPR_E_NOMEM, "mgc: out of memory"); }
    for (size_t i = 0; i < c->n; i++) label[i] = -1;
    int K = 0;
    for (size_t o = 0; o < c->n; o++) {
        uint32_t v = order[o].idx;
        for (uint64_t k = g.start[v]; k < g.start[v + 1]; k++) {
            int32_t lc = label[g.adj[k]];
            if (lc >= 0 && (uint32_t)lc <= maxdeg) stamp[lc] = (uint32_t)o + 1;
        }
        int col = 0;
        while (stamp[col] == (uint32_t)o + 1) col++;
        label[v] = col;
        if (col + 1 > K) K = col + 1;
    }
    st->K = K;
    st->max_degree = (int)maxdeg;
    st->edges = (size_t)(w / 2);
    st->avg_degree = c->n ? (double)w / (double)c->n : 0.0;
    st->ms_color = spr_now_ms() - t0;
    free(stamp);
    free(order);
    spr_graph_free(&g);
    if (K > SPR_MAX_GROUPS) return spr__fail(err, SPR_E_TOO_LARGE, "mgc: %d colours needed (limit %d); lower --c", K, SPR_MAX_GROUPS);
    return SPR_OK;
}
