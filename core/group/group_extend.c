/* group_extend.c — extended grouping for surface coverage ([ZP] §4.4.2, SPEC §5.5).
 *
 * Duplication, per group k:
 *     Q = splats not in S_k keyed by Clipped(p_i, r_i, k), least first
 *     pop i: v = Clipped(p_i, r_i, k) now
 *            v/(π r_i²) > max_share → drop;  v == key → S_k += i;  else re-queue (v)
 * Radius enlargement, per group k (Eq. 13, radii scaled by a common factor):
 *     s_{t+1} = sqrt((A + Σ_{i∈S_k} Clipped(p_i, s_t r_i, k)) / Σ_{i∈S_k} π r_i²)
 *     with A = area covered by all splats (the union, Eq. 11), until
 *     |s_{t+1} − s_t| < 1e-3 s_t.
 * [decision] In Eq. 13 an overlap is counted once, by the lower-numbered of
 * the disks covering it, so that n·π·r̃² − Σ Clipped is the union of the
 * group — the estimator A uses for all splats.  Counted by every disk (the
 * literal reading), Σ Clipped approaches n·π·r̃² on densely overlapping
 * groups and the iteration has no fixed point.
 */
#include "spr_group.h"
#include "spr_overlap.h"
#include "spr_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void spr_extend_defaults(spr_extend_desc *d)
{
    memset(d, 0, sizeof *d);
    d->max_share = 0.5;
    d->max_scale = 3.0;
    d->max_iterations = 50;
}

/* Clipped(p_i, s·r_i, k): disk i covered by its neighbours flagged in_k
 * (only those numbered below i when `lower_only`: each overlap counted once). */
static double clipped_by(const spr_cloud *c, const spr_graph *g, size_t i, const unsigned char *in_k, double scale, double eps,
                         uint32_t *buf, int lower_only)
{
    size_t m = 0;
    for (uint64_t e = g->start[i]; e < g->start[i + 1]; e++)
        if (in_k[g->adj[e]] && (!lower_only || g->adj[e] < i)) buf[m++] = g->adj[e];
    return spr_clipped_area(c, i, scale, buf, m, scale, eps);
}

static size_t max_degree(const spr_graph *g)
{
    size_t m = 0;
    for (size_t i = 0; i < g->n; i++)
        if (g->start[i + 1] - g->start[i] > m) m = (size_t)(g->start[i + 1] - g->start[i]);
    return m;
}

spr_result spr_group_duplicate(const spr_cloud *c, const int32_t *label, int K, const spr_extend_desc *din, spr_groups *out,
                               double *dup_ratio, spr_error *err)
{
    spr_extend_desc d = *din;
    if (!(d.eps > 0.0)) d.eps = spr_cloud_default_eps(c);
    if (!(d.max_share > 0.0)) d.max_share = 0.5;
    memset(out, 0, sizeof *out);
    spr_graph g;
    spr_result r = spr__pair_graph(c, 1.0, d.threads, &d.progress, &g, err);
    if (r) return r;
    const size_t n = c->n;
    unsigned char *in_k = malloc(n);
    double *val = malloc(n * sizeof *val);
    size_t total = 0;
    uint32_t **lists = calloc((size_t)K, sizeof *lists);
    size_t *lens = calloc((size_t)K, sizeof *lens);
    size_t md = max_degree(&g) + 1;
    uint32_t *buf = malloc(md * sizeof *buf);
    spr__heap h = {.max = 0}; /* least covered first, ties: smaller index */
    if (!in_k || !val || !lists || !lens || !buf) { r = spr__fail(err, SPR_E_NOMEM, "duplication: out of memory"); goto done; }
    for (int k = 0; k < K && !r; k++) {
        spr_progress_report(&d.progress, "duplication", (size_t)k, (size_t)K);
        for (size_t i = 0; i < n; i++) in_k[i] = label[i] == k;
#pragma omp parallel num_threads(d.threads > 0 ? d.threads : 1)
        {
            uint32_t *tb = malloc(md * sizeof *tb);
#pragma omp for schedule(dynamic, 256)
            for (long i = 0; i < (long)n; i++)
                val[i] = in_k[i] || !tb ? -1.0 : clipped_by(c, &g, (size_t)i, in_k, 1.0, d.eps, tb, 0);
            free(tb);
        }
        h.n = 0;
        for (size_t i = 0; i < n; i++)
            if (!in_k[i] && spr__heap_push(&h, (spr__heap_item){val[i], (uint32_t)i, 0})) { r = spr__fail(err, SPR_E_NOMEM, "duplication: out of memory"); break; }
        while (h.n && !r) {
            spr__heap_item top = spr__heap_pop(&h);
            size_t i = top.id;
            double v = clipped_by(c, &g, i, in_k, 1.0, d.eps, buf, 0);
            double area = M_PI * (double)c->radius[i] * c->radius[i];
            if (v > d.max_share * area) continue;    /* already covered enough */
            if (v == top.key) in_k[i] = 2;             /* the value held: duplicate into S_k */
            else if (spr__heap_push(&h, (spr__heap_item){v, (uint32_t)i, 0})) r = spr__fail(err, SPR_E_NOMEM, "duplication: out of memory");
        }
        size_t m = 0;
        for (size_t i = 0; i < n; i++) m += in_k[i] != 0;
        lists[k] = malloc((m ? m : 1) * sizeof(uint32_t));
        if (!lists[k]) { r = spr__fail(err, SPR_E_NOMEM, "duplication: out of memory"); break; }
        for (size_t i = 0; i < n; i++)
            if (in_k[i]) lists[k][lens[k]++] = (uint32_t)i;
        total += lens[k];
    }
    spr_progress_report(&d.progress, "duplication", (size_t)K, (size_t)K);
    if (!r) {
        out->start = malloc(((size_t)K + 1) * sizeof(uint32_t));
        out->members = malloc((total ? total : 1) * sizeof(uint32_t));
        if (!out->start || !out->members) { r = spr__fail(err, SPR_E_NOMEM, "duplication: out of memory"); spr_groups_free(out); }
        else {
            size_t o = 0;
            for (int k = 0; k < K; k++) {
                out->start[k] = (uint32_t)o;
                memcpy(out->members + o, lists[k], lens[k] * sizeof(uint32_t));
                o += lens[k];
            }
            out->start[K] = (uint32_t)o;
            out->K = K;
            out->n_splats = n;
            *dup_ratio = n ? (double)(total - n) / (double)n : 0.0;
        }
    }
done:
    for (int k = 0; lists && k < K; k++) free(lists[k]);
    free(lists);
    free(lens);
    spr__heap_free(&h);
    free(buf);
    free(val);
    free(in_k);
    spr_graph_free(&g);
    return r;
}

/* Union area of all splats (Eq. 11): each disk counts what no lower-numbered
 * neighbour covers. */
static double union_area(const spr_cloud *c, const spr_graph *g, double eps, uint32_t *buf)
{
    double A = 0.0;
    for (size_t i = 0; i < c->n; i++) {
        size_t m = 0;
        for (uint64_t e = g->start[i]; e < g->start[i + 1]; e++)
            if (g->adj[e] < i) buf[m++] = g->adj[e];
        double ri = c->radius[i];
        A += M_PI * ri * ri - spr_clipped_area(c, i, 1.0, buf, m, 1.0, eps);
    }
    return A;
}

spr_result spr_group_enlarge(const spr_cloud *c, spr_groups *grp, const spr_extend_desc *din, int *capped, spr_error *err)
{
    spr_extend_desc d = *din;
    if (!(d.eps > 0.0)) d.eps = spr_cloud_default_eps(c);
    if (!(d.max_scale >= 1.0) || d.max_iterations < 1)
        return spr__fail(err, SPR_E_ARG, "enlarge: max scale %g or %d iterations out of range", d.max_scale, d.max_iterations);
    if (capped) *capped = 0;
    const double F = d.max_scale; /* the neighbour search covers every pair that can overlap up to this scale */
    spr_graph gw;
    spr_result r = spr__pair_graph(c, F, d.threads, &d.progress, &gw, err);
    if (r) return r;
    size_t md = max_degree(&gw) + 1;
    unsigned char *in_k = calloc(c->n ? c->n : 1, 1);
    uint32_t *buf = malloc(md * sizeof *buf);
    double *clip = malloc((c->n ? c->n : 1) * sizeof *clip);
    free(grp->radius_scale);
    grp->radius_scale = malloc((size_t)grp->K * sizeof(float));
    if (!in_k || !buf || !clip || !grp->radius_scale) {
        free(in_k);
        free(buf);
        free(clip);
        spr_graph_free(&gw);
        return spr__fail(err, SPR_E_NOMEM, "enlarge: out of memory");
    }
    /* the wider graph holds every overlapping pair (and some that cannot cover) */
    double A = union_area(c, &gw, d.eps, buf);
    for (int k = 0; k < grp->K; k++) {
        spr_progress_report(&d.progress, "radius enlargement", (size_t)k, (size_t)grp->K);
        memset(in_k, 0, c->n);
        double disk_sum = 0.0;
        const long nm = (long)(grp->start[k + 1] - grp->start[k]);
        const uint32_t *S_k = grp->members + grp->start[k];
        for (long m = 0; m < nm; m++) {
            in_k[S_k[m]] = 1;
            disk_sum += M_PI * (double)c->radius[S_k[m]] * c->radius[S_k[m]];
        }
        double s = 1.0;
        int converged = disk_sum == 0.0;
        for (int it = 0; it < d.max_iterations && !converged; it++) {
#pragma omp parallel num_threads(d.threads > 0 ? d.threads : 1)
            {
                uint32_t *tb = malloc(md * sizeof *tb);
#pragma omp for schedule(static)
                for (long m = 0; m < nm; m++) clip[m] = tb ? clipped_by(c, &gw, S_k[m], in_k, s, d.eps, tb, 1) : 0.0;
                free(tb);
            }
            double sum = 0.0; /* in member order: the same bits for any thread count */
            for (long m = 0; m < nm; m++) sum += clip[m];
            double next = sqrt((A + sum) / disk_sum);
            if (next > F) { s = F; break; } /* beyond the searched neighbourhood: stop at the cap, counted below */
            converged = fabs(next - s) < 1e-3 * s;
            s = next;
        }
        if (!converged && capped) (*capped)++;
        grp->radius_scale[k] = (float)s;
    }
    spr_progress_report(&d.progress, "radius enlargement", (size_t)grp->K, (size_t)grp->K);
    free(in_k);
    free(buf);
    free(clip);
    spr_graph_free(&gw);
    return SPR_OK;
}

double spr_group_coverage(const spr_cloud *c, const spr_groups *grp, double eps, int threads)
{
    spr_error err;
    spr_graph gw;
    double F = 1.0;
    for (int k = 0; grp->radius_scale && k < grp->K; k++)
        if (grp->radius_scale[k] > F) F = grp->radius_scale[k];
    if (spr__pair_graph(c, F, threads, NULL, &gw, &err)) return -1.0;
    unsigned char *in_k = calloc(c->n ? c->n : 1, 1);
    double *share = malloc((c->n ? c->n : 1) * sizeof *share);
    double total = 0.0;
    size_t md = max_degree(&gw) + 1;
    for (int k = 0; k < grp->K && in_k && share; k++) {
        memset(in_k, 0, c->n);
        for (uint32_t m = grp->start[k]; m < grp->start[k + 1]; m++) in_k[grp->members[m]] = 1;
        double s = grp->radius_scale ? grp->radius_scale[k] : 1.0;
#pragma omp parallel num_threads(threads > 0 ? threads : 1)
        {
            uint32_t *tb = malloc(md * sizeof *tb);
#pragma omp for schedule(static)
            for (long i = 0; i < (long)c->n; i++) {
                if (in_k[i] || !tb) { share[i] = in_k[i] ? 1.0 : 0.0; continue; }
                /* share of disk i (its own radius) covered by S_k at scale s */
                size_t m = 0;
                for (uint64_t e = gw.start[i]; e < gw.start[i + 1]; e++)
                    if (in_k[gw.adj[e]]) tb[m++] = gw.adj[e];
                double ri = c->radius[i];
                share[i] = spr_clipped_area(c, (size_t)i, 1.0, tb, m, s, eps) / (M_PI * ri * ri);
            }
            free(tb);
        }
        double cov = 0.0;
        for (size_t i = 0; i < c->n; i++) cov += share[i];
        total += cov / (double)c->n;
    }
    free(in_k);
    free(share);
    spr_graph_free(&gw);
    return grp->K ? total / grp->K : 0.0;
}
