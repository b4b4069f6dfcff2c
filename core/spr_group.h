/* spr_group.h — splat groups S_k for deferred blending (SPEC §5).
 *
 * spr_groups holds memberships ordered by group, then by submission order:
 * members[start[k] … start[k+1]) are the splats of group k.  Grouping
 * methods produce one label per splat; spr_groups_from_labels() builds the
 * membership lists from them.
 */
#ifndef SPR_GROUP_H
#define SPR_GROUP_H

#include <stdint.h>
#include "spr_cloud.h"
#include "spr_knn.h"
#include "spr_result.h"

typedef struct spr_groups {
    int K;
    size_t n_splats;
    uint32_t *start;    /* K + 1 */
    uint32_t *members;
} spr_groups;

/* Labels in [0, K) → memberships (K = 1 + largest label when K_hint <= 0). */
spr_result spr_groups_from_labels(const int32_t *label, size_t n, int K_hint, spr_groups *g, spr_error *err);
void spr_groups_free(spr_groups *g);
/* Read one integer group per line for n splats; the file, line and value on error. */
spr_result spr_groups_read(const char *path, size_t n, int32_t *label, spr_error *err);
/* Write labels, one per line, through a temporary file. */
spr_result spr_groups_write(const char *path, const int32_t *label, size_t n, spr_error *err);

/* MGC options, zero = defaults of SPEC §5.1 (via spr_mgc_defaults). */
typedef struct spr_mgc_desc {
    double c;               /* overlap relaxation factor, (0, 1] */
    int relax_coplanar;     /* relaxation 1 */
    int relax_opposite;     /* relaxation 2 */
    double coplanar_deg;    /* θ_c */
    double coplanar_tau;    /* τ */
    int threads;
    spr_progress progress;
} spr_mgc_desc;
void spr_mgc_defaults(spr_mgc_desc *d);

typedef struct spr_group_stats {
    int K;
    int max_degree;
    double avg_degree;
    size_t edges;
    double ms_graph, ms_color;
} spr_group_stats;

/* [ZP] Eq. 5 with the active relaxations: 1 when splats i and j conflict
 * (must not share a group).  Symmetric; evaluated in double. */
int spr_mgc_conflict(const spr_cloud *c, const spr_mgc_desc *d, size_t i, size_t j);
/* Largest-first greedy colouring of the conflict graph (SPEC §5.1). */
spr_result spr_group_mgc(const spr_cloud *c, const spr_mgc_desc *d, int32_t *label, spr_group_stats *st, spr_error *err);

/* Hash grouping mode 1 ([ZP] Eq. 9, SPEC §5.3) with the axis from each
 * splat's own normal: label = (x + s·y) mod K. */
spr_result spr_group_hash(const spr_cloud *c, int K, int32_t *label, spr_group_stats *st, spr_error *err);
/* Step s in [1, K−1] maximising the shortest distance between distinct
 * same-group cells (ties: smallest s); 3 for K = 8. */
int spr_hash_step(int K);
/* Cell coordinates of Eq. 9 for splat i (exposed for tests and tools). */
void spr_hash_cell(const spr_cloud *c, size_t i, int64_t *x, int64_t *y);

#endif
