/* spr_domain.h — domain primitives, first half of SPEC §7 ([R]): local
 * analysis (§7.1), the multi-scale soft decomposition (§7.2) and domains
 * (§7.3).  Host-side and in double: nothing here reaches a plane directly.
 *
 * Sparse matrices are a small CSR type of our own (docs/domains.md says
 * why no library): rows of (column, value) pairs, columns ascending.
 */
#ifndef SPR_DOMAIN_H
#define SPR_DOMAIN_H

#include <stddef.h>
#include <stdint.h>
#include "spr_cloud.h"
#include "spr_result.h"
#include "spr_util.h"
#include "spr_backend.h"

typedef struct spr_csr {
    size_t rows, cols;
    size_t *ptr;     /* rows + 1 */
    uint32_t *col;   /* ptr[rows] entries, ascending within a row */
    double *val;
} spr_csr;
void spr_csr_free(spr_csr *m);
/* out = a·b; entries below drop·(the row's largest) are dropped and the row
 * is rescaled to its former sum (drop 0: exact product). */
spr_result spr_csr_mul(const spr_csr *a, const spr_csr *b, double drop, spr_csr *out, spr_error *err);

/* §7.1: per point the k nearest neighbours (FLANN, exact), the PCA normal
 * (λ0 eigenvector, unoriented) and the surface variation σ = λ0/(λ0+λ1+λ2). */
typedef struct spr_local {
    size_t n;
    int k;
    uint32_t *nb;    /* n·k, UINT32_MAX where fewer exist */
    float *normal;   /* n·3 */
    double *sigma;   /* n */
} spr_local;
spr_result spr_local_analysis(const spr_cloud *c, int k, int threads, const spr_progress *prog, spr_local *out, spr_error *err);
void spr_local_free(spr_local *l);

/* §7.2: the decomposition's parameters. */
typedef struct spr_decomp_desc {
    int k;              /* neighbours of the local analysis and of the graph (default 10) */
    double delta;       /* coupling M_jk = |n_j·n_k|^normal_power / (delta + max(σ_j, σ_k)) (default 0.01) */
    double normal_power;/* with the cloud's normals; 0: σ alone (default 4) */
    double strong;      /* an aggregate edge is strong when its mean fine coupling is at least
                           strong × the fine mean (default 0.05); weaker ones wait for a later level */
    double relative;    /* and only pairs when also ≥ relative × the chooser's strongest edge (default 0.8) */
    double omega;       /* smoothing weight in [0, 1) (default 0.5) */
    int smooth;         /* smoothing steps on the point graph: the width of the fuzzy band (default 3) */
    size_t min_regions; /* stop coarsening at this many regions or fewer (default 2) */
    int threads;
    spr_progress progress;
} spr_decomp_desc;
void spr_decomp_defaults(spr_decomp_desc *d);

/* The levels: basis[l] is n × regions[l], level 0 the coarsest ([R]'s
 * numbering); entries ≥ 0 and every row sums to 1 (a partition of unity). */
typedef struct spr_decomp {
    int levels;
    size_t n;
    size_t *regions;
    spr_csr *basis;
    double ms_analysis, ms_coarsen, ms_basis;
} spr_decomp;
spr_result spr_decompose(const spr_cloud *c, const spr_decomp_desc *d, spr_decomp *out, spr_error *err);
void spr_decomp_free(spr_decomp *d);

/* §7.3: strict domains, domain[p] = the j with the largest φ_j(p) (ties: the
 * lowest j); the domains as out = regions × n with the points of region j
 * in row j (values φ_j): φ_j(p) ≥ K (thresholded) or j = domain[p] (strict). */
void spr_domain_strict(const spr_csr *basis, int32_t *domain);
spr_result spr_domain_members(const spr_csr *basis, int strict, double K, spr_csr *out, spr_error *err);

/* §7.4: the support rectangle of a domain (polygon.c). */
typedef struct spr_polygon {
    double centroid[3];          /* weighted centroid, the rectangle's origin */
    double normal[3], u[3], v[3]; /* plane normal and rectangle axes, orthonormal, v = n × u */
    double umin, umax, vmin, vmax; /* the rectangle in (u, v) about the centroid, enlarged */
    double error, error_norm;    /* mean |point − projection|, and over the mean radius */
    double flatness;             /* weighted λ0/(λ0+λ1+λ2): the domain's curvature measure (§7.6) */
    size_t points;
} spr_polygon;
/* The m points idx[·] with weights phi[·] (NULL: 1); enlarge 0.05 = 5%;
 * with_radii: grow each projection by its radius. */
spr_result spr_support_polygon(const spr_cloud *c, const uint32_t *idx, const double *phi, size_t m, double enlarge, int with_radii,
                               spr_polygon *out, spr_error *err);

/* §7.6: merge thresholded domains (φ ≥ K) greedily by shared points while
 * both are flatter than `flat` and their normals' dot exceeds `dot`; out
 * is the merged basis (columns summed: still a partition of unity). */
spr_result spr_domain_merge(const spr_cloud *c, const spr_csr *B, double K, double flat, double dot, spr_csr *out, size_t *merges,
                            spr_error *err);

/* §7.5: textures (texture.c). */
typedef enum spr_rbf { SPR_RBF_CONSTANT = 0, SPR_RBF_LINEAR, SPR_RBF_GAUSS } spr_rbf;
typedef enum spr_rbf_norm { SPR_NORM_GE1 = 0, SPR_NORM_GT0 } spr_rbf_norm; /* [R] Eq. 3.3, Eq. 3.4 */
typedef struct spr_texture_desc {
    double texel_factor;  /* texel side = factor × the domain's mean radius (default 1) */
    double width;         /* radial support w·r_p (default 1) */
    spr_rbf shape;
    spr_rbf_norm normalize;
    int extend_color;     /* texels no point reaches take the nearest point's colour */
} spr_texture_desc;
typedef struct spr_texture {
    int w, h;             /* texels along u and v */
    double texel;         /* texel side in model units */
    float *rgba;          /* w·h·4: colour and alpha (= the basis function); row 0 at vmin */
} spr_texture;
/* The texel side (texel_factor × the domain's mean radius) and the texels
 * along u and v of a domain's texture on its support rectangle pg, as
 * doubles (one texture holds at most 2^24 texels: SPR_E_TOO_LARGE above). */
spr_result spr_texture_size(const spr_cloud *c, const uint32_t *idx, size_t m, const spr_polygon *pg, const spr_texture_desc *td,
                            double *texel, double *w, double *h, spr_error *err);
/* The radial texture of a domain (points idx, basis values phi) on its
 * support rectangle pg. */
spr_result spr_texture_radial(const spr_cloud *c, const uint32_t *idx, const double *phi, size_t m, const spr_polygon *pg,
                              const spr_texture_desc *td, spr_texture *out, spr_error *err);
void spr_texture_free(spr_texture *t);
/* The linear affine texture (affine.c): qhull's Delaunay triangulation of
 * the projections without edges longer than the sum of their endpoints'
 * radii, barycentric colour and basis inside the triangles, the radial
 * linear texture (Eq. 3.4, width 1) elsewhere; *triangles kept. */
spr_result spr_texture_affine(const spr_cloud *c, const uint32_t *idx, const double *phi, size_t m, const spr_polygon *pg,
                              const spr_texture_desc *td, spr_texture *out, size_t *triangles, spr_error *err);

/* §7.3–7.5, §7.7: the domain primitives of one level (prims.c). */
typedef struct spr_prims_desc {
    int strict;            /* strict domains (argmax) instead of thresholded */
    double K;              /* thresholded: φ ≥ K (default 0.01) */
    double enlarge;        /* rectangles grown by this fraction (default 0.05) */
    spr_texture_desc tex;  /* default: linear radial, width 1, texel 1, Eq. 3.4 */
    int affine;            /* linear affine textures (qhull) instead of radial */
    double nbr_ratio;      /* neighbours: shared points above this fraction of either domain (default 0.05) */
    int threads;
} spr_prims_desc;
void spr_prims_defaults(spr_prims_desc *d);
typedef struct spr_prims_stats {
    size_t polygons, texels, triangles, neighbour_pairs;
    double error, error_norm;  /* means over the polygons */
    double points;             /* mean points per polygon */
    double ms;
} spr_prims_stats;
/* One rectangle per domain of B with at least 3 points and a proper plane,
 * in domain order (spr_rects.i[DOMAIN] = the region number). */
spr_result spr_domain_prims(const spr_cloud *c, const spr_csr *B, const spr_prims_desc *d, spr_rects *out, spr_prims_stats *st,
                            spr_error *err);

#endif
