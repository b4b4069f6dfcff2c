/* camera.c — view matrices in double, the shared float M, pixel bounds. */
#include "spr_camera.h"
#include "spr_backend.h"

#include <math.h>
#include <string.h>

void spr_camera_defaults(spr_camera_desc *c)
{
    memset(c, 0, sizeof *c);
    c->width = 512;
    c->height = 512;
    c->fov_deg = 30.0;
    c->up[1] = 1.0;
}

static double len3(const double *a) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

void spr_view_matrix_eye(const double V[16], double eye[3])
{
    for (int k = 0; k < 3; k++) eye[k] = -(V[k] * V[3] + V[4 + k] * V[7] + V[8 + k] * V[11]);
}

/* near/far of a projection matrix: the eye depths P maps to NDC z = −1, +1. */
static void planes_of_projection(const double P[16], double *n, double *f)
{
    if (P[15] == 1.0) { /* orthographic: z_ndc = P10·z + P11 */
        *n = (P[11] + 1.0) / P[10];
        *f = (P[11] - 1.0) / P[10];
    } else { /* perspective: z_ndc = (P10·z + P11)/(−z) */
        *n = P[11] / (P[10] - 1.0);
        *f = P[11] / (P[10] + 1.0);
    }
}

void spr_pinhole_eye(const spr_pinhole *p, double eye[3])
{
    for (int k = 0; k < 3; k++) eye[k] = -(p->R[k] * p->t[0] + p->R[3 + k] * p->t[1] + p->R[6 + k] * p->t[2]);
}

void spr_camera_frame(spr_camera_desc *c, const spr_bounds *b)
{
    if (c->have_pinhole) { /* the camera is placed: its eye −Rᵀt, and near/far framed below */
        spr_pinhole_eye(&c->pinhole, c->eye);
        c->have_eye = 1;
    }
    if (c->have_matrices) { /* the matrices place the camera: only the eye (hash mode 3) and missing planes */
        spr_view_matrix_eye(c->V, c->eye);
        c->have_eye = 1;
        if (c->near_plane == 0.0 && c->far_plane == 0.0) planes_of_projection(c->P, &c->near_plane, &c->far_plane);
        return;
    }
    double center[3], radius = 0.0;
    for (int k = 0; k < 3; k++) {
        center[k] = 0.5 * (b->lo[k] + b->hi[k]);
        double h = 0.5 * (b->hi[k] - b->lo[k]);
        radius += h * h;
    }
    radius = sqrt(radius) + b->max_radius;
    if (!(radius > 0.0)) radius = 1.0;
    int have_eye = c->have_eye || c->eye[0] != 0.0 || c->eye[1] != 0.0 || c->eye[2] != 0.0;
    int have_target = c->have_target || c->target[0] != 0.0 || c->target[1] != 0.0 || c->target[2] != 0.0;
    if (!have_target && !c->have_pinhole) memcpy(c->target, center, sizeof center);
    if (!have_eye) {
        double half = c->ortho_height > 0.0 ? 0.0 : 0.5 * c->fov_deg * M_PI / 180.0;
        double dist = half > 0.0 ? 1.05 * radius / sin(half) : 3.0 * radius;
        memcpy(c->eye, c->target, sizeof c->eye);
        c->eye[2] += dist;
        if (c->ortho_height <= 0.0 && c->fov_deg <= 0.0) c->fov_deg = 30.0;
    }
    if (c->near_plane == 0.0 && c->far_plane == 0.0) {
        double to_center[3] = {center[0] - c->eye[0], center[1] - c->eye[1], center[2] - c->eye[2]};
        double dist = len3(to_center);
        double nearp = dist - 1.02 * radius, farp = dist + 1.02 * radius;
        if (nearp < 1e-3 * radius) nearp = 1e-3 * radius;
        c->near_plane = nearp;
        c->far_plane = farp;
    }
    if (c->ortho_height == 0.0 && c->fov_deg == 0.0) c->fov_deg = 30.0;
}

void spr__mat4_mul(const double a[16], const double b[16], double out[16])
{
    double r[16];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j] +
                           a[4 * i + 3] * b[12 + j];
    memcpy(out, r, sizeof r);
}

int spr__mat4_inverse(const double m[16], double out[16])
{
    double a[4][8];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 8; j++) a[i][j] = j < 4 ? m[4 * i + j] : (j - 4 == i ? 1.0 : 0.0);
    for (int col = 0; col < 4; col++) {
        int piv = col;
        for (int i = col + 1; i < 4; i++)
            if (fabs(a[i][col]) > fabs(a[piv][col])) piv = i;
        if (a[piv][col] == 0.0) return -1;
        if (piv != col)
            for (int j = 0; j < 8; j++) { double t = a[col][j]; a[col][j] = a[piv][j]; a[piv][j] = t; }
        double inv = 1.0 / a[col][col];
        for (int j = 0; j < 8; j++) a[col][j] *= inv;
        for (int i = 0; i < 4; i++) {
            if (i == col || a[i][col] == 0.0) continue;
            double f = a[i][col];
            for (int j = 0; j < 8; j++) a[i][j] -= f * a[col][j];
        }
    }
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) out[4 * i + j] = a[i][4 + j];
    return 0;
}

/* Everything after V and P: M = (P·V)^-1 rounded to float once (SPEC §2). */
static spr_result view_finish(const spr_camera_desc *c, const double V[16], const double P[16], double n, double fa, spr_view *v,
                              spr_error *err)
{
    double PV[16], Minv[16];
    spr__mat4_mul(P, V, PV);
    if (spr__mat4_inverse(PV, Minv) != 0) return spr__fail(err, SPR_E_ARG, "camera: P·V is singular");
    for (int i = 0; i < 16; i++) v->M[i] = (float)Minv[i];
    memcpy(v->PV, PV, sizeof PV);
    static const int rows[3] = {0, 1, 3};
    for (int j = 0; j < 3; j++) {
        const double *q = PV + 4 * rows[j];
        v->row_norm[j] = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    }
    memcpy(v->V, V, sizeof v->V);
    memcpy(v->P, P, sizeof v->P);
    v->width = c->width;
    v->height = c->height;
    v->ndc_sx = (float)(2.0 / c->width);
    v->ndc_sy = (float)(2.0 / c->height);
    v->near_plane = n;
    v->far_plane = fa;
    return SPR_OK;
}

spr_result spr_pinhole_check(const spr_pinhole *p, const char *what, spr_error *err)
{
    for (int i = 0; i < 9; i++)
        if (!isfinite(p->R[i])) return spr__fail(err, SPR_E_ARG, "%s: rotation element %d is not finite", what, i + 1);
    double worst = 0.0;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double d = p->R[a] * p->R[b] + p->R[3 + a] * p->R[3 + b] + p->R[6 + a] * p->R[6 + b] - (a == b ? 1.0 : 0.0);
            if (fabs(d) > worst) worst = fabs(d);
        }
    const double *R = p->R;
    const double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) + R[2] * (R[3] * R[7] - R[4] * R[6]);
    if (!(worst <= 1e-6) || !(det > 0.0))
        return spr__fail(err, SPR_E_ARG, "%s: the rotation is not rigid (|RᵀR − I| reaches %.3g, det %.6g; a rotation has 0 and +1)", what, worst, det);
    for (int k = 0; k < 3; k++)
        if (!isfinite(p->t[k])) return spr__fail(err, SPR_E_ARG, "%s: translation %c is not finite", what, "xyz"[k]);
    if (!(p->fx > 0.0) || !isfinite(p->fx) || !(p->fy > 0.0) || !isfinite(p->fy))
        return spr__fail(err, SPR_E_ARG, "%s: focal lengths fx %g, fy %g must be positive and finite (pixels)", what, p->fx, p->fy);
    if (!isfinite(p->cx) || !isfinite(p->cy)) return spr__fail(err, SPR_E_ARG, "%s: principal point %g, %g is not finite", what, p->cx, p->cy);
    return SPR_OK;
}

/* The pinhole of a perspective V and P (SPEC §10.2): y and z negated. */
static void pinhole_of(const double V[16], const double P[16], int W, int H, spr_pinhole *p)
{
    for (int j = 0; j < 3; j++) {
        p->R[j] = V[j];
        p->R[3 + j] = -V[4 + j];
        p->R[6 + j] = -V[8 + j];
    }
    p->t[0] = V[3], p->t[1] = -V[7], p->t[2] = -V[11];
    p->fx = 0.5 * W * P[0];
    p->cx = 0.5 * W * (1.0 - P[2]);
    p->fy = 0.5 * H * P[5];
    p->cy = 0.5 * H * (1.0 + P[6]);
}

static spr_result view_from_pinhole(const spr_camera_desc *c, spr_view *v, spr_error *err)
{
    const spr_pinhole *p = &c->pinhole;
    spr_result r = spr_pinhole_check(p, "camera", err);
    if (r) return r;
    const double n = c->near_plane, fa = c->far_plane;
    if (!(n > 0.0) || !(fa > n) || !isfinite(fa))
        return spr__fail(err, SPR_E_ARG, "camera: near %g, far %g are not 0 < near < far", n, fa);
    const double W = c->width, H = c->height;
    double V[16] = {0}, P[16] = {0};
    for (int j = 0; j < 3; j++) { /* OpenCV to GL's eye space: y and z negated */
        V[j] = p->R[j];
        V[4 + j] = -p->R[3 + j];
        V[8 + j] = -p->R[6 + j];
    }
    V[3] = p->t[0], V[7] = -p->t[1], V[11] = -p->t[2], V[15] = 1.0;
    P[0] = 2.0 * p->fx / W;
    P[2] = 1.0 - 2.0 * p->cx / W;
    P[5] = 2.0 * p->fy / H;
    P[6] = 2.0 * p->cy / H - 1.0;
    P[10] = (fa + n) / (n - fa);
    P[11] = 2.0 * fa * n / (n - fa);
    P[14] = -1.0;
    if ((r = view_finish(c, V, P, n, fa, v, err))) return r;
    v->cv = *p;
    return SPR_OK;
}

static spr_result view_from_matrices(const spr_camera_desc *c, spr_view *v, spr_error *err)
{
    for (int i = 0; i < 16; i++)
        if (!isfinite(c->V[i]) || !isfinite(c->P[i]))
            return spr__fail(err, SPR_E_ARG, "camera: %s-matrix element %d (row %d, column %d) is not finite",
                             isfinite(c->V[i]) ? "projection" : "view", i, i / 4 + 1, i % 4 + 1);
    if (!(c->V[12] == 0.0 && c->V[13] == 0.0 && c->V[14] == 0.0 && c->V[15] == 1.0))
        return spr__fail(err, SPR_E_ARG, "camera: view-matrix row 4 must be 0,0,0,1 (got %g,%g,%g,%g)", c->V[12], c->V[13], c->V[14], c->V[15]);
    const int persp = c->P[12] == 0.0 && c->P[13] == 0.0 && c->P[14] == -1.0 && c->P[15] == 0.0;
    const int ortho = c->P[12] == 0.0 && c->P[13] == 0.0 && c->P[14] == 0.0 && c->P[15] == 1.0;
    if (!persp && !ortho)
        return spr__fail(err, SPR_E_ARG, "camera: projection-matrix row 4 must be 0,0,-1,0 (perspective) or 0,0,0,1 (orthographic), got %g,%g,%g,%g",
                         c->P[12], c->P[13], c->P[14], c->P[15]);
    double n = c->near_plane, fa = c->far_plane;
    if (n == 0.0 && fa == 0.0) planes_of_projection(c->P, &n, &fa);
    if (!(fa > n) || !isfinite(n) || !isfinite(fa) || (persp && !(n > 0.0)))
        return spr__fail(err, SPR_E_ARG, "camera: the projection's planes near %g, far %g are not 0 < near < far", n, fa);
    v->ortho = ortho;
    spr_result r = view_finish(c, c->V, c->P, n, fa, v, err);
    if (!r && !ortho) pinhole_of(v->V, v->P, v->width, v->height, &v->cv);
    return r;
}

spr_result spr_view_make(const spr_camera_desc *c, spr_view *v, spr_error *err)
{
    memset(v, 0, sizeof *v);
    if (c->width < 1 || c->height < 1 || c->width > SPR_MAX_IMAGE_SIDE || c->height > SPR_MAX_IMAGE_SIDE)
        return spr__fail(err, SPR_E_ARG, "camera: image size %dx%d outside 1..%d", c->width, c->height,
                         SPR_MAX_IMAGE_SIDE);
    if (c->have_pinhole) return view_from_pinhole(c, v, err);
    if (c->have_matrices) return view_from_matrices(c, v, err);
    if (!(c->near_plane > 0.0) && c->ortho_height <= 0.0)
        return spr__fail(err, SPR_E_ARG, "camera: --near must be > 0 for a perspective camera (got %g)", c->near_plane);
    if (!(c->far_plane > c->near_plane) || !isfinite(c->far_plane))
        return spr__fail(err, SPR_E_ARG, "camera: --far (%g) must be finite and greater than --near (%g)",
                         c->far_plane, c->near_plane);
    double f[3], s[3], u[3];
    for (int k = 0; k < 3; k++) f[k] = c->target[k] - c->eye[k];
    double lf = len3(f);
    if (!(lf > 0.0) || !isfinite(lf)) return spr__fail(err, SPR_E_ARG, "camera: --eye and --target coincide");
    for (int k = 0; k < 3; k++) f[k] /= lf;
    s[0] = f[1] * c->up[2] - f[2] * c->up[1];
    s[1] = f[2] * c->up[0] - f[0] * c->up[2];
    s[2] = f[0] * c->up[1] - f[1] * c->up[0];
    double ls = len3(s);
    if (!(ls > 1e-12)) return spr__fail(err, SPR_E_ARG, "camera: --up is parallel to the view direction");
    for (int k = 0; k < 3; k++) s[k] /= ls;
    u[0] = s[1] * f[2] - s[2] * f[1];
    u[1] = s[2] * f[0] - s[0] * f[2];
    u[2] = s[0] * f[1] - s[1] * f[0];
    double V[16] = {s[0],  s[1],  s[2],  -(s[0] * c->eye[0] + s[1] * c->eye[1] + s[2] * c->eye[2]),
                    u[0],  u[1],  u[2],  -(u[0] * c->eye[0] + u[1] * c->eye[1] + u[2] * c->eye[2]),
                    -f[0], -f[1], -f[2], f[0] * c->eye[0] + f[1] * c->eye[1] + f[2] * c->eye[2],
                    0,     0,     0,     1};
    double P[16] = {0};
    double aspect = (double)c->width / (double)c->height;
    double n = c->near_plane, fa = c->far_plane;
    if (c->ortho_height > 0.0) {
        double hh = 0.5 * c->ortho_height, hw = hh * aspect;
        P[0] = 1.0 / hw;
        P[5] = 1.0 / hh;
        P[10] = -2.0 / (fa - n);
        P[11] = -(fa + n) / (fa - n);
        P[15] = 1.0;
        v->ortho = 1;
    } else {
        if (!(c->fov_deg > 0.0 && c->fov_deg < 180.0))
            return spr__fail(err, SPR_E_ARG, "camera: --fov %g outside (0, 180) degrees", c->fov_deg);
        double ft = 1.0 / tan(0.5 * c->fov_deg * M_PI / 180.0);
        P[0] = ft / aspect;
        P[5] = ft;
        P[10] = (fa + n) / (n - fa);
        P[11] = 2.0 * fa * n / (n - fa);
        P[14] = -1.0;
    }
    spr_result r = view_finish(c, V, P, n, fa, v, err);
    if (!r && !v->ortho) pinhole_of(v->V, v->P, v->width, v->height, &v->cv);
    return r;
}

float spr_view_eps_t(const spr_view *v, double eps_world)
{
    return (float)(eps_world / (v->far_plane - v->near_plane));
}

void spr_lowres_make(const spr_view *v, const spr_bounds *b, float eps_t, double n_override, spr_lowres *out)
{
    double tmin = INFINITY, tmax = -INFINITY, r = b->max_radius;
    for (int corner = 0; corner < 8; corner++) {
        double p[3];
        for (int k = 0; k < 3; k++) p[k] = (corner >> k & 1) ? b->hi[k] + r : b->lo[k] - r;
        double z_eye = v->V[8] * p[0] + v->V[9] * p[1] + v->V[10] * p[2] + v->V[11];
        double t = (-z_eye - v->near_plane) / (v->far_plane - v->near_plane);
        if (t < 0.0) t = 0.0;
        if (t > 1.0) t = 1.0;
        if (t < tmin) tmin = t;
        if (t > tmax) tmax = t;
    }
    out->d_min = (float)tmin;
    out->d_max = (float)tmax;
    if (!(out->d_max > out->d_min)) out->d_max = nextafterf(out->d_min, 2.0f);
    double n = n_override > 0.0 ? n_override
                                : ceil(((double)out->d_max - (double)out->d_min) / (double)eps_t);
    if (!(n >= 1.0)) n = 1.0;
    if (n > 16777216.0) n = 16777216.0; /* float must hold n exactly */
    out->n = (float)n;
    out->inv_n = (float)(1.0 / n);
}

/* Grow the NDC box by world point q; 0 when q is not in front of the eye. */
static int ndc_extend(const spr_view *v, const double q[3], double box[4])
{
    const double *PV = v->PV;
    double cw = PV[12] * q[0] + PV[13] * q[1] + PV[14] * q[2] + PV[15];
    if (!(cw > 1e-9 * (v->far_plane))) return 0;
    double cx = (PV[0] * q[0] + PV[1] * q[1] + PV[2] * q[2] + PV[3]) / cw;
    double cy = (PV[4] * q[0] + PV[5] * q[1] + PV[6] * q[2] + PV[7]) / cw;
    if (cx < box[0]) box[0] = cx;
    if (cx > box[1]) box[1] = cx;
    if (cy < box[2]) box[2] = cy;
    if (cy > box[3]) box[3] = cy;
    return 1;
}

/* Pixels whose centres an NDC box may cover (everything when `full`: a
 * corner behind the eye); 0 when none is on screen. */
static inline double clampd(double x, double lo, double hi) { return x > lo ? (x < hi ? x : hi) : lo; } /* NaN → lo */
/* floor and ceil of a value well inside the int range */
static inline int floor_int(double x) { int i = (int)x; return (double)i > x ? i - 1 : i; }
static inline int ceil_int(double x) { int i = (int)x; return (double)i < x ? i + 1 : i; }

static int spr__pixel_bounds(const spr_view *v, int full, const double box[4], int *x0, int *y0, int *x1, int *y1)
{
    const int W = v->width, H = v->height;
    const double xmin = box[0], xmax = box[1], ymin = box[2], ymax = box[3];
    if (full) { *x0 = 0; *y0 = 0; *x1 = W - 1; *y1 = H - 1; return 1; }
    /* ndc → pixel-centre coordinate: x + 0.5 = (ndc + 1)·W/2.  The centres
     * inside the box, and those up to half a pixel outside it: a margin
     * thousands of times any rounding of the per-pixel test (whose float
     * error is ~1e-6 of the image), while a sub-pixel splat is tested at 1–4
     * pixels instead of the 9–16 a whole pixel of slack on each side gave. */
    const double slack = 0.5;
    /* clamped to a little beyond the image first, so the conversions to int
     * below are exact floor/ceil of values that fit (and NaN-free) */
    const double bx0 = clampd((xmin + 1.0) * 0.5 * W - 0.5 - slack, -2.0, W + 1.0), bx1 = clampd((xmax + 1.0) * 0.5 * W - 0.5 + slack, -2.0, W + 1.0);
    const double by0 = clampd((ymin + 1.0) * 0.5 * H - 0.5 - slack, -2.0, H + 1.0), by1 = clampd((ymax + 1.0) * 0.5 * H - 0.5 + slack, -2.0, H + 1.0);
    const int ix0 = ceil_int(bx0), ix1 = floor_int(bx1), iy0 = ceil_int(by0), iy1 = floor_int(by1);
    if (ix1 < ix0 || iy1 < iy0) return 0; /* no centre near the box */
    if (ix1 < 0 || iy1 < 0 || ix0 > W - 1 || iy0 > H - 1) return 0;
    *x0 = ix0 < 0 ? 0 : ix0;
    *y0 = iy0 < 0 ? 0 : iy0;
    *x1 = ix1 > W - 1 ? W - 1 : ix1;
    *y1 = iy1 > H - 1 ? H - 1 : iy1;
    return 1;
}

/* Bounds of the NDC coordinate num/den over the ball |d| ≤ r around the
 * centre, num = a0 + a·d, den = w0 + b·d with |a·d| ≤ r|a|, |b·d| ≤ r|b|
 * (Cauchy–Schwarz); den > 0 on the whole ball (checked by the caller). */
static void ball_range(double a0, double an, double w0, double bn, double r, double *lo, double *hi)
{
    const double nlo = a0 - r * an, nhi = a0 + r * an, dlo = w0 - r * bn, dhi = w0 + r * bn;
    *lo = nlo / (nlo >= 0.0 ? dhi : dlo);
    *hi = nhi / (nhi >= 0.0 ? dlo : dhi);
}

int spr_splat_pixel_rect(const spr_view *v, const float p[3], const float n[3], float r,
                         int *x0, int *y0, int *x1, int *y1)
{
    const float circle[4] = {0.0f, 0.0f, 0.0f, r};
    return spr_splat_pixel_rect_ell(v, p, n, circle, r, x0, y0, x1, y1);
}

int spr_splat_pixel_rect_ell(const spr_view *v, const float p[3], const float n[3], const float el[4], float r,
                             int *x0, int *y0, int *x1, int *y1)
{
    /* First the bounding ball of the disk: one projection of the centre,
     * four divisions.  Enough for the many splats that project to a few
     * pixels (the ball is at most √2 wider than the disk's box there);
     * larger ones take the tighter box below. */
    const double *PV = v->PV;
    const double cx0 = PV[0] * p[0] + PV[1] * p[1] + PV[2] * p[2] + PV[3];
    const double cy0 = PV[4] * p[0] + PV[5] * p[1] + PV[6] * p[2] + PV[7];
    const double cw0 = PV[12] * p[0] + PV[13] * p[1] + PV[14] * p[2] + PV[15];
    const double rb = (double)r * 1.001 + 1e-7 * (double)r;
    if (cw0 - rb * v->row_norm[2] > 1e-9 * v->far_plane) {
        double box[4];
        ball_range(cx0, v->row_norm[0], cw0, v->row_norm[2], rb, &box[0], &box[1]);
        ball_range(cy0, v->row_norm[1], cw0, v->row_norm[2], rb, &box[2], &box[3]);
        if ((box[1] - box[0]) * v->width < 8.0 && (box[3] - box[2]) * v->height < 8.0) /* at most 4 pixels across */
            return spr__pixel_bounds(v, 0, box, x0, y0, x1, y1);
    }
    /* The 8 corners of the disk's bounding box p ± ext: clip coordinates are
     * linear in the corner, c(p ± ext) = c(p) + Σ_k ±ext_k·PV[·][k], so the
     * centre is projected once and each corner adds three terms (z is not
     * needed).  Rounding differs from projecting each corner by a few ulps
     * of a double: far inside the half-pixel slack of spr__pixel_bounds. */
    double e[3][3];
    const double c0[3] = {cx0, cy0, cw0}; /* rows x, y, w */
    static const int row[3] = {0, 1, 3};
    const int ellipse = el[3] != r;
    /* the ellipse's half-extent along axis k: sqrt((r_u·u_k)² + (r_v·v_k)²), v = n × u (a circle: r·sqrt(1 − n_k²));
     * the margin 1.001 covers the float arithmetic of the per-pixel test, u off the plane by up to 1e-4 included */
    for (int k = 0; k < 3; k++) {
        double nk = n[k], s = 1.0 - nk * nk;
        double ext = (double)r * sqrt(s > 0.0 ? s : 0.0);
        if (ellipse) {
            const int k1 = (k + 1) % 3, k2 = (k + 2) % 3; /* v_k of v = n × u */
            const double vk = (double)n[k1] * el[k2] - (double)n[k2] * el[k1];
            const double a = (double)r * el[k], b = (double)el[3] * vk;
            const double ee = sqrt(a * a + b * b);
            ext = ee < ext ? ee : ext;
        }
        ext = ext * 1.001 + 1e-7 * (double)r;
        for (int j = 0; j < 3; j++) e[j][k] = ext * PV[4 * row[j] + k];
    }
    double box[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY}; /* NDC x min, max, y min, max */
    int full = 0;
    const double wmin = 1e-9 * v->far_plane;
    for (int corner = 0; corner < 8 && !full; corner++) {
        double c[3];
        for (int j = 0; j < 3; j++)
            c[j] = c0[j] + ((corner & 1) ? e[j][0] : -e[j][0]) + ((corner & 2) ? e[j][1] : -e[j][1]) + ((corner & 4) ? e[j][2] : -e[j][2]);
        if (!(c[2] > wmin)) { full = 1; break; } /* a corner behind the eye */
        const double iw = 1.0 / c[2], cx = c[0] * iw, cy = c[1] * iw;
        if (cx < box[0]) box[0] = cx;
        if (cx > box[1]) box[1] = cx;
        if (cy < box[2]) box[2] = cy;
        if (cy > box[3]) box[3] = cy;
    }
    return spr__pixel_bounds(v, full, box, x0, y0, x1, y1);
}

int spr_rect_pixel_rect(const spr_view *v, const float *f, int *x0, int *y0, int *x1, int *y1)
{
    double box[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY}; /* NDC x min, max, y min, max */
    int full = 0;
    for (int corner = 0; corner < 4; corner++) {
        const double s = (corner & 1) ? f[SPR_RECT_UMAX] : f[SPR_RECT_UMIN], w = (corner & 2) ? f[SPR_RECT_VMAX] : f[SPR_RECT_VMIN];
        double q[3];
        for (int k = 0; k < 3; k++) q[k] = (double)f[SPR_RECT_C + k] + s * f[SPR_RECT_U + k] + w * f[SPR_RECT_V + k];
        if (!ndc_extend(v, q, box)) { full = 1; break; }
    }
    return spr__pixel_bounds(v, full, box, x0, y0, x1, y1);
}
