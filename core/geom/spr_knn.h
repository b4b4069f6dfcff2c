/* spr_knn.h — neighbour queries over splat centres through FLANN.
 *
 * Exact searches only (single kd-tree, unlimited checks), so results do not
 * depend on random seeds.  Neighbour lists come back sorted by index, and
 * kNN distances are recomputed in double from the float positions, so
 * callers never see FLANN's internal ordering of ties.
 */
#ifndef SPR_KNN_H
#define SPR_KNN_H

#include <stddef.h>
#include <stdint.h>
#include "spr_graph.h"
#include "spr_result.h"
#include "spr_util.h"

typedef struct spr_knn spr_knn;

/* Index over n points (3 floats each, kept by reference). */
spr_result spr_knn_build(const float *pos, size_t n, spr_knn **out, spr_error *err);
void spr_knn_free(spr_knn *k);

/* k nearest neighbours of every point, the point itself excluded: idx[n·k]
 * and dist[n·k] (double, ascending, ties by index).  Fewer than k points
 * available: the remaining entries get idx = UINT32_MAX, dist = INFINITY. */
spr_result spr_knn_query_all(spr_knn *kn, int k, int threads, uint32_t *idx, double *dist, const spr_progress *prog,
                             spr_error *err);

#endif
