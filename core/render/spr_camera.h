/* spr_camera.h — camera, pixels and rays shared by every backend (SPEC §2).
 *
 * The host builds V (gluLookAt) and P (gluPerspective or glOrtho) in double,
 * inverts P·V in double and rounds M = (P·V)^-1 to float once: every backend
 * receives the same float bits (spr_view).  Per-pixel arithmetic lives in
 * spr_fragment.h.
 */
#ifndef SPR_CAMERA_H
#define SPR_CAMERA_H

#include "spr_cloud.h"
#include "spr_result.h"

/* The pinhole camera of the Gaussian algorithms and of the training code
 * (SPEC §10.2): world-to-camera rotation R (row-major) and translation t in
 * OpenCV's axes (x right, y down, z forward), focal lengths and principal
 * point in pixels, continuous coordinates (pixel centres at i + 0.5, row 0
 * at the top). */
typedef struct spr_pinhole {
    double R[9], t[3];
    double fx, fy, cx, cy;
} spr_pinhole;

/* Camera descriptor; zero fields take the defaults of spr_camera_defaults(). */
typedef struct spr_camera_desc {
    double eye[3], target[3], up[3];
    int have_eye, have_target; /* eye/target given even when (0,0,0); a non-zero value counts as given too */
    double fov_deg;       /* vertical field of view, perspective */
    double ortho_height;  /* > 0 selects glOrtho with this height */
    double near_plane, far_plane;
    int width, height;
    /* Raw matrices (a scene as another renderer saw it): V and P row-major in
     * double replace eye/target/up/fov/ortho.  P's bottom row must be
     * (0, 0, −1, 0) (perspective) or (0, 0, 0, 1) (orthographic); near/far,
     * when zero, are the planes P maps to NDC z = −1 and +1. */
    int have_matrices;
    double V[16], P[16];
    /* A pinhole camera (--intrinsics with --world-to-camera, or an entry of
     * the training code's cameras.json) replaces eye/target/up/fov and the
     * matrices; V and P are made from it, near/far framed as ever. */
    int have_pinhole;
    spr_pinhole pinhole;
} spr_camera_desc;

/* What every backend gets: float bits computed once on the host. */
typedef struct spr_view {
    int width, height;
    float M[16];          /* (P·V)^-1, row-major, rounded from double */
    float ndc_sx, ndc_sy; /* 2/W and 2/H as floats: ndc = (x + 0.5)·sx − 1 */
    double PV[16];        /* P·V in double (host-side bounds only) */
    double row_norm[3];   /* |(PV_r0, PV_r1, PV_r2)| of rows x, y, w (bounds of a ball's projection) */
    double V[16];         /* view matrix in double */
    double P[16];         /* projection matrix in double */
    double near_plane, far_plane;
    int ortho;
    spr_pinhole cv;       /* perspective views: the same camera as a pinhole (SPEC §10.2), in double — the desc's own
                             numbers for a pinhole camera, else from V (y and z negated) and P (fx = W/2·P00,
                             cx = W/2·(1 − P02), fy = H/2·P11, cy = H/2·(1 + P12)) */
} spr_view;

/* Defaults: 512×512, fov 30°, up +y; eye/target/near/far 0 = "frame the model". */
void spr_camera_defaults(spr_camera_desc *c);
/* Place eye on the +z side of the bounding sphere of b and set tight near/far
 * for every field the caller did not give (eye/target: neither flagged nor
 * non-zero; near/far: both zero). */
void spr_camera_frame(spr_camera_desc *c, const spr_bounds *b);
/* The eye position of a view matrix: −R^T·t (world space). */
void spr_view_matrix_eye(const double V[16], double eye[3]);
/* The eye position of a pinhole's world-to-camera (R, t): −R^T·t, each component summed left to right. */
void spr_pinhole_eye(const spr_pinhole *p, double eye[3]);
/* Build the view; SPR_E_ARG for a degenerate camera (names the field). */
spr_result spr_view_make(const spr_camera_desc *c, spr_view *v, spr_error *err);
/* A pinhole camera a renderer can use: R a rotation (RᵀR = I within 1e-6,
 * det +1), t finite, fx, fy positive and finite, cx, cy finite; `what`
 * names the camera in the one-line error. */
spr_result spr_pinhole_check(const spr_pinhole *p, const char *what, spr_error *err);
/* The entry whose "id" is `id` of the training code's cameras.json
 * (graphdeco-inria/gaussian-splatting, utils/camera_utils.py: width, height,
 * position, rotation = camera-to-world 3×3 rows, fx, fy; the principal
 * point at the image centre) as a pinhole camera and its image size; an
 * error naming the file and the entry when it is not there or not valid. */
spr_result spr_cameras_json(const char *path, long id, spr_pinhole *p, int *width, int *height, spr_error *err);
/* Every entry of a cameras.json, in the file's order (the order the
 * training code's render.py numbers its images 00000.png, 00001.png, …):
 * its id, its img_name ("" when it has none), its pinhole and image size.
 * Each entry is checked as spr_cameras_json checks one; ids must differ.
 * *out is the caller's to free. */
typedef struct spr_camera_entry {
    long id;
    char img_name[256];
    spr_pinhole pinhole;
    int width, height;
} spr_camera_entry;
spr_result spr_cameras_json_all(const char *path, spr_camera_entry **out, size_t *count, spr_error *err);

/* World tolerance → ray-parameter tolerance: ε/(far − near) in double → float. */
float spr_view_eps_t(const spr_view *v, double eps_world);

/* Low-precision depth parameters of SPEC §3.3 ([ZP] Eq. 10). */
typedef struct spr_lowres {
    float d_min, d_max;  /* depth range of the enlarged box of the centres */
    float n;             /* quantisation steps, as float */
    float inv_n;         /* float nearest to 1.0/n */
} spr_lowres;
/* n_override > 0 fixes n; otherwise n = max(1, ceil((d_max − d_min)/ε_t)). */
void spr_lowres_make(const spr_view *v, const spr_bounds *b, float eps_t, double n_override, spr_lowres *out);

/* Conservative pixel rectangle covered by splat (p, n, r): fills x0..x1,
 * y0..y1 (inclusive, clipped to the viewport); returns 0 when empty.  Computed
 * in double from the splat's bounding box; coverage itself is decided per
 * pixel by the exact test, so this only has to be conservative. */
int spr_splat_pixel_rect(const spr_view *v, const float p[3], const float n[3], float r,
                         int *x0, int *y0, int *x1, int *y1);
/* The same for the ellipse e = (u, r_v) of major radius r (spr_ray_ellipse;
 * a circle when e[3] == r): the box of the ellipse itself, so a thin splat
 * is tested over its own extent, not over its bounding circle's. */
int spr_splat_pixel_rect_ell(const spr_view *v, const float p[3], const float n[3], const float e[4], float r,
                             int *x0, int *y0, int *x1, int *y1);

/* 4×4 row-major double helpers (exposed for tests). */
void spr__mat4_mul(const double a[16], const double b[16], double out[16]);
int spr__mat4_inverse(const double m[16], double out[16]);

#endif
