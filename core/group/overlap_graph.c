/* overlap_graph.c — the neighbour graphs of grouping (SPEC §5): all pairs
 * with |p_i − p_j| < f·(r_i + r_j) found on a grid of columns, and the overlap graph
 * (f = 1) with the areas A_ij of [ZP] Eq. 8 on every directed edge, shared
 * by WGC, hash collision handling, extended grouping and the metrics. */
#include "spr_group.h"
#include "spr_util.h"
#include "spr_overlap.h"
#include "spr__group.h"

#include <math.h>
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

/* The pairs are found on a grid of columns, not with a kd-tree: the (y, z)
 * plane is cut into square cells of side h (about twice the mean search
 * radius), each column holds its points sorted by x, and a query scans the
 * columns its ball meets, each over the x of the ball's chord there.
 * The candidates lie contiguous in cell order, copied there once (x, y, z,
 * r as columns of floats), and the work splits evenly over threads.  A pair with r_j ≤ r_i lies
 * within f·2r_i of p_i, so every pair is found from the side of its larger
 * radius (ties: the smaller index) with that search radius, whatever the
 * largest radius of the cloud, then entered in both rows.  Membership is
 * decided in double, |p_i − p_j|² < (f·(r_i + r_j))², so the graph is
 * exactly the one of any exact search: rows ascending, the same for any
 * thread count. */
enum { QB = 8 }; /* the candidates of a column are tested in blocks of QB */
typedef struct col_grid {
    double lo[2], h;   /* y, z */
    int64_t dim[2];
    double slack;      /* more than any rounding of a coordinate near the cloud: the pruning below stays conservative */
    uint32_t *start;   /* columns + 1 */
    float *rmax;       /* columns: the largest radius of each */
    uint32_t *idx;     /* point index in column order (by x, then index) */
    float *x, *y, *z, *r; /* centre and radius per entry */
    uint32_t *before;  /* with a filter's `before`: its value per entry */
    unsigned char *searched; /* with a filter's `row`: whether the entry's row is searched */
} col_grid;

/* Which rows are searched and which pairs kept, asked in the cloud's
 * indices (order[]: copy → cloud): rows i with row[i] == want (row NULL:
 * all, each pair from one side), pairs keep(user, i, j) accepts, and with
 * `before` only the neighbours j with before[j] < before[i]. */
typedef struct pair_filter {
    const unsigned char *row;
    unsigned char want;
    spr__pair_keep keep;
    const void *user;
    const uint32_t *before;
} pair_filter;

static int64_t col_cell(const col_grid *G, double v, int a)
{
    double k = floor((v - G->lo[a]) / G->h);
    return k < 0.0 ? 0 : k >= (double)G->dim[a] ? G->dim[a] - 1 : (int64_t)k;
}

typedef struct xkey { float x; uint32_t i; } xkey;
static int by_x(const void *a, const void *b)
{
    const xkey *p = a, *q = b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    return (p->i > q->i) - (p->i < q->i);
}

static spr_result grid_build(const spr_cloud *c, const spr_bounds *b, double f, const pair_filter *pf, const uint32_t *order, int nt,
                             col_grid *G, spr_error *err)
{
    const size_t n = c->n;
    double ext[2];
    for (int a = 0; a < 2; a++) {
        G->lo[a] = b->lo[a + 1];
        ext[a] = b->hi[a + 1] - b->lo[a + 1];
    }
    /* twice the mean search radius (fewer columns a query, more
     * candidates in each): at 1.1M splats on one thread the whole pair
     * graph took 660-810 ms against 910-1090 with cells of one search
     * radius; at most 4n (+64K) columns */
    G->h = 4.0 * f * b->mean_radius;
    if (!(G->h > 0.0)) G->h = 1.0;
    double cols;
    for (;;) {
        cols = (floor(ext[0] / G->h) + 1.0) * (floor(ext[1] / G->h) + 1.0);
        if (cols <= 4.0 * (double)n + 65536.0) break;
        G->h *= 1.25;
    }
    for (int a = 0; a < 2; a++) G->dim[a] = (int64_t)(floor(ext[a] / G->h) + 1.0);
    double big = G->h;
    for (int a = 0; a < 3; a++) big = fmax(big, fmax(fabs(b->lo[a]), fabs(b->hi[a])));
    G->slack = 1e-9 * (big + 4.0 * b->max_radius);
    const size_t ncol = (size_t)cols;
    G->start = spr__big_calloc(ncol + 1, sizeof *G->start);
    G->rmax = spr__big_alloc(ncol * sizeof *G->rmax);
    /* QB entries beyond the last, for the blocks of grid_query */
    G->idx = spr__big_calloc(n + QB, sizeof *G->idx);
    G->x = spr__big_calloc(n + QB, sizeof *G->x);
    G->y = spr__big_calloc(n + QB, sizeof *G->y);
    G->z = spr__big_calloc(n + QB, sizeof *G->z);
    G->r = spr__big_calloc(n + QB, sizeof *G->r);
    G->before = spr__big_calloc(n + QB, sizeof *G->before); /* 0 without a filter's: every pair kept */
    if (pf->row) G->searched = spr__big_alloc(n);
    uint32_t *key = spr__big_alloc(n * sizeof *key), *fill = spr__big_alloc(ncol * sizeof *fill);
    xkey *xk = spr__big_alloc(n * sizeof *xk);
    spr_result r = SPR_OK;
    if (!G->start || !G->rmax || !G->idx || !G->x || !G->y || !G->z || !G->r || !G->before || (pf->row && !G->searched) || !key || !fill ||
        !xk) {
        r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour grid");
        goto done;
    }
#pragma omp parallel for num_threads(nt) schedule(static)
    for (long i = 0; i < (long)n; i++) {
        const float *p = c->pos + 3 * (size_t)i;
        key[i] = (uint32_t)(col_cell(G, p[2], 1) * G->dim[0] + col_cell(G, p[1], 0));
    }
    for (size_t i = 0; i < n; i++) G->start[key[i] + 1]++;
    for (size_t k = 0; k < ncol; k++) G->start[k + 1] += G->start[k];
    memcpy(fill, G->start, ncol * sizeof *fill);
    for (size_t i = 0; i < n; i++) {
        xkey *e = &xk[fill[key[i]]++];
        e->x = c->pos[3 * i];
        e->i = (uint32_t)i;
    }
#pragma omp parallel for num_threads(nt) schedule(dynamic, 64)
    for (long k = 0; k < (long)ncol; k++) {
        const uint32_t a = G->start[k], e = G->start[k + 1];
        if (e - a > 1) qsort(xk + a, e - a, sizeof *xk, by_x);
        float rm = 0.0f;
        for (uint32_t q = a; q < e; q++) {
            const uint32_t i = xk[q].i;
            G->idx[q] = i;
            G->x[q] = xk[q].x;
            if (pf->before) G->before[q] = pf->before[order[i]];
            if (G->searched) G->searched[q] = pf->row[order[i]] == pf->want;
            G->y[q] = c->pos[3 * (size_t)i + 1];
            G->z[q] = c->pos[3 * (size_t)i + 2];
            G->r[q] = c->radius[i];
            rm = c->radius[i] > rm ? c->radius[i] : rm;
        }
        G->rmax[k] = rm;
    }
done:
    free(key);
    free(fill);
    free(xk);
    return r;
}

/* How far v lies outside column k's span on axis a (0 inside), less the
 * grid's slack: never more than the distance of any point the column holds
 * (the end columns reach out without bound, as col_cell clamps). */
static double col_gap(const col_grid *G, double v, int64_t k, int a)
{
    const double lo = k > 0 ? G->lo[a] + (double)k * G->h - G->slack : -INFINITY;
    const double hi = k + 1 < G->dim[a] ? G->lo[a] + (double)(k + 1) * G->h + G->slack : INFINITY;
    return v < lo ? lo - v : v > hi ? v - hi : 0.0;
}

/* The pair test of entry q against entries k … k + QB − 1 of a column
 * ending before hi, those with x ≤ xhi: ok[t] says whether entry k + t is a
 * neighbour (|p_q − p_j| < f·(r_q + r_j) in double; with `half`, found
 * from q's side; before[k + t] < bq, UINT32_MAX without a filter's
 * `before`).  Branch-free over a block of fixed length, so the compiler
 * vectorises it (AVX2 where the CPU has it, no FMA: the roundings of the
 * scalar test). */
__attribute__((target_clones("avx2", "default")))
static void block_test(const col_grid *G, uint32_t k, uint32_t hi, double xhi, size_t q, double f, int half, uint32_t bq,
                       uint32_t *restrict ok)
{
    const double px = G->x[q], py = G->y[q], pz = G->z[q], ri = G->r[q];
    const uint32_t i = G->idx[q];
    const float *restrict X = G->x + k, *restrict Y = G->y + k, *restrict Z = G->z + k, *restrict Rj = G->r + k;
    const uint32_t *restrict J = G->idx + k, *restrict B = G->before + k;
    for (uint32_t t = 0; t < QB; t++) {
        const double x = X[t], dx = px - x, dy = py - (double)Y[t], dz = pz - (double)Z[t];
        const double rj = Rj[t], lim = f * (ri + rj);
        const double d2 = dx * dx + dy * dy + dz * dz;
        const uint32_t j = J[t];
        const int mine = !half | !((rj > ri) | ((rj == ri) & (j < i))); /* else found from j's side */
        ok[t] = (uint32_t)((k + t < hi) & (x <= xhi) & (j != i) & (d2 < lim * lim) & mine & (B[t] < bq));
    }
}

/* Where the last queries' searches ended, by column (direct-mapped):
 * queries in grid order lie close, so a column's next start lies near. */
enum { CURSORS = 64 };
typedef struct col_cursor { size_t col[CURSORS]; uint32_t at[CURSORS]; } col_cursor;

/* The neighbours of point i (entry q of the grid) within R that meet the
 * pair test (with `half`: only those found from i's side; keep is asked
 * with the indices order[] gives); out gets up to cap of them; returns how
 * many there are.  A column is searched only as far as its largest radius
 * can reach: a pair lies within f·(r_i + r_j) ≤ f·(r_i + its r_max) (with
 * `half`, r_j ≤ r_i too), so a column whose (y, z) span lies farther is
 * skipped and the others are scanned over the x of that ball's chord; the
 * bounds are widened by the slack and 1e-9 relative, so that they skip
 * only candidates block_test would refuse. */
static size_t grid_query(const col_grid *G, size_t q, double R, double f, int half, const pair_filter *pf, const uint32_t *order,
                         col_cursor *cur, uint32_t *out, size_t cap)
{
    const uint32_t i = G->idx[q];
    const double px = G->x[q], py = G->y[q], pz = G->z[q], ri = G->r[q];
    const int64_t y0 = col_cell(G, py - R, 0), y1 = col_cell(G, py + R, 0);
    const int64_t z0 = col_cell(G, pz - R, 1), z1 = col_cell(G, pz + R, 1);
    size_t m = 0;
    for (int64_t z = z0; z <= z1; z++) {
        const double gz = col_gap(G, pz, z, 1);
        for (int64_t y = y0; y <= y1; y++) {
            const size_t col = (size_t)(z * G->dim[0] + y);
            uint32_t lo = G->start[col], hi = G->start[col + 1];
            if (lo == hi) continue;
            const double rm = half && G->rmax[col] > G->r[q] ? ri : (double)G->rmax[col];
            const double Rc = fmin(R, f * (ri + rm)) * (1.0 + 1e-9) + G->slack, gy = col_gap(G, py, y, 0);
            const double w2 = Rc * Rc - (gy * gy + gz * gz);
            if (!(w2 > 0.0)) continue;
            const double wx = sqrt(w2) * (1.0 + 1e-9) + G->slack;
            const double xlo = px - wx, xhi = px + wx;
            const size_t slot = col % CURSORS;
            if (cur->col[slot] == col) { /* the first entry with x ≥ px − wx, by steps from the last one */
                const uint32_t first = lo;
                lo = cur->at[slot];
                while (lo > first && (double)G->x[lo - 1] >= xlo) lo--;
                while (lo < hi && (double)G->x[lo] < xlo) lo++;
            } else {
                for (uint32_t len = hi - lo; len > 1;) { /* the same by halves, in steps that depend on the length alone */
                    const uint32_t h = len / 2;
                    lo = (double)G->x[lo + h - 1] < xlo ? lo + h : lo;
                    len -= h;
                }
                lo += (double)G->x[lo] < xlo;
                cur->col[slot] = col;
            }
            cur->at[slot] = lo;
            const uint32_t bq = pf->before ? G->before[q] : UINT32_MAX;
            for (uint32_t k = lo; k < hi && (double)G->x[k] <= xhi; k += QB) {
                uint32_t ok[QB];
                block_test(G, k, hi, xhi, q, f, half, bq, ok);
                if (pf->keep)
                    for (int t = 0; t < QB; t++) ok[t] = ok[t] && pf->keep(pf->user, order[i], order[G->idx[k + t]]);
                for (int t = 0; t < QB; t++) { /* without branches: the kept ones to out */
                    if (m < cap) out[m] = G->idx[k + t];
                    m += ok[t];
                }
            }
        }
    }
    return m;
}

/* pair_graph's queries run in chunks of QCHUNK grid entries; chunk ch ends at chunk_end(ch, n). */
enum { QCHUNK = 1024 };
static size_t chunk_end(size_t ch, size_t n) { return ch * QCHUNK + QCHUNK < n ? ch * QCHUNK + QCHUNK : n; }

/* The pair graph of cloud c — the spatial copy — in c's indices, each row
 * in the order its pairs were found (the same for any thread count;
 * to_cloud_order sorts the rows it makes); the filters (row, keep) are
 * asked with the indices order[] gives. */
static spr_result pair_graph(const spr_cloud *c, const spr_bounds *b0, double f, const pair_filter *pf, const uint32_t *order, int nt,
                             const spr_progress *prog, spr_graph *g, spr_error *err)
{
    memset(g, 0, sizeof *g);
    const size_t n = c->n;
    g->n = n;
    if (n == 0) {
        if (!(g->start = calloc(1, sizeof *g->start))) return spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
        return SPR_OK;
    }
    const spr_bounds b = *b0;
    col_grid G = {0};
    spr_result r = grid_build(c, &b, f, pf, order, nt, &G, err);
    uint32_t *cnt = r ? NULL : spr__big_calloc(n + 1, sizeof *cnt);
    if (!r && !cnt) r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
    const int half = pf->row == NULL; /* whole graph: each pair from one side, then both rows */
    /* One query per searched row, in grid order (neighbours share cache
     * lines): each chunk of QCHUNK queries writes its finds, row after row,
     * into a buffer of its own (grown geometrically), then every row's finds
     * are copied to their place: the rows hold what two passes (count, then
     * fill) would put there, in the same order. */
    const size_t nchunk = (n + QCHUNK - 1) / QCHUNK;
    uint32_t **cbuf = r ? NULL : calloc(nchunk, sizeof *cbuf);
    if (!r && !cbuf) r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
    if (!r) {
        int failed = 0;
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1) reduction(| : failed)
        for (long ch = 0; ch < (long)nchunk; ch++) {
            if (omp_get_thread_num() == 0) spr_progress_report(prog, "neighbour graph", (size_t)ch * QCHUNK, n);
            size_t used = 0, cap = 0;
            uint32_t *buf = NULL;
            col_cursor cur;
            for (int k = 0; k < CURSORS; k++) cur.col[k] = SIZE_MAX;
            const size_t q1 = chunk_end((size_t)ch, n);
            for (size_t q = (size_t)ch * QCHUNK; q < q1 && !failed; q++) {
                const uint32_t i = G.idx[q];
                if (G.searched && !G.searched[q]) continue;
                const double R = half ? 2.0 * f * c->radius[i] : f * ((double)c->radius[i] + b.max_radius);
                size_t m = grid_query(&G, q, R, f, half, pf, order, &cur, buf ? buf + used : NULL, cap - used);
                if (used + m > cap) { /* did not fit: grow, then the same query again */
                    size_t nc = cap ? 2 * cap : 4096;
                    while (nc < used + m) nc *= 2;
                    uint32_t *nb = realloc(buf, nc * sizeof *nb);
                    if (!nb) { failed = 1; break; }
                    buf = nb, cap = nc;
                    grid_query(&G, q, R, f, half, pf, order, &cur, buf + used, m);
                }
                cnt[i] = (uint32_t)m;
                used += m;
            }
            cbuf[ch] = buf;
        }
        if (failed) r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
    }
    uint64_t *fst = r ? NULL : spr__big_alloc((n + 1) * sizeof *fst);
    if (!r && !fst) r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
    uint32_t *found = NULL;
    if (!r) {
        fst[0] = 0;
        for (size_t i = 0; i < n; i++) fst[i + 1] = fst[i] + cnt[i];
        if (!(found = spr__big_alloc((fst[n] ? fst[n] : 1) * sizeof *found))) r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
    }
    if (!r) {
#pragma omp parallel for num_threads(nt) schedule(dynamic, 16)
        for (long ch = 0; ch < (long)nchunk; ch++) {
            size_t off = 0;
            const size_t q1 = chunk_end((size_t)ch, n);
            for (size_t q = (size_t)ch * QCHUNK; q < q1; q++) {
                const uint32_t i = G.idx[q];
                if (G.searched && !G.searched[q]) continue;
                if (cnt[i]) memcpy(found + fst[i], cbuf[ch] + off, cnt[i] * sizeof *found);
                off += cnt[i];
            }
        }
    }
    for (size_t ch = 0; cbuf && ch < nchunk; ch++) free(cbuf[ch]);
    free(cbuf);
    free(G.start);
    free(G.rmax);
    free(G.idx);
    free(G.x);
    free(G.y);
    free(G.z);
    free(G.r);
    free(G.before);
    free(G.searched);
    if (!r && !half) { /* the rows are the finds as they stand */
        g->start = fst, g->adj = found;
        fst = NULL, found = NULL;
    } else if (!r) { /* the rows: a row's own finds, and every pair entered from the other side too */
        if (!(g->start = spr__big_alloc((n + 1) * sizeof *g->start))) r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
    }
    if (!r && fst) {
        uint64_t *deg = spr__big_calloc(n + 1, sizeof *deg);
        if (!deg) r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
        for (size_t i = 0; !r && i < n; i++) {
            deg[i] += fst[i + 1] - fst[i];
            for (uint64_t k = fst[i]; k < fst[i + 1]; k++) deg[found[k]]++;
        }
        if (!r) {
            g->start[0] = 0;
            for (size_t i = 0; i < n; i++) g->start[i + 1] = g->start[i] + deg[i];
            if (!(g->adj = spr__big_alloc((g->start[n] ? g->start[n] : 1) * sizeof *g->adj)))
                r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
        }
        if (!r) {
            for (size_t i = 0; i < n; i++) deg[i] = g->start[i];
            for (size_t i = 0; i < n; i++)
                for (uint64_t k = fst[i]; k < fst[i + 1]; k++) {
                    g->adj[deg[i]++] = found[k];
                    g->adj[deg[found[k]]++] = (uint32_t)i;
                }
        }
        free(deg);
    }
    free(found);
    free(fst);
    free(cnt);
    if (r) spr_graph_free(g);
    spr_progress_report(prog, "neighbour graph", n, n);
    return r;
}

/* The areas of the rows of graph g over cloud c (the spatial copy, rows
 * in its order, so neighbours' data lie close), A_ij for every edge. */
static spr_result row_areas(const spr_cloud *c, const spr_graph *g, double eps, int nt, const spr_progress *prog, float *A_out)
{
    const long n = (long)c->n;
#pragma omp parallel for num_threads(nt) schedule(dynamic, 256)
    for (long i = 0; i < n; i++) {
        if ((i & 0x3FFF) == 0 && omp_get_thread_num() == 0) spr_progress_report(prog, "overlap areas", (size_t)i, (size_t)n);
        spr_overlap_areas(c, (size_t)i, g->adj + g->start[i], (size_t)(g->start[i + 1] - g->start[i]), eps, A_out + g->start[i]);
    }
    spr_progress_report(prog, "overlap areas", c->n, c->n);
    return SPR_OK;
}

/* w_ij = (A_ij + A_ji)(1 − n_i·n_j) of [ZP] Eq. 7 for every edge of the
 * copy's graph g (spr_wgc_weights' arithmetic): the reverse edge is found
 * by a scan of row j, which lies close to row i in the copy. */
static void row_weights(const spr_cloud *c, const spr_graph *g, const float *A, int nt, float *w)
{
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1024)
    for (long i = 0; i < (long)c->n; i++)
        for (uint64_t e = g->start[i]; e < g->start[i + 1]; e++) {
            const uint32_t j = g->adj[e];
            double a_back = 0.0; /* none in a symmetric graph */
            for (uint64_t b = g->start[j]; b < g->start[j + 1]; b++)
                if (g->adj[b] == (uint32_t)i) { a_back = A[b]; break; }
            const float *ni = c->nrm + 3 * (size_t)i, *nj = c->nrm + 3 * (size_t)j;
            double nn = (double)ni[0] * nj[0] + (double)ni[1] * nj[1] + (double)ni[2] * nj[2];
            w[e] = (float)(((double)A[e] + a_back) * (1.0 - nn));
        }
}

typedef struct edge { uint32_t j; float a, w; } edge;
static int by_j(const void *a, const void *b)
{
    const edge *p = a, *q = b;
    return (p->j > q->j) - (p->j < q->j);
}

/* The graph (and areas) of the spatial copy s in the cloud's indices: row i
 * is the copy's row rank[i] with every j mapped through order[], ascending. */
static spr_result to_cloud_order(const spr__spatial *s, const spr_graph *gs, const float *As, const float *Ws, int nt, spr_graph *g,
                                 float **A, float **W, spr_error *err)
{
    const size_t n = s->c.n;
    memset(g, 0, sizeof *g);
    g->n = n;
    g->start = spr__big_alloc((n + 1) * sizeof *g->start);
    if (!g->start) return spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
    g->start[0] = 0;
    uint64_t max_deg = 0;
    for (size_t i = 0; i < n; i++) {
        const uint64_t d = gs->start[s->rank[i] + 1] - gs->start[s->rank[i]];
        g->start[i + 1] = g->start[i] + d;
        if (d > max_deg) max_deg = d;
    }
    const uint64_t w = g->start[n];
    g->adj = spr__big_alloc((w ? w : 1) * sizeof *g->adj);
    float *a = As ? spr__big_alloc((w ? w : 1) * sizeof *a) : NULL, *wt = Ws ? spr__big_alloc((w ? w : 1) * sizeof *wt) : NULL;
    if (!g->adj || (As && !a) || (Ws && !wt)) {
        free(a);
        free(wt);
        spr_graph_free(g);
        return spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
    }
    int failed = 0;
#pragma omp parallel num_threads(nt) reduction(| : failed)
    {
        edge *e = malloc((max_deg ? max_deg : 1) * sizeof *e);
        failed |= !e;
#pragma omp for schedule(dynamic, 4096)
        for (long i = 0; i < (long)n; i++) { /* in the cloud's order: the writes in turn, the copy's rows fetched ahead */
            if (!e) continue;
            if (i + 16 < (long)n) __builtin_prefetch(gs->start + s->rank[i + 16]);
            if (i + 8 < (long)n) { /* hints, no arithmetic */
                const uint32_t q8 = s->rank[i + 8];
                const uint64_t s8 = gs->start[q8];
                __builtin_prefetch(gs->adj + s8);
                __builtin_prefetch(s->order + q8);
                if (As) __builtin_prefetch(As + s8);
                if (Ws) __builtin_prefetch(Ws + s8);
            }
            const size_t q = s->rank[i];
            const uint64_t s0 = gs->start[q];
            const size_t m = (size_t)(gs->start[q + 1] - s0);
            for (size_t k = 0; k < m; k++) e[k] = (edge){s->order[gs->adj[s0 + k]], As ? As[s0 + k] : 0.0f, Ws ? Ws[s0 + k] : 0.0f};
            if (m > 64) {
                qsort(e, m, sizeof *e, by_j); /* the j of a row are distinct: any sort gives one order */
            } else {
                for (size_t x = 1; x < m; x++) { /* short rows: insertion sort */
                    edge v = e[x];
                    size_t y = x;
                    for (; y > 0 && e[y - 1].j > v.j; y--) e[y] = e[y - 1];
                    e[y] = v;
                }
            }
            for (size_t k = 0; k < m; k++) {
                g->adj[g->start[i] + k] = e[k].j;
                if (a) a[g->start[i] + k] = e[k].a;
                if (wt) wt[g->start[i] + k] = e[k].w;
            }
        }
        free(e);
    }
    if (failed) {
        free(a);
        free(wt);
        spr_graph_free(g);
        return spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
    }
    if (A) *A = a;
    if (W) *W = wt;
    return SPR_OK;
}

/* Every graph of this file: built on a copy of the cloud in Morton order
 * (spr__spatial.h; a cloud in no spatial order took twice as long for its
 * neighbour walks), then put in the cloud's indices.  The pair test and
 * every area use the same floats in either order, so the graph and its
 * areas are the bits a search in submission order gives. */
static spr_result spatial_graph(const spr_cloud *c, double f, const pair_filter *pf, int threads, const spr_progress *prog, int areas,
                                double eps, spr_graph *g, float **A, float **W, spr_error *err)
{
    memset(g, 0, sizeof *g);
    if (A) *A = NULL;
    if (W) *W = NULL;
    const int nt = threads > 0 ? threads : omp_get_max_threads();
    spr_bounds b;
    spr_cloud_bounds(c, &b);
    spr__spatial s;
    spr_result r = spr__spatial_make(c, &b, nt, &s, err);
    if (r) return r;
    spr_graph gs;
    r = pair_graph(&s.c, &b, f, pf, s.order, nt, prog, &gs, err);
    if (r) { spr__spatial_free(&s); return r; }
    float *As = NULL, *Ws = NULL;
    if (areas) {
        const uint64_t w = gs.start[c->n];
        if (!(As = spr__big_alloc((w ? w : 1) * sizeof *As)) || (W && !(Ws = spr__big_alloc((w ? w : 1) * sizeof *Ws))))
            r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for overlap areas");
        if (!r) r = row_areas(&s.c, &gs, eps, threads > 0 ? threads : 1, prog, As);
        if (!r && Ws) row_weights(&s.c, &gs, As, nt, Ws);
    }
    if (!r) r = to_cloud_order(&s, &gs, As, Ws, nt, g, areas ? A : NULL, Ws ? W : NULL, err);
    free(As);
    free(Ws);
    spr_graph_free(&gs);
    spr__spatial_free(&s);
    return r;
}

spr_result spr__pair_graph_rows(const spr_cloud *c, double f, const unsigned char *row, unsigned char want, int threads,
                                const spr_progress *prog, spr_graph *g, spr_error *err)
{
    const pair_filter pf = {.row = row, .want = want};
    return spatial_graph(c, f, &pf, threads, prog, 0, 0.0, g, NULL, NULL, err);
}

spr_result spr__pair_graph_spatial(const spr_cloud *c, double f, const unsigned char *in, const unsigned char *row, unsigned char want,
                                   const uint32_t *before, int threads, const spr_progress *prog, spr__spatial *s, spr_graph *gs,
                                   spr_error *err)
{
    memset(gs, 0, sizeof *gs);
    memset(s, 0, sizeof *s);
    const int nt = threads > 0 ? threads : omp_get_max_threads();
    spr_cloud part = *c; /* the splats that take part: all, or those `in` names, in submission order */
    uint32_t *sub = NULL;
    if (in) {
        size_t m = 0;
        for (size_t i = 0; i < c->n; i++) m += in[i] != 0;
        const size_t mm = m ? m : 1;
        memset(&part, 0, sizeof part);
        part.n = m;
        sub = spr__alloc(mm * sizeof *sub);
        part.pos = spr__alloc(3 * mm * sizeof(float));
        part.nrm = spr__alloc(3 * mm * sizeof(float));
        part.radius = spr__alloc(mm * sizeof(float));
        if (!sub || !part.pos || !part.nrm || !part.radius) {
            free(sub), free(part.pos), free(part.nrm), free(part.radius);
            return spr__fail(err, SPR_E_NOMEM, "groups: out of memory for %zu splats of the neighbour graph", m);
        }
        for (size_t i = 0, k = 0; i < c->n; i++)
            if (in[i]) {
                sub[k] = (uint32_t)i;
                memcpy(part.pos + 3 * k, c->pos + 3 * i, 3 * sizeof(float));
                memcpy(part.nrm + 3 * k, c->nrm + 3 * i, 3 * sizeof(float));
                part.radius[k++] = c->radius[i];
            }
    }
    spr_bounds b;
    spr_cloud_bounds(&part, &b);
    spr_result r = spr__spatial_make(&part, &b, nt, s, err);
    if (in) {
        free(part.pos), free(part.nrm), free(part.radius);
        if (!r) { /* the copy's indices into the cloud's */
            uint32_t *rank = spr__alloc((c->n ? c->n : 1) * sizeof *rank);
            if (!rank) r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory for the neighbour graph");
            for (size_t i = 0; !r && i < c->n; i++) rank[i] = UINT32_MAX;
            for (size_t q = 0; !r && q < part.n; q++) {
                s->order[q] = sub[s->order[q]];
                rank[s->order[q]] = (uint32_t)q;
            }
            if (r) spr__spatial_free(s);
            else free(s->rank), s->rank = rank;
        }
        free(sub);
    }
    if (r) return r;
    const pair_filter pf = {.row = row, .want = want, .before = before};
    if ((r = pair_graph(&s->c, &b, f, &pf, s->order, nt, prog, gs, err))) spr__spatial_free(s);
    return r;
}

spr_result spr__pair_graph_keep(const spr_cloud *c, double f, int threads, const spr_progress *prog, spr__pair_keep keep, const void *user,
                                spr_graph *g, spr_error *err)
{
    const pair_filter pf = {.keep = keep, .user = user};
    return spatial_graph(c, f, &pf, threads, prog, 0, 0.0, g, NULL, NULL, err);
}

spr_result spr_overlap_graph_build(const spr_cloud *c, double eps, int threads, const spr_progress *prog,
                                   spr_overlap_graph *og, spr_error *err)
{
    return spr_overlap_graph_build_rows(c, eps, NULL, 0, threads, prog, og, err);
}

spr_result spr_overlap_graph_build_rows(const spr_cloud *c, double eps, const unsigned char *row, unsigned char want, int threads,
                                        const spr_progress *prog, spr_overlap_graph *og, spr_error *err)
{
    memset(og, 0, sizeof *og);
    og->eps = eps;
    const pair_filter pf = {.row = row, .want = want};
    return spatial_graph(c, 1.0, &pf, threads, prog, 1, eps, &og->g, &og->A, NULL, err);
}

spr_result spr__overlap_graph_weights(const spr_cloud *c, double eps, int threads, const spr_progress *prog, spr_overlap_graph *og, float **w,
                                      spr_error *err)
{
    memset(og, 0, sizeof *og);
    og->eps = eps;
    const pair_filter pf = {0};
    return spatial_graph(c, 1.0, &pf, threads, prog, 1, eps, &og->g, &og->A, w, err);
}
