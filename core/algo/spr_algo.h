/* spr_algo.h — the rendering algorithms, written once over spr_backend.
 *
 * spr_render() runs one algorithm as a sequence of named passes, calls the
 * pass hook after each (dumps, traces: SPEC §8) and returns the final image.
 * The algorithms form one registry (SPR_ALGO_LIST, algo_registry.c): its
 * name, a one-line summary, the SPEC section, the options it uses and the
 * function that issues its passes (algo_<name>.c).  Help text, `info`,
 * `bench`, `parity` and `reference` iterate the registry; a new algorithm is
 * one row and one file (docs/architecture.md, "add an algorithm").
 */
#ifndef SPR_ALGO_H
#define SPR_ALGO_H

#include "spr_backend.h"
#include "spr_group.h"

/* Options of spr_render_desc an algorithm reads (the CLI rejects the others). */
enum {
    SPR_USES_KERNEL  = 1u << 0,  /* kernel */
    SPR_USES_EPS     = 1u << 1,  /* eps */
    SPR_USES_GROUPS  = 1u << 2,  /* groups */
    SPR_USES_VORONOI = 1u << 3,  /* voronoi, and lowres_n with it */
    SPR_USES_LOWRES  = 1u << 4,  /* lowres_n without Voronoi (low-precision depth culling) */
    SPR_USES_ORDER   = 1u << 5,  /* order: back to front by BSP or by sorting */
    SPR_USES_ALPHA   = 1u << 6,  /* alpha: one opacity for every splat */
    SPR_USES_SHADE   = 1u << 7,  /* shade: deferred Phong shading (SPEC 4.3) */
    SPR_USES_ENV     = 1u << 8,  /* shade.env: environment effects (SPEC 6.3) */
    SPR_USES_LAYERS  = 1u << 9,  /* layers: depth-peeling layers (SPEC 6.4) */
    SPR_USES_RECTS   = 1u << 10, /* rects, sampling: domain primitives (SPEC 7.7) */
    SPR_USES_ALPHAREF = 1u << 11, /* alpha_ref: the overlap method's lock threshold (SPEC 7.7) */
    SPR_USES_GAUSS   = 1u << 12  /* gauss_aa, gauss_profile: the Gaussian splatting references (SPEC 10) */
};

/* Back-to-front order of the transparent algorithms (SPEC §6.1). */
typedef enum spr_order {
    SPR_ORDER_BSP = 0,   /* BSP traversal, far child first ([ZP] §5.2.1, SPEC §5.6) */
    SPR_ORDER_SORT       /* all centres sorted by view depth, farthest first (ties: index) */
} spr_order;

/* The registry: X(ENUM, function, "name", uses, SPEC section, summary).  Row order is
 * the order parity, bench and reference run them; row 0 is the default. */
#define SPR_ALGO_LIST(X)                                                                                      \
    X(DEFERRED, deferred, "deferred", SPR_USES_KERNEL | SPR_USES_EPS | SPR_USES_GROUPS | SPR_USES_VORONOI | SPR_USES_SHADE, "4.2", \
      "1+1-pass deferred blending: one target per group, then the eps-composite ([ZP] 3.2)")                  \
    X(PBR2P1, pbr2p1, "pbr2p1", SPR_USES_KERNEL | SPR_USES_EPS | SPR_USES_SHADE, "4.1",                                   \
      "standard 2+1-pass splatting: visibility, additive blend, normalise ([ZP] 3.1)")                       \
    X(ZBUFFER, zbuffer, "zbuffer", 0, "3.3", "no blending: the nearest splat's colour per pixel (the aliasing baseline)")          \
    X(TRANSPARENT1, transparent1, "transparent1", SPR_USES_EPS | SPR_USES_GROUPS | SPR_USES_LOWRES | SPR_USES_ORDER | SPR_USES_ALPHA, "6.1",  \
      "transparent surfaces, Algorithm-1: per group back to front, `over` with z-tilde culling, average ([ZP] 3.3)")     \
    X(TRANSPARENT2, transparent2, "transparent2",                                                                                           \
      SPR_USES_KERNEL | SPR_USES_EPS | SPR_USES_GROUPS | SPR_USES_VORONOI | SPR_USES_LOWRES | SPR_USES_ORDER | SPR_USES_ALPHA | \
          SPR_USES_SHADE | SPR_USES_ENV,                                                                                    \
      "6.2", "transparent surfaces, Algorithm-2: nearest layer blended opaque, the others back to front, alpha_F mix ([ZP] 3.3)") \
    X(DEPTHPEEL, depthpeel, "depthpeel", SPR_USES_KERNEL | SPR_USES_EPS | SPR_USES_ALPHA | SPR_USES_LAYERS, "6.4",                      \
      "depth peeling, the transparency reference: L pbr2p1 layers, each beyond the last, blended back to front ([ZP] 6.3)") \
    X(DOMAIN_BLENDALL, domain_blendall, "domain-blendall", SPR_USES_RECTS, "7.7",                                         \
      "domain primitives, every fragment summed, no depth test ([R] 4.4)")                                                 \
    X(DOMAIN_NOBLEND, domain_noblend, "domain-noblend", SPR_USES_RECTS, "7.7",                                            \
      "domain primitives, plain depth test, opaque: the nearest texel's colour ([R] 4.4)")                                \
    X(DOMAIN_TWOPASS, domain_twopass, "domain-twopass", SPR_USES_RECTS | SPR_USES_EPS, "7.7",                             \
      "domain primitives, depth pass offset by eps, then fragments within it summed ([R] 4.4.2)")                          \
    X(DOMAIN_DARKBACK_HARD, domain_darkback_hard, "domain-darkback-hard", SPR_USES_RECTS, "7.7",                          \
      "domain primitives back to front: front faces add, back faces reset to black ([R] 4.4.3)")                         \
    X(DOMAIN_DARKBACK_SOFT, domain_darkback_soft, "domain-darkback-soft", SPR_USES_RECTS, "7.7",                          \
      "domain primitives back to front: front faces add, back faces subtract alpha, clamped at 0 ([R] 4.4.3)")           \
    X(DOMAIN_OVERLAP, domain_overlap, "domain-overlap", SPR_USES_RECTS | SPR_USES_ALPHAREF, "7.7",                        \
      "domain primitives front to back with their neighbours, pixels locked by depth where alpha >= ref ([R] 4.4.4)")    \
    X(DOMAIN_PREFIX, domain_prefix, "domain-prefix", SPR_USES_RECTS, "7.7",                                               \
      "domain primitives: per-pixel fragment lists sorted, the front-most and its neighbours summed (the exact [R] 4.4)") \
    X(GAUSS3D, gauss3d, "gauss3d", SPR_USES_GAUSS, "10.4",                                                                 \
      "3D Gaussian splatting's training rasterizer: 16x16 tiles, depth-sorted lists, front to back (0.99 cap, 1/255 skip, 1e-4 stop)") \
    X(GAUSS2D, gauss2d, "gauss2d", SPR_USES_GAUSS, "10.5",                                                                 \
      "2D Gaussian splatting's surfel rasterizer: each tile's list, ray-disk hits with the screen low-pass, front to back") \
    X(GAUSS_BLEND, gauss_blend, "gauss-blend", SPR_USES_GAUSS, "10.7",                                                     \
      "the viewers' image: every Gaussian once as a screen-space ellipse, farthest first, premultiplied over")

typedef enum spr_algo {
#define SPR__ALGO_ENUM(e, fn, name, uses, spec, summary) SPR_ALGO_##e,
    SPR_ALGO_LIST(SPR__ALGO_ENUM)
#undef SPR__ALGO_ENUM
    SPR_ALGO__COUNT
} spr_algo;

struct spr__run;
typedef struct spr_algo_info {
    const char *name;
    unsigned uses;           /* SPR_USES_* */
    const char *spec;        /* SPEC section */
    const char *summary;     /* one line */
    spr_result (*run)(struct spr__run *run, int *final_target); /* issues the passes */
} spr_algo_info;
/* Row a of the registry (NULL when a is not an algorithm). */
const spr_algo_info *spr_algo_info_of(spr_algo a);

/* ---- Gaussian renderer profiles (SPEC §10.9; core/algo/gauss_profile.c) ----
 * A profile is one row of named rules: the image one renderer means to draw,
 * as parameters of the shared arithmetic (arith/gauss.h) and of the host's
 * sort and colours.  gauss3d (tile lists, front to back, a stop) and
 * gauss-blend (one global order, each Gaussian drawn once) are the two
 * skeletons a profile fills in; gauss2d takes the rules of a gauss3d row that
 * apply to it (cull, α, stop).  Adding a renderer is adding a row. */
typedef enum spr_gauss_comp {
    SPR_GCOMP_OPTION = 0,  /* compensation only with --gauss-aa (the renderer's option, off by default) */
    SPR_GCOMP_ALWAYS       /* always on (--gauss-aa changes nothing) */
} spr_gauss_comp;
typedef enum spr_gauss_comp_form {
    SPR_GCOMP_ROOT_OF_MAX = 0,  /* o·√(max(f, det₀/det)): the floor under the root */
    SPR_GCOMP_MAX_OF_ROOT       /* o·max(f, √(det₀/det)): the floor on the factor */
} spr_gauss_comp_form;
typedef enum spr_gauss_extent {
    SPR_GEXT_SQUARE = 0,   /* r = ceil(k·√λmax), λ from max(λfloor, mid² − det); tiles by trunc (inria) */
    SPR_GEXT_AXES,         /* per axis r_a = ceil(k·√Σ'_aa); tiles floor((m − r)/16) … ceil((m + r)/16) (gsplat) */
    SPR_GEXT_QUAD,         /* a screen quad of k·√λ per eigen-axis, each at most cap pixels (the conic then follows
                              the capped axes); cut inside where power < −k²/2 */
    SPR_GEXT_BOX           /* no tiles of its own: the pixel box [floor(m − r) − pad, ceil(m + r) + pad) per axis,
                              r = k·√Σ'_aa (not rounded), clamped to the image; the Gaussian goes into every tile the box
                              touches and pixels outside the box skip it (OpenSplat's CPU rasterizer) */
} spr_gauss_extent;
typedef enum spr_gauss_key {
    SPR_GKEY_TILE_DEPTH = 0, /* per tile, by the float t.z (its bits), ties in file order (gauss3d) */
    SPR_GKEY_DISTANCE,       /* global, |μ − eye| in double, farthest first */
    SPR_GKEY_VIEW_Z,         /* global, the float t.z (the camera-forward depth), farthest first */
    SPR_GKEY_CLIP_INT,       /* global, GaussianSplats3D's integer clip depth (centres to 1/1000) in 2^bits − 1 buckets over the
                                frame's kept [min, max], farthest first (core/algo/gauss.c, spr__gauss_order) */
    SPR_GKEY_TILE_GLDEPTH    /* per tile, by the float OpenGL depth z/w of a projection with the order's znear, zfar:
                                fl(z·fl(1/max(w, 1e-6))), z = ((p₀μx + p₁μy) + p₂μz) + p₃, p_j = fl(a·R₂ⱼ), p₃ = fl(fl(a·t₂) + b),
                                a = fl((f + n)/(f − n)), b = fl((−f·n)/(f − n)), w the float t.z; ties in file order
                                (core/algo/gauss.c, gldepth_keys) */
} spr_gauss_key;
typedef enum spr_gauss_blend {
    SPR_GBLEND_UNDER = 0,  /* front to back: C += c·α·T (the tile loop of gauss3d) */
    SPR_GBLEND_PREMUL,     /* back to front, premultiplied over: dst = c·α + (1 − α)·dst, alpha likewise */
    SPR_GBLEND_STRAIGHT    /* back to front, straight alpha: rgb = c·α + (1 − α)·rgb (GL SRC_ALPHA, ONE_MINUS_SRC_ALPHA),
                              alpha = α + (1 − α)·alpha (ONE, ONE_MINUS_SRC_ALPHA) */
} spr_gauss_blend;

typedef struct spr_gauss_profile {
    const char *name;
    spr_algo skeleton;                 /* SPR_ALGO_GAUSS3D or SPR_ALGO_GAUSS_BLEND */
    const char *renderer, *version, *source; /* the row's citation: whose image, which release or commit, which files */
    struct { float near; int near_lt; float clip_k; int det_le; } cull;
    /* 1. near: culled at t.z ≤ near (near_lt: t.z < near); clip_k > 0: also culled when |x/w| or |y/w| > clip_k in
     *    clip space; det_le: a dilated det ≤ 0 culled (else det == 0) */
    int tan_clamp;                     /* 2. the Jacobian's tangents clamped: 0 no; 1 at ±1.3·tan(fov/2) (inria); 2 at
                                          [−(cx/fx + 0.3·tan), (W − cx)/fx + 0.3·tan] (gsplat: the principal point) */
    struct { float eps2d; spr_gauss_comp when; spr_gauss_comp_form form; float floor; } dilation; /* 3. (eps2d in px²) */
    struct { spr_gauss_extent kind; double k2; float cap_px; int cap_view; float lambda_min; int falloff; float min_px; float pad_px; } extent;
    /* 4. k2: the extent in standard deviations, squared (9 for 3σ, 8 for the viewers' √8σ): k = sqrt(k2) rounded once,
     *    and gauss-blend cuts at power < −k2/2; lambda_min: the floor under sqrt(mid² − det) of the eigenvalues; quad: half-axes k·√λ at most cap_px pixels
     *    (cap_view: and at most min(W, H)), the falloff following the quad (the conic from its axes); falloff:
     *    e^power renormalised to reach 0 at the cut, (e^power − e^−cut)/(1 − e^−cut); min_px > 0: dropped when both
     *    half-axes are shorter than min_px pixels; pad_px: SPR_GEXT_BOX's margin in whole pixels */
    struct { float cap; float floor; } alpha;   /* 5. α = min(cap, o·e^power) (cap 1: none); skipped below floor (0: none) */
    struct { float t_min; int le; } stop;       /* 6. stop when T·(1 − α) < t_min (le: ≤); t_min 0: no stop */
    struct { spr_gauss_key key; int bits; float znear, zfar; } order; /* 7. (znear, zfar: SPR_GKEY_TILE_GLDEPTH's projection) */
    spr_gauss_blend blend;                      /* 8. */
    struct { int sh_max; int dc8; int op8; int post8; int clamp_hi; int scale8; int pos16; } colour;
    /* 9. SH degree used at most; dc8: DC + 0.5 stored in 8 bits before the SH sum, op8: the opacity, post8: the
     *    colour after the sum (SPR_Q8_* of spr_cloud.h: none, round, floor); clamp_hi: the colour clamped to [0, 1]
     *    after the sum (always ≥ 0); scale8: σ stored in a log 8-bit code (SPR_GSCALE8_*); pos16: the centre stored
     *    as half floats, absolute then relative to the eye (Spark: μ' = eye + h(h(μ) − eye), h the nearest half) */
    struct { int trains; int gate; int tclamp; float cap; int tdiv; int half_b; int detach_dirs; } grad;
    /* 10. the backward pass (SPEC 10.10), read at the renderer's backward: trains: it has one (the viewers do not);
     *     gate: no gradient through a capped α (else as if uncapped); tclamp: 0 the clamped tangent's exact
     *     derivative, 1 inria's (the clamped u held constant: J's t.z term twice the exact one); cap > 0: the
     *     backward's own α cap, α_b = min(cap, α) in every backward term (0: the forward's α); tdiv: T recovered
     *     back to front by division, T ← T·(1/(1 − α_b)) from the final T (0: the forward's own T, SPEC 10.10
     *     item 3); half_b: ∂L/∂B of the conic's off-diagonal halved before the chain (the conic's gradient too);
     *     detach_dirs: the SH colour's view direction detached (no ∂L/∂μ through the colour) */
    struct { int centre; } camera;
    /* 11. centre: the principal point ignored, cx = W/2, cy = H/2 (the renderer takes only the focal lengths) */
} spr_gauss_profile;

/* The table: count, row i, the row named name (NULL: none), the names joined by sep. */
int spr_gauss_profile_count(void);
const spr_gauss_profile *spr_gauss_profile_at(int i);
int spr_gauss_profile_from_name(const char *name);
const char *spr_gauss_profile_names(const char *sep);
/* The profile an algorithm runs under: row profile − 1, else (0) the skeleton's default (inria; khr for gauss-blend). */
const spr_gauss_profile *spr_gauss_profile_of(spr_algo algo, int profile);
/* Whether an algorithm takes a profile: its skeleton, or gauss2d with a gauss3d row. */
int spr_gauss_profile_fits(const spr_gauss_profile *p, spr_algo algo);
/* Gaussian G of cloud c as the profile's renderer stores it (rule 9), for a camera at eye, in double, rounded once:
 * its σ in s (given as loaded; scale8: SPR_GSCALE8_SPARK code = 1 + round(clamp((ln σ + 12)/21, 0, 1)·254),
 * σ = e^(−12 + (code − 1)·21/254); SPR_GSCALE8_PLAYCANVAS code = trunc(clamp((ln σ + 12)·255/21 + 0.5, 1, 255)), 0 below
 * 1e-10, σ = e^(code·21/255 − 12)), its centre in mu (pos16: eye + h(h(μ) − eye), h the nearest half float) and its
 * opacity in *o (op8).  spr_gauss_profile_stores: whether any of the three changes anything. */
enum { SPR_GSCALE8_NONE = 0, SPR_GSCALE8_SPARK, SPR_GSCALE8_PLAYCANVAS };
int spr_gauss_profile_stores(const spr_gauss_profile *p);
void spr_gauss_profile_store(const spr_gauss_profile *p, const spr_cloud *c, size_t G, const double eye[3], float s[3], float mu[3], float *o);

int spr_algo_from_name(const char *name);  /* −1 if unknown */
const char *spr_algo_name(spr_algo a);
/* "deferred | pbr2p1" — the names joined by sep, for help and errors. */
const char *spr_algo_names(const char *sep);

/* What the hook sees after a pass. */
typedef struct spr_pass_info {
    int index;                    /* 0-based, in execution order */
    const char *name;             /* "visibility", "blend", "normalize", "geometry", "composite" */
    int group;                    /* k of a geometry pass, the rectangle of a domain-overlap pass, −1 otherwise */
    const spr_pass_state *state;  /* NULL for compositing passes */
    int target;                   /* the target the pass wrote */
    spr_draw_stats stats;
    double ms;
    const float *records;         /* a Gaussian preprocessing pass: its records (SPR_GREC_FLOATS each), else NULL */
    size_t n_records;
} spr_pass_info;
typedef void (*spr_pass_hook)(void *user, spr_backend *b, const spr_pass_info *info);

/* Every plane of every pass kept in memory: render with hook =
 * spr_capture_hook and hook_user = a zeroed spr_capture (as_float set:
 * planes as floats, ids none = −1, spr_backend_read_plane_f; otherwise the
 * raw values); failed and err say when a read failed. */
typedef struct spr_captured_pass {
    char name[32];
    int index, group, target;
    int composite;               /* a composite pass (no state) */
    spr_pass_state state;
    spr_draw_stats stats;
    double ms;
    unsigned planes;             /* the planes the pass's target has */
    void *plane[SPR_PLANE__COUNT];
    float *records;              /* a copy of the pass's records (spr_pass_info.records), or NULL */
    size_t n_records;
} spr_captured_pass;
typedef struct spr_capture {
    int as_float;
    spr_captured_pass *passes;
    int n, cap;
    int failed;
    spr_error err;
} spr_capture;
void spr_capture_hook(void *user, spr_backend *b, const spr_pass_info *info);
void spr_capture_free(spr_capture *c);

/* Deferred shading and environment effects (SPEC §4.3, §6.3). */
typedef enum spr_shade_model { SPR_SHADE_NONE = 0, SPR_SHADE_PHONG } spr_shade_model;
typedef struct spr_shading {
    spr_shade_model model;
    double light_eye[3];       /* direction towards the light, eye space (normalised on use); 0 = default */
    double ka, kd, ks;         /* material coefficients */
    int exponent;              /* specular exponent, 1 … 1024 */
    const spr_envmap *env;     /* environment cube map; NULL = no environment effects */
    double eta[3];             /* refraction ratio per channel (outside/inside) */
    int multilayer;            /* 1: eta^(l+1) (Eq. 16), 0: one interface */
} spr_shading;
/* The defaults: no shading, light from the upper left in front, ka 0.2,
 * kd 0.8, ks 0.4, exponent 32, glass-like eta (1/1.49, 1/1.50, 1/1.52),
 * multi-layer on. */
void spr_shading_defaults(spr_shading *s);

typedef struct spr_render_desc {
    spr_algo algo;
    spr_kernel kernel;
    int voronoi;                 /* deferred: Voronoi test value (§3.3) */
    double eps;                  /* world units; 0 = 2 × mean splat radius */
    double lowres_n;             /* 0 = derived from ε (§3.3) */
    float background[3];
    const spr_groups *groups;    /* deferred, transparent1; NULL = one group */
    spr_order order;             /* transparent1: back-to-front order */
    const struct spr_bsp *bsp;   /* order BSP: the cloud's tree, built once and kept across frames ([ZP] §5.2.1:
                                    preprocessing); NULL: built for the frame */
    float alpha;                 /* transparent1: > 0 replaces every splat's opacity */
    spr_shading shade;           /* SPEC 4.3, 6.3 (zero: none) */
    int layers;                  /* depthpeel: L ≥ 1 (0 = 8) */
    const spr_rects *rects;      /* domain-*: the domain primitives (SPEC 7.7) */
    spr_sampling sampling;       /* domain-*: texture sampling (nearest, linear = explicit bilinear) */
    float alpha_ref;             /* domain-overlap: pixels locked where alpha >= alpha_ref (0 = 0.1) */
    int gauss_aa;                /* gauss*: the antialiased opacity of SPEC 10.3 step 5 (--gauss-aa) */
    int gauss_profile;           /* gauss*: the renderer profile (--gauss-profile), 1 + its row of the table; 0 (a zeroed
                                    desc): the skeleton's default (inria for gauss3d and gauss2d, khr for gauss-blend) */
    spr_pass_hook hook;
    void *hook_user;
    spr_progress progress;       /* one report per finished pass ("frame: pass 3 geometry"), cleared at the end */
    const spr_cloud_source *source; /* not NULL: the cloud is read chunk by chunk from here for every draw (`--stream`),
                                       and spr_render's `cloud` only gives n; algorithms that need the whole cloud
                                       (an order, domain primitives) are refused */
} spr_render_desc;

typedef struct spr_pass_record {
    char name[32];
    int group;
    spr_draw_stats stats;
    double ms;
} spr_pass_record;

typedef struct spr_render_result {
    float *rgba;         /* W·H·4: final colour, alpha 1 where covered; row 0 = bottom */
    int width, height;
    float eps_t;
    spr_lowres lowres;
    int K;
    int n_passes;
    spr_pass_record *passes;
} spr_render_result;

/* Run desc->algo for `cloud` seen through `view` on backend b. */
spr_result spr_render(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc,
                      spr_render_result *out, spr_error *err);
void spr_render_result_free(spr_render_result *r);
/* SPR_OK when a frame of desc->algo over `cloud` is within b's fixed limits (spr_backend_fits), else one line
 * naming the backend and the limit.  spr_render asks it first; parity asks the tested backend before the
 * reference renders, so a capture too large for it is refused at once. */
spr_result spr_render_fits(spr_backend *b, const spr_cloud *cloud, spr_algo algo, spr_error *err);
/* SPR_OK when `algo` can draw a streamed cloud of n splats (desc->source):
 * its passes draw the splats in file order; otherwise one line saying why
 * and what the whole cloud would take. */
spr_result spr_stream_check(spr_algo algo, size_t n, spr_error *err);

/* ---- internal: shared by the algorithm files ---- */
typedef struct spr__run {
    spr_backend *b;
    const spr_cloud *cloud;
    const spr_render_desc *desc;
    spr_render_result *out;
    spr_error *err;
    float eps_t;
    spr_lowres lowres;
    int pass_cap;
    float prm[SPR_PRM_COUNT];  /* shading parameters (SPR_PARAM_LIST) */
    int use_prm;               /* composites get prm (shading or environment asked for) */
    spr_cloud chunk;           /* --stream: the chunk being drawn */
    uint32_t *local;           /* --stream: a draw's indices within the chunk */
} spr__run;
spr_result spr__run_draw(spr__run *run, const char *name, int group, int target, const spr_draw_desc *d);
/* n draws into n distinct targets, recorded as n passes in order (the same
 * as n spr__run_draw calls; a streamed cloud is then read once for all). */
spr_result spr__run_draws(spr__run *run, const char *name, const int *group, const int *target, const spr_draw_desc *d, int n);
spr_result spr__run_composite(spr__run *run, const char *name, const spr_composite_desc *c);
/* A rectangle draw recorded as pass `name`; group: the rectangle a pass is about (overlap), −1 otherwise. */
spr_result spr__run_rects(spr__run *run, const char *name, int group, int target, const spr_rect_draw_desc *d);
/* The radius scale of group k's draw ([ZP] §4.4.2 enlarged radii; 0: none). */
float spr__group_radius_scale(const spr_groups *g, int k);
/* The last pass of a K-group algorithm: composite op over I[0 … K−1] into
 * I[K] with the background, recorded as "composite"; sets the final target. */
spr_result spr__run_finish(spr__run *run, spr_composite_op op, const int *I, int K, int *final_target);
/* A composite desc of op over inputs into output, with the run's ε_t,
 * background, shading parameters and cube map. */
spr_composite_desc spr__run_comp(const spr__run *run, spr_composite_op op, const int *inputs, int n, int output);
/* Planes the geometry passes write beyond colour: the normal plane when shading. */
unsigned spr__run_normal_planes(const spr__run *run);
/* Target of `planes` for the run, failures named after the algorithm. */
spr_result spr__run_target(spr__run *run, unsigned planes, int *target);
/* Passes shared by algorithms: the opaque geometry pass of §4.2 into I[0 … K−1]
 * (extra: more planes to write), and the back-to-front pass of §6.1 into
 * O[0 … K−1] (mask ≥ 0: drop fragments within that target's nearest layer). */
spr_result spr__deferred_geometry(spr__run *run, const int *I, unsigned extra);
spr_result spr__transparent_geometry(spr__run *run, const int *O, int mask);
/* The Gaussian algorithms' passes (core/algo/gauss.c): "preprocess" (the
 * backend's records, recorded with them), "sort" (host: the tiles' lists,
 * or gauss-blend's order), then the rasterization. */
spr_result spr__gauss_run(spr__run *run, int mode, int *final_target);
/* What a Gaussian frame holds between its passes: the preprocessing's inputs (gd, with the arrays it points to), the
 * records, gauss3d's and gauss2d's tile lists or gauss-blend's order, the profile.  spr__gauss_prepare runs
 * "preprocess" and "sort" (freeing everything when it fails), spr__gauss_raster_frame the rasterization into a new
 * target; spr__gauss_run the whole frame; the backward pass (gauss_grad.c) starts from the same frame. */
typedef struct spr__gauss_frame_st {
    spr_gauss_desc gd;
    float *q, *s, *col, *mu, *op, *rec;
    uint32_t *range, *list, *order;
    size_t count;
    const spr_gauss_profile *pf;
} spr__gauss_frame_st;
spr_result spr__gauss_prepare(spr__run *run, int mode, spr__gauss_frame_st *f);
spr_result spr__gauss_raster_frame(spr__run *run, int mode, const spr__gauss_frame_st *f, int *target);
void spr__gauss_frame_free(spr__gauss_frame_st *f);
/* mode: 0 gauss3d, 1 gauss2d, 2 gauss-blend.  The cloud's Gaussians (its own, or each surfel flat with σ a third of
 * its radii), n·4 quaternions and n·3 scales; the tiles' sorted lists (range GX·GY + 1, list); gauss-blend's order. */
spr_result spr__gauss_of_cloud(const spr_cloud *c, float *q, float *s);
/* A frame's parameters (SPR_GPRM_COUNT floats) for view v, mode 0 (3D) or 1 (2D), desc's --gauss-aa and profile pf. */
void spr__gauss_frame(const spr_view *v, int mode, const spr_render_desc *desc, const spr_gauss_profile *pf, float *g);
spr_result spr__gauss_tiles(const float *rec, size_t n, int gx, int gy, int threads, uint32_t **range, uint32_t **list, spr_error *err);
/* The same with each Gaussian's 32-bit key in keys (NULL: its record's float t.z), ties in file order. */
spr_result spr__gauss_tiles_keyed(const float *rec, const uint32_t *keys, size_t n, int gx, int gy, int threads, uint32_t **range,
                                  uint32_t **list, spr_error *err);
spr_result spr__gauss_order(const float *rec, const spr_cloud *c, const double eye[3], const double zrow[3], spr_gauss_key key, int bits,
                            uint32_t **order, size_t *count, spr_error *err);
/* The Gaussian passes, recorded: preprocessing (with its records), a host pass (no target), rasterization, a draw. */
spr_result spr__run_gauss_preprocess(spr__run *run, const spr_gauss_desc *d, float *rec);
spr_result spr__run_host_pass(spr__run *run, const char *name, const spr_draw_stats *st, double ms);
spr_result spr__run_gauss_raster(spr__run *run, const char *name, int target, const spr_gauss_raster_desc *d);
spr_result spr__run_gauss_draw(spr__run *run, const char *name, int target, const spr_gauss_draw_desc *d);
/* The algorithms of the registry, one file each. */
#define SPR__ALGO_DECL(e, fn, name, uses, spec, summary) spr_result spr__algo_##fn(spr__run *run, int *final_target);
SPR_ALGO_LIST(SPR__ALGO_DECL)
#undef SPR__ALGO_DECL

#endif
