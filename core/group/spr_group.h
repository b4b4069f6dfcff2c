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
    float *radius_scale; /* K factors for enlarged radii ([ZP] §4.4.2), NULL = 1 */
} spr_groups;

/* Labels in [0, K) → memberships (K = 1 + largest label when K_hint <= 0). */
spr_result spr_groups_from_labels(const int32_t *label, size_t n, int K_hint, spr_groups *g, spr_error *err);
void spr_groups_free(spr_groups *g);
/* Read one integer group per line for n splats; the file, line and value on error. */
spr_result spr_groups_read(const char *path, size_t n, int32_t *label, spr_error *err);
/* Read either format: one group per line (render --groups-out), or one
 * membership `splat_index group` per line (splatref group --out, which may
 * list a splat in several groups).  Every splat must belong to a group.
 * label (n entries) gets each splat's first group. */
spr_result spr_groups_read_any(const char *path, size_t n, spr_groups *g, int32_t *label, spr_error *err);
/* Write labels, one per line, through a temporary file. */
spr_result spr_groups_write(const char *path, const int32_t *label, size_t n, spr_error *err);
/* Write memberships, `splat_index group` per line, by group then splat. */
spr_result spr_groups_write_memberships(const char *path, const spr_groups *g, spr_error *err);

/* MGC options, zero = defaults of SPEC §5.1 (via spr_mgc_defaults). */
typedef struct spr_mgc_desc {
    double c;               /* overlap relaxation factor, [0, 1] */
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
    double ms_graph, ms_color, ms_optimise;
    double cost_before, cost_after;  /* WGC: L(G, K) of [ZP] Eq. 6 */
    size_t pops;                     /* WGC optimisation steps */
    size_t displaced;                /* hash modes 2/3: splats moved off their cell's group */
} spr_group_stats;

/* [ZP] Eq. 5 with the active relaxations: 1 when splats i and j conflict
 * (must not share a group).  Symmetric; evaluated in double. */
int spr_mgc_conflict(const spr_cloud *c, const spr_mgc_desc *d, size_t i, size_t j);
/* Largest-first greedy colouring of the conflict graph (SPEC §5.1). */
spr_result spr_group_mgc(const spr_cloud *c, const spr_mgc_desc *d, int32_t *label, spr_group_stats *st, spr_error *err);

/* ---- hash grouping ([ZP] §4.3, Eq. 9, Fig. 9; SPEC §5.3) ---- */
typedef enum spr_hash_axis {
    SPR_HASH_AXIS_BSP = 0,   /* largest |component| of the BSP leaf's average normal (default) */
    SPR_HASH_AXIS_NORMAL     /* largest |component| of the splat's own normal */
} spr_hash_axis;
typedef struct spr_hash_desc {
    int K;                /* default 8 */
    int mode;             /* 1: no collision handling, 2: collisions handled, 3: mixed (default 1) */
    spr_hash_axis axis;
    double eye[3];        /* mode 3: collisions handled for splats with |p − eye| < near_dist */
    double near_dist;
    double eps;           /* overlap areas of collision handling (0 = spr_cloud_default_eps) */
    const int32_t *axes;  /* optional: the axis of every splat, e.g. from a BSP kept across frames */
    int threads;
    spr_progress progress;
} spr_hash_desc;
/* Axis of every splat from the BSP leaves' average normals (or own normals). */
spr_result spr_hash_axes(const spr_cloud *c, spr_hash_axis how, int32_t *axis, spr_error *err);
/* The same on at most `threads` threads (0: OpenMP's default; the BSP build's). */
spr_result spr__hash_axes_threads(const spr_cloud *c, spr_hash_axis how, int threads, int32_t *axis, spr_error *err);
/* The BSP axes from a tree already built (its leaves' normals). */
struct spr_bsp;
void spr_hash_axes_of_bsp(const struct spr_bsp *t, int32_t *axis);
void spr_hash_defaults(spr_hash_desc *d);
/* label = (x + s·y) mod K, then (modes 2/3) collisions: the first splat of a
 * cell keeps the table group, later ones take the group of minimal total
 * overlap A with the neighbours placed before them (ties: the table group
 * if minimal, else the smallest k). */
spr_result spr_group_hash(const spr_cloud *c, const spr_hash_desc *d, int32_t *label, spr_group_stats *st, spr_error *err);
/* Dynamic clouds: regroup only the m splats in `changed` (their positions or
 * normals moved); every other label is left as it is.  A changed splat takes
 * its cell's table group unless an unchanged splat already occupies the cell
 * (modes 2/3), in which case it takes the minimal-overlap group. */
spr_result spr_group_hash_update(const spr_cloud *c, const spr_hash_desc *d, int32_t *label, const uint32_t *changed,
                                 size_t m, spr_group_stats *st, spr_error *err);
/* Step s in [1, K−1] maximising the shortest distance between distinct
 * same-group cells (ties: smallest s); 3 for K = 8. */
int spr_hash_step(int K);
/* Enlarged-radius factor for hash groups: the circumradius, in cell units, of
 * the triangle of the two shortest same-group lattice vectors; √50/4 for K = 8. */
double spr_hash_enlarge_factor(int K);
/* Axis (0..2) and cell (Eq. 9) of splat i; `leaf_normal` NULL = own normal. */
int spr_hash_axis_of(const float n[3]);
void spr_hash_cell(const spr_cloud *c, size_t i, int d, int64_t *x, int64_t *y);
/* Table group of a cell: (x + s·y) mod K, non-negative. */
int spr_hash_table(int64_t x, int64_t y, int K, int s);

/* ---- overlap graph shared by WGC, hash collisions and the metrics ---- */
/* All pairs with |p_i − p_j| < r_i + r_j (FLANN), and for every directed
 * edge e = (i → j) the area A_ij of [ZP] Eq. 8 (spr_overlap.h). */
typedef struct spr_overlap_graph {
    spr_graph g;
    float *A;            /* per directed edge */
    double eps;
} spr_overlap_graph;
spr_result spr_overlap_graph_build(const spr_cloud *c, double eps, int threads, const spr_progress *prog,
                                   spr_overlap_graph *og, spr_error *err);
void spr_overlap_graph_free(spr_overlap_graph *og);
/* The same for the rows i with row[i] == want only (the other rows stay
 * empty: a one-sided graph for callers that read those rows alone). */
spr_result spr_overlap_graph_build_rows(const spr_cloud *c, double eps, const unsigned char *row, unsigned char want, int threads,
                                        const spr_progress *prog, spr_overlap_graph *og, spr_error *err);
/* All pairs with |p_i − p_j| < f·(r_i + r_j) (no areas); row (may be NULL):
 * only rows i with row[i] == want are searched. */
spr_result spr__pair_graph(const spr_cloud *c, double f, int threads, const spr_progress *prog, spr_graph *g, spr_error *err);
/* The same graph with only the pairs keep(user, i, j) accepts; keep must be
 * symmetric (keep(i, j) == keep(j, i)): each pair is asked once. */
typedef int (*spr__pair_keep)(const void *user, size_t i, size_t j);
spr_result spr__pair_graph_keep(const spr_cloud *c, double f, int threads, const spr_progress *prog, spr__pair_keep keep, const void *user,
                                spr_graph *g, spr_error *err);
spr_result spr__pair_graph_rows(const spr_cloud *c, double f, const unsigned char *row, unsigned char want, int threads,
                                const spr_progress *prog, spr_graph *g, spr_error *err);


/* ---- WGC: weighted graph colouring with K colours (SPEC §5.2) ---- */
typedef struct spr_wgc_desc {
    int K;              /* default 8 */
    double eps;         /* 0 = spr_cloud_default_eps */
    double tau_w;       /* optimisation threshold τ_w (default 0) */
    size_t max_pops;    /* 0 = 10·n */
    int threads;
    spr_progress progress;
    spr_overlap_graph *graph_out; /* if set, receives the overlap graph (caller frees) */
} spr_wgc_desc;
void spr_wgc_defaults(spr_wgc_desc *d);
spr_result spr_group_wgc(const spr_cloud *c, const spr_wgc_desc *d, int32_t *label, spr_group_stats *st, spr_error *err);
/* w_ij = (A_ij + A_ji)(1 − n_i·n_j), [ZP] Eq. 7, per directed edge (malloc'd). */
float *spr_wgc_weights(const spr_cloud *c, const spr_overlap_graph *og);
/* L(G, K) of [ZP] Eq. 6: Σ w_ij over edges whose ends share a colour. */
double spr_wgc_cost(const spr_overlap_graph *og, const float *w, const int32_t *label);
/* MinimizeOverlap: the colour k minimising Σ A_vj over neighbours j with
 * colour k (label < 0 = uncoloured, ignored); ties: smallest k. */
int spr_minimize_overlap(const spr_overlap_graph *og, size_t v, const int32_t *label, int K);

/* ---- extended grouping for surface coverage ([ZP] §4.4.2, SPEC §5.5) ---- */
typedef struct spr_extend_desc {
    double eps;          /* 0 = spr_cloud_default_eps */
    double max_share;    /* duplication: drop a candidate covered beyond this share (default 0.5) */
    double max_scale;    /* Eq. 13: largest radius scale (default 3: the neighbour search covers pairs up to 3·(r_i + r_j)) */
    int max_iterations;  /* Eq. 13: iterations per group before giving up on the 1e-3 criterion (default 50) */
    int threads;
    spr_progress progress;
} spr_extend_desc;
void spr_extend_defaults(spr_extend_desc *d);
/* Duplication: for each group k, splats not in k, least covered by S_k first
 * [decision: ascending, SPEC §5.5], re-evaluated on pop, inserted when the
 * value held, dropped beyond max_share; groups built from `label` plus the
 * duplicates (memberships ordered by group, then submission order). */
spr_result spr_group_duplicate(const spr_cloud *c, const int32_t *label, int K, const spr_extend_desc *d, spr_groups *out,
                               double *dup_ratio, spr_error *err);
/* Radius enlargement by [ZP] Eq. 13 per group: n·π·r̃² = A + Σ Clipped(p_i, r̃, k),
 * iterated from r̃ = r until the relative change is below 1e-3; the result
 * is a radius scale per group in g->radius_scale (allocated here).  A group
 * whose iteration reaches d->max_scale or runs d->max_iterations times
 * stops there and is counted in *capped (may be NULL). */
spr_result spr_group_enlarge(const spr_cloud *c, spr_groups *g, const spr_extend_desc *d, int *capped, spr_error *err);
/* Mean over groups k and splats i of the share of disk i covered by S_k
 * (with S_k's radius scale): how completely each group alone covers the surface. */
double spr_group_coverage(const spr_cloud *c, const spr_groups *g, double eps, int threads);

/* ---- grouping as one call: method, then extension (SPEC §5) ---- */
typedef enum spr_group_method {
    SPR_GROUP_NONE = 0,  /* one group */
    SPR_GROUP_MGC,       /* §5.1 */
    SPR_GROUP_WGC,       /* §5.2 */
    SPR_GROUP_HASH,      /* §5.3 */
    SPR_GROUP_FILE,      /* memberships read from a groups file */
    SPR_GROUP__COUNT
} spr_group_method;
typedef enum spr_group_extend {
    SPR_EXTEND_NONE = 0,
    SPR_EXTEND_DUP,          /* §5.5 (1) duplication */
    SPR_EXTEND_RADIUS,       /* §5.5 (2) Eq. 13 */
    SPR_EXTEND_HASH_RADIUS,  /* §5.5 (2) the lattice circumradius, √50/4 for K = 8 */
    SPR_EXTEND__COUNT
} spr_group_extend;
/* Name ↔ enum ("none", "mgc", "wgc", "hash", "file"; "none", "dup",
 * "radius", "hash-radius"); −1 if unknown. */
int spr_group_method_from_name(const char *name);
const char *spr_group_method_name(spr_group_method m);
int spr_group_extend_from_name(const char *name);

/* Everything a grouping needs; zero = defaults via spr_grouping_defaults(). */
typedef struct spr_grouping_desc {
    spr_group_method method;
    spr_mgc_desc mgc;        /* MGC options (c, relaxations) */
    spr_wgc_desc wgc;        /* WGC options (K) */
    spr_hash_desc hash;      /* hash options (K, mode, axis, eye, near_dist) */
    const char *file;        /* SPR_GROUP_FILE: the groups file */
    spr_group_extend extend;
    spr_extend_desc ext;
    int keep_graph;          /* WGC: keep its overlap graph in the result */
    int threads;
    spr_progress progress;
} spr_grouping_desc;
void spr_grouping_defaults(spr_grouping_desc *d);

typedef struct spr_grouping {
    spr_groups groups;       /* memberships by group, radius scales when extended */
    int32_t *labels;         /* each splat's first group */
    spr_group_stats stats;
    double ms_grouping, ms_extend, dup_ratio;
    spr_overlap_graph graph; /* WGC's overlap graph when keep_graph (n = 0 otherwise) */
    int capped_groups;       /* Eq. 13 groups stopped by max_scale or max_iterations */
} spr_grouping;
/* Group c by d->method, then extend; *out is owned by the caller. */
spr_result spr_group_run(const spr_cloud *c, const spr_grouping_desc *d, spr_grouping *out, spr_error *err);
void spr_grouping_free(spr_grouping *g);

/* ---- metrics (SPEC §5.7) ---- */
/* Mean over splats of Σ (r_i + r_k − |p_i − p_k|)/r_i over overlapping
 * same-group neighbours k ([ZP] §6.1 with unequal radii [decision]). */
double spr_overlap_factor(const spr_cloud *c, const spr_graph *g, const int32_t *label);

#endif
