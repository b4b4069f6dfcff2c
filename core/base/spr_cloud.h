/* spr_cloud.h — the splat cloud (SPEC §1).
 *
 * Structure of arrays, one entry per splat, in submission order (the input
 * order is the order every backend draws in, SPEC §3.4).  Invariants after
 * spr_cloud_validate(): every value is finite, normals have unit length
 * (renormalised in double), radii are > 0, colours and opacity lie in [0,1].
 */
#ifndef SPR_CLOUD_H
#define SPR_CLOUD_H

#include <stddef.h>
#include <stdint.h>
#include "spr_result.h"

/* Where the cloud's attributes came from (reported by `splatref info`). */
typedef enum spr_source_flags {
    SPR_SRC_NORMALS = 1u << 0,  /* normals read from the file */
    SPR_SRC_COLORS  = 1u << 1,  /* colours read from the file */
    SPR_SRC_RADII   = 1u << 2,  /* radii read from the file */
    SPR_SRC_ALPHA   = 1u << 3,  /* opacity read from the file */
    SPR_SRC_FACES   = 1u << 4   /* normals from mesh faces */
} spr_source_flags;

typedef struct spr_cloud {
    size_t n;
    float *pos;     /* 3n: x y z */
    float *nrm;     /* 3n: unit normal */
    float *radius;  /* n */
    float *color;   /* 3n: r g b in [0,1] */
    float *alpha;   /* n: opacity in [0,1] */
    float *ell;     /* 4n or NULL (every splat circular): elliptical splats (SPEC §1, issue 15) —
                     * u, the unit major tangent axis (⟂ n), then r_v, the minor radius, in
                     * (0, radius]; radius is the major radius r_u, the splat's bounding radius.
                     * A splat with r_v == radius is a circle (u unused). */
    float *sh;      /* n·sh_k·3 or NULL: a Gaussian capture's spherical-harmonics coefficients per
                     * splat, coefficient-major, r g b each (k = 0 the DC term), for colours that
                     * depend on the view (spr_cloud_sh_colors, --sh-degree) */
    int sh_k;       /* coefficients per channel: (degree + 1)², 0 without sh; a Gaussian capture keeps at
                     * least its DC term (sh_k ≥ 1), the colour of SPEC §10.3 step 9 before any clamp */
    float *gauss;   /* SPR_GAUSS_FLOATS·n or NULL: a Gaussian capture's own Gaussians (SPEC §10.1), beside the
                     * surfel view above — the unit quaternion w x y z (normalised in double, rounded once),
                     * then σ along the local x, y, z axes (linear; a 2D Gaussian's third σ is 0), then the
                     * quaternion's norm as the file gave it (the backward's ∂L/∂q is for the quaternion as
                     * given, SPEC 10.10; 0: unknown, taken as 1) */
    int gauss_aa;   /* the file says its Gaussians were trained antialiased (.spz flag; --gauss-aa) */
    float gauss_cut; /* > 0: a Gaussian-splat capture, its radii gauss_cut × σ (--gauss-cut): the gauss
                      * kernel then weighs by the file's σ (spr_draw_kernel_scale); 0: not a capture */
    unsigned flags; /* spr_source_flags */
} spr_cloud;

/* Floats per Gaussian of spr_cloud.gauss: q (w x y z), σ (x y z), |q| as given. */
#define SPR_GAUSS_FLOATS 8

/* Every per-splat array of spr_cloud with its floats per splat (c the cloud): the one list that
 * spr_cloud_view and spr_cloud_free walk.  A new per-splat array goes here; cloud.c's static
 * assert on the struct's size fails until it does. */
#define SPR_CLOUD_ARRAYS(X, c)                                                                     \
    X(pos, 3) X(nrm, 3) X(radius, 1) X(color, 3) X(alpha, 1) X(ell, 4) X(sh, (size_t)(c)->sh_k * 3) \
    X(gauss, SPR_GAUSS_FLOATS)

/* Splats [first, first + m) of c as a cloud of its own that shares c's memory: every per-splat
 * array (SPR_CLOUD_ARRAYS) advanced to splat `first`, a NULL array left NULL, the rest of c
 * copied.  first + m ≤ c->n.  Never free a view; write through it to fill c piece by piece. */
spr_cloud spr_cloud_view(const spr_cloud *c, size_t first, size_t m);

/* Allocate n splats (normals +z, colour 0.8, alpha 1, radius 0); 0 or SPR_E_NOMEM. */
spr_result spr_cloud_alloc(spr_cloud *c, size_t n);
/* Give c its ellipse array, every splat a circle (u = 0, r_v = radius): 0 or SPR_E_NOMEM. */
spr_result spr_cloud_alloc_ell(spr_cloud *c);
/* Colours of a cloud with sh for a camera at eye (world space), into
 * color (3n): for every splat c = 0.5 + Σ_k Y_k(dir)·sh_k, dir the unit
 * vector from the eye to its centre — or, for an orthographic camera
 * (view_dir not NULL), the viewing direction itself, the same for every
 * splat — in double, clamped to [0,1] and rounded once.  spr_render calls
 * it once per frame, on the host, so every backend gets the same bits. */
void spr_cloud_sh_colors(const spr_cloud *c, const double eye[3], const double *view_dir, float *color);
/* The same evaluation for the Gaussian algorithms (SPEC §10.3 step 9):
 * max(0, 0.5 + Σ_k Y_k(dir)·sh_k), not clamped above 1, dir always from the
 * eye; a cloud without sh gives its colours.  In double, rounded once. */
void spr_cloud_gauss_colors(const spr_cloud *c, const double eye[3], float *color);
/* The same under a renderer profile's colour rule (SPEC §10.9 rule 9): at most SH degree sh_max; dc8: the DC part
 * (0.5 + Y_0·sh_0) stored in 8 bits before the rest is added; post8: the final colour stored in 8 bits; clamp_hi:
 * the sum clamped to 1 as well as to 0.  dc8 and post8 are SPR_Q8_* modes. */
void spr_cloud_gauss_colors_as(const spr_cloud *c, const double eye[3], int sh_max, int dc8, int post8, int clamp_hi, float *color);
/* The backward of spr_cloud_gauss_colors_as for Gaussian i (SPEC 10.10; a training profile: no 8-bit storage, no
 * clamp above): given vc = ∂L/∂colour, vsh (3 per coefficient, K = min(sh_k, (sh_max + 1)²)) = Y_k(dir)·vc where
 * the colour's max(0, ·) does not clamp, and vmu = ∂L/∂μ through the view direction, dir = (μ − eye)/|μ − eye|.
 * In double. */
void spr_cloud_gauss_colors_bwd(const spr_cloud *c, const double eye[3], int sh_max, size_t i, const float vc[3], double *vsh, double vmu[3]);
/* A viewer's 8-bit storage of x in [0, 1] (clamped): SPR_Q8_NONE x itself, SPR_Q8_ROUND the nearest k/255,
 * SPR_Q8_FLOOR floor(x·255)/255, SPR_Q8_HALVED Spark's opacity: k = round(255x), then stored as round(k/2) (halves to
 * even) and read back doubled, 2·round(k/2)/255, at most 1 (in double). */
enum { SPR_Q8_NONE = 0, SPR_Q8_ROUND, SPR_Q8_FLOOR, SPR_Q8_HALVED };
double spr_unorm8(double x, int mode);
/* Splat i's frame as a rotation: the quaternion (w x y z, double) taking (x, y, z) to (u, v, n) — u its major
 * axis (an ellipse's), or for a circle n × the axis of n's smallest component — and its radii along u and v. */
void spr__surfel_frame(const spr_cloud *c, size_t i, double q[4], double *ru, double *rv);
/* Release the arrays; safe on a zeroed cloud. */
void spr_cloud_free(spr_cloud *c);
/* Check every invariant above; names `what` (a file) and the first bad splat. */
spr_result spr_cloud_validate(const spr_cloud *c, const char *what, spr_error *err);
/* The same for a piece of a larger cloud whose splat 0 is splat `first` (messages give that index). */
spr_result spr__cloud_validate_from(const spr_cloud *c, const char *what, size_t first, spr_error *err);
/* What every loaded splat gets once its file's values are in (a whole load
 * or a streamed chunk): colours by normal when c->flags has no colours,
 * opacity (> 0: every splat's, in (0, 1]), then the invariants checked. */
spr_result spr__cloud_finish(spr_cloud *c, const char *path, size_t first, double opacity, spr_error *err);
/* Renormalise normal i in double; SPR_E_VALUE for a zero or non-finite normal. */
spr_result spr__normalize3(float *n);

/* The streaming pass: read every attribute of every splat once (11 floats)
 * on `threads` threads (0: all cores), summing them so nothing is skipped —
 * the physical floor of any per-splat phase, in ms; `splatref bench` reports
 * every phase as a multiple of it.  *sum receives the sum (use it). */
double spr_cloud_stream_ms(const spr_cloud *c, int threads, double *sum);

/* Axis-aligned bounds of the centres and the largest radius. */
typedef struct spr_bounds {
    double lo[3], hi[3];
    double max_radius, mean_radius, min_radius;
} spr_bounds;
void spr_cloud_bounds(const spr_cloud *c, spr_bounds *b);
/* The default world tolerance ε of rendering and grouping: 2 × mean radius
 * [decision], the single definition every caller uses. */
double spr_cloud_default_eps(const spr_cloud *c);
double spr_bounds_default_eps(const spr_bounds *b);
/* Bytes an in-memory cloud of n splats takes (the estimate --stream's errors quote). */
static inline size_t spr_cloud_bytes(size_t n) { return n * 11 * sizeof(float); }

/* The bounds over clouds given piece by piece (a streamed cloud's chunks,
 * in order): the same numbers as spr_cloud_bounds over the whole. */
typedef struct spr_bounds_acc {
    spr_bounds b;
    double sum;
    size_t n;
} spr_bounds_acc;
void spr_bounds_begin(spr_bounds_acc *a);
void spr_bounds_add(spr_bounds_acc *a, const spr_cloud *c);
void spr_bounds_end(const spr_bounds_acc *a, spr_bounds *b);

/* A cloud read in chunks, for clouds larger than memory (`render --stream`):
 * read() fills `out` — allocated by spr_cloud_alloc for `chunk` splats —
 * with splats [first, first + count) exactly as spr_load would hold them
 * (out->n = count), or fails naming the file and the splat.  bounds are the
 * whole cloud's (spr_cloud_source_scan). */
typedef struct spr_cloud_source {
    size_t n;             /* splats in all */
    size_t chunk;         /* splats per read */
    unsigned flags;       /* spr_source_flags */
    spr_bounds bounds;
    spr_result (*read)(void *user, size_t first, size_t count, spr_cloud *out, spr_error *err);
    void *user;
} spr_cloud_source;
/* One pass over the source: every splat read and checked (a bad value fails
 * here, before anything is drawn), the bounds set; when keep is not NULL it
 * receives the centres, normals and radii of every splat (colour and
 * opacity arrays NULL: what grouping reads). */
struct spr_progress;
spr_result spr_cloud_source_scan(spr_cloud_source *src, spr_cloud *keep, const struct spr_progress *progress, spr_error *err);

/* Colour every splat by its normal, c = 0.5·n + 0.5 (used when a file has no
 * colours: flat colours would show only a silhouette without shading). */
void spr_cloud_color_by_normal(spr_cloud *c);

#endif
