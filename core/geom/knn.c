/* knn.c — FLANN (C API) wrapper: exact kNN and radius graphs. */
#include "spr_knn.h"

#include <flann/flann.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

struct spr_knn {
    const float *pos;
    size_t n;
    flann_index_t index;
    struct FLANNParameters params;
};

spr_result spr_knn_build(const float *pos, size_t n, spr_knn **out, spr_error *err)
{
    *out = NULL;
    if (n == 0 || n > INT32_MAX) return spr__fail(err, SPR_E_ARG, "knn: %zu points", n);
    spr_knn *k = calloc(1, sizeof *k);
    if (!k) return spr__fail(err, SPR_E_NOMEM, "knn: out of memory");
    k->pos = pos;
    k->n = n;
    k->params = DEFAULT_FLANN_PARAMETERS;
    k->params.algorithm = FLANN_INDEX_KDTREE_SINGLE;
    k->params.leaf_max_size = 10;
    k->params.checks = FLANN_CHECKS_UNLIMITED;
    k->params.eps = 0.0f;
    k->params.log_level = FLANN_LOG_NONE;
    k->params.random_seed = 1;
    k->params.cores = 1;
    float speedup;
    /* FLANN takes a non-const pointer but does not modify the data. */
    k->index = flann_build_index_float((float *)pos, (int)n, 3, &speedup, &k->params);
    if (!k->index) {
        free(k);
        return spr__fail(err, SPR_E_BACKEND, "knn: FLANN could not build an index over %zu points", n);
    }
    *out = k;
    return SPR_OK;
}

void spr_knn_free(spr_knn *k)
{
    if (!k) return;
    flann_free_index_float(k->index, &k->params);
    free(k);
}

static double dist3(const float *a, const float *b)
{
    double dx = (double)a[0] - b[0], dy = (double)a[1] - b[1], dz = (double)a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* Insertion sort of (dist, idx) pairs, ties by index: lists are short. */
static void sort_pairs(double *d, uint32_t *ix, int m)
{
    for (int a = 1; a < m; a++) {
        double dv = d[a];
        uint32_t iv = ix[a];
        int b = a - 1;
        while (b >= 0 && (d[b] > dv || (d[b] == dv && ix[b] > iv))) {
            d[b + 1] = d[b];
            ix[b + 1] = ix[b];
            b--;
        }
        d[b + 1] = dv;
        ix[b + 1] = iv;
    }
}

spr_result spr_knn_query_all(spr_knn *kn, int k, int threads, uint32_t *idx, double *dist, const spr_progress *prog,
                             spr_error *err)
{
    if (k < 1 || k > 1024) return spr__fail(err, SPR_E_ARG, "knn: k = %d outside 1..1024", k);
    /* Ask for a few extra so that duplicates of the query point and distance
     * ties at the k-th place are resolved by our own sort. */
    int m = k + 4;
    if ((size_t)m > kn->n) m = (int)kn->n;
    const size_t n = kn->n, block = 65536;
    int *fi = malloc(block * (size_t)m * sizeof(int));
    float *fd = malloc(block * (size_t)m * sizeof(float));
    if (!fi || !fd) {
        free(fi);
        free(fd);
        return spr__fail(err, SPR_E_NOMEM, "knn: out of memory");
    }
    struct FLANNParameters p = kn->params;
    p.cores = threads > 0 ? threads : 0;
    spr_result res = SPR_OK;
    for (size_t b0 = 0; b0 < n; b0 += block) {
        size_t nb = n - b0 < block ? n - b0 : block;
        spr_progress_report(prog, "neighbours", b0, n);
        if (flann_find_nearest_neighbors_index_float(kn->index, (float *)kn->pos + 3 * b0, (int)nb, fi, fd, m, &p) != 0) {
            res = spr__fail(err, SPR_E_BACKEND, "knn: FLANN search failed");
            break;
        }
        for (size_t q = 0; q < nb; q++) {
            size_t i = b0 + q;
            double dd[1040];
            uint32_t ii[1040];
            int c = 0;
            for (int j = 0; j < m; j++) {
                int o = fi[q * m + j];
                if (o < 0 || (size_t)o == i) continue;
                ii[c] = (uint32_t)o;
                dd[c] = dist3(kn->pos + 3 * i, kn->pos + 3 * (size_t)o);
                c++;
            }
            sort_pairs(dd, ii, c);
            for (int j = 0; j < k; j++) {
                idx[i * k + j] = j < c ? ii[j] : UINT32_MAX;
                dist[i * k + j] = j < c ? dd[j] : INFINITY;
            }
        }
    }
    free(fi);
    free(fd);
    spr_progress_report(prog, "neighbours", n, n);
    return res;
}

void spr_graph_free(spr_graph *g)
{
    free(g->start);
    free(g->adj);
    memset(g, 0, sizeof *g);
}
