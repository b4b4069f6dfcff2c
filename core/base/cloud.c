/* cloud.c — allocation, validation and bounds of splat clouds. */
#include "spr_cloud.h"
#include "spr_util.h"
#include <omp.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

spr_result spr_cloud_alloc(spr_cloud *c, size_t n)
{
    memset(c, 0, sizeof *c);
    if (n > SPR_MAX_SPLATS) return SPR_E_TOO_LARGE;
    size_t m = n ? n : 1;
    c->pos = spr__big_alloc(3 * m * sizeof(float));
    c->nrm = spr__big_alloc(3 * m * sizeof(float));
    c->radius = spr__big_alloc(m * sizeof(float));
    c->color = spr__big_alloc(3 * m * sizeof(float));
    c->alpha = spr__big_alloc(m * sizeof(float));
    if (!c->pos || !c->nrm || !c->radius || !c->color || !c->alpha) {
        spr_cloud_free(c);
        return SPR_E_NOMEM;
    }
    c->n = n;
    for (size_t i = 0; i < n; i++) {
        c->pos[3 * i] = c->pos[3 * i + 1] = c->pos[3 * i + 2] = 0.0f;
        c->nrm[3 * i] = c->nrm[3 * i + 1] = 0.0f;
        c->nrm[3 * i + 2] = 1.0f;
        c->color[3 * i] = c->color[3 * i + 1] = c->color[3 * i + 2] = 0.8f;
        c->radius[i] = 0.0f;
        c->alpha[i] = 1.0f;
    }
    return SPR_OK;
}

spr_result spr_cloud_alloc_ell(spr_cloud *c)
{
    if (c->ell) return SPR_OK;
    c->ell = malloc(4 * (c->n ? c->n : 1) * sizeof(float));
    if (!c->ell) return SPR_E_NOMEM;
    for (size_t i = 0; i < c->n; i++) {
        c->ell[4 * i] = c->ell[4 * i + 1] = c->ell[4 * i + 2] = 0.0f;
        c->ell[4 * i + 3] = c->radius[i];
    }
    return SPR_OK;
}

/* A field added to spr_cloud changes its size: if it is a per-splat array, list it in
 * SPR_CLOUD_ARRAYS (then views and frees carry it), and update this size (LP64). */
#if UINTPTR_MAX == UINT64_MAX
_Static_assert(sizeof(spr_cloud) == 96, "spr_cloud changed: a per-splat array belongs in SPR_CLOUD_ARRAYS (spr_cloud.h)");
#endif

spr_cloud spr_cloud_view(const spr_cloud *c, size_t first, size_t m)
{
    spr_cloud v = *c;
#define SPR_ADVANCE(a, k) if (v.a) v.a += first * (k);
    SPR_CLOUD_ARRAYS(SPR_ADVANCE, c)
#undef SPR_ADVANCE
    v.n = m;
    return v;
}

void spr_cloud_free(spr_cloud *c)
{
#define SPR_FREE(a, k) free(c->a);
    SPR_CLOUD_ARRAYS(SPR_FREE, c)
#undef SPR_FREE
    memset(c, 0, sizeof *c);
}

spr_result spr__normalize3(float *n)
{
    double x = n[0], y = n[1], z = n[2];
    double l = sqrt(x * x + y * y + z * z);
    if (!(l > 0.0) || !isfinite(l)) return SPR_E_VALUE;
    n[0] = (float)(x / l);
    n[1] = (float)(y / l);
    n[2] = (float)(z / l);
    return SPR_OK;
}

spr_result spr_cloud_validate(const spr_cloud *c, const char *what, spr_error *err)
{
    return spr__cloud_validate_from(c, what, 0, err);
}

spr_result spr__cloud_validate_from(const spr_cloud *c, const char *what, size_t first, spr_error *err)
{
    for (size_t i = 0; i < c->n; i++) {
        const float *p = c->pos + 3 * i, *nv = c->nrm + 3 * i, *col = c->color + 3 * i;
        for (int k = 0; k < 3; k++) {
            if (!isfinite(p[k]))
                return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: non-finite coordinate %c", what, first + i, "xyz"[k]);
            if (!isfinite(nv[k]))
                return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: non-finite normal", what, first + i);
            if (!(col[k] >= 0.0f && col[k] <= 1.0f))
                return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: colour outside [0,1]", what, first + i);
        }
        double l2 = (double)nv[0] * nv[0] + (double)nv[1] * nv[1] + (double)nv[2] * nv[2];
        if (fabs(l2 - 1.0) > 1e-5)
            return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: normal is not unit length", what, first + i);
        if (!isfinite(c->radius[i]) || !(c->radius[i] > 0.0f))
            return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: radius %g is not positive and finite", what, first + i,
                             (double)c->radius[i]);
        if (!(c->alpha[i] >= 0.0f && c->alpha[i] <= 1.0f))
            return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: opacity outside [0,1]", what, first + i);
        if (c->gauss) {
            const float *G = c->gauss + SPR_GAUSS_FLOATS * i;
            double q2 = (double)G[0] * G[0] + (double)G[1] * G[1] + (double)G[2] * G[2] + (double)G[3] * G[3];
            if (!(fabs(q2 - 1.0) <= 1e-5))
                return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: Gaussian rotation is not a unit quaternion", what, first + i);
            for (int k = 0; k < 3; k++)
                if (!isfinite(G[4 + k]) || !(G[4 + k] > 0.0f || (k == 2 && G[4 + k] == 0.0f)))
                    return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: Gaussian scale %d (σ = %g) is not positive and finite", what,
                                     first + i, k, (double)G[4 + k]);
        }
        if (c->ell && c->ell[4 * i + 3] != c->radius[i]) {
            const float *e = c->ell + 4 * i;
            double u2 = (double)e[0] * e[0] + (double)e[1] * e[1] + (double)e[2] * e[2];
            double un = (double)e[0] * nv[0] + (double)e[1] * nv[1] + (double)e[2] * nv[2];
            if (!(fabs(u2 - 1.0) <= 1e-5) || !(fabs(un) <= 1e-4))
                return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: ellipse axis is not a unit tangent", what, first + i);
            if (!isfinite(e[3]) || !(e[3] > 0.0f) || !(e[3] <= c->radius[i]))
                return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: minor radius %g is not in (0, radius %g]", what,
                                 first + i, (double)e[3], (double)c->radius[i]);
        }
    }
    return SPR_OK;
}

void spr_bounds_begin(spr_bounds_acc *a)
{
    for (int k = 0; k < 3; k++) { a->b.lo[k] = INFINITY; a->b.hi[k] = -INFINITY; }
    a->b.max_radius = 0.0;
    a->b.min_radius = INFINITY;
    a->b.mean_radius = 0.0;
    a->sum = 0.0;
    a->n = 0;
}

/* lo/hi of the centres and min/max of the radii over splats [i0, i1): the
 * strict comparisons of one walk in order, so a tie (−0 and +0) keeps the
 * first seen. */
static void bounds_range(const spr_cloud *c, size_t i0, size_t i1, spr_bounds *b)
{
    for (size_t i = i0; i < i1; i++) {
        for (int k = 0; k < 3; k++) {
            double v = c->pos[3 * i + k];
            if (v < b->lo[k]) b->lo[k] = v;
            if (v > b->hi[k]) b->hi[k] = v;
        }
        double r = c->radius[i];
        if (r > b->max_radius) b->max_radius = r;
        if (r < b->min_radius) b->min_radius = r;
    }
}

void spr_bounds_add(spr_bounds_acc *a, const spr_cloud *c)
{
    /* the extremes in contiguous chunks in parallel, merged in chunk order
     * with the same strict comparisons: the numbers of one walk in order */
    enum { CHUNKS = 16 };
    spr_bounds part[CHUNKS];
    const size_t step = (c->n + CHUNKS - 1) / CHUNKS;
#pragma omp parallel for schedule(static, 1) if (c->n >= ((size_t)1 << 16))
    for (int ch = 0; ch < CHUNKS; ch++) {
        spr_bounds *p = &part[ch];
        for (int k = 0; k < 3; k++) p->lo[k] = INFINITY, p->hi[k] = -INFINITY;
        p->max_radius = 0.0, p->min_radius = INFINITY;
        const size_t i0 = (size_t)ch * step < c->n ? (size_t)ch * step : c->n, i1 = i0 + step < c->n ? i0 + step : c->n;
        bounds_range(c, i0, i1, p);
    }
    spr_bounds *b = &a->b;
    for (int ch = 0; ch < CHUNKS; ch++) {
        const spr_bounds *p = &part[ch];
        for (int k = 0; k < 3; k++) {
            if (p->lo[k] < b->lo[k]) b->lo[k] = p->lo[k];
            if (p->hi[k] > b->hi[k]) b->hi[k] = p->hi[k];
        }
        if (p->max_radius > b->max_radius) b->max_radius = p->max_radius;
        if (p->min_radius < b->min_radius) b->min_radius = p->min_radius;
    }
    /* the radii's sum in order, one double rounding after another (ε is twice their mean) */
    double sum = a->sum;
    for (size_t i = 0; i < c->n; i++) sum += c->radius[i];
    a->sum = sum;
    a->n += c->n;
}

void spr_bounds_end(const spr_bounds_acc *a, spr_bounds *b)
{
    *b = a->b;
    if (!a->n) {
        for (int k = 0; k < 3; k++) b->lo[k] = b->hi[k] = 0.0;
        b->min_radius = 0.0;
    }
    b->mean_radius = a->n ? a->sum / (double)a->n : 0.0;
}

void spr_cloud_bounds(const spr_cloud *c, spr_bounds *b)
{
    spr_bounds_acc a;
    spr_bounds_begin(&a);
    spr_bounds_add(&a, c);
    spr_bounds_end(&a, b);
}

spr_result spr_cloud_source_scan(spr_cloud_source *src, spr_cloud *keep, const spr_progress *prog, spr_error *err)
{
    spr_cloud chunk;
    spr_result r = spr_cloud_alloc(&chunk, src->chunk);
    if (r) return spr__fail(err, r, "stream: cannot allocate a chunk of %zu splats", src->chunk);
    if (keep) {
        memset(keep, 0, sizeof *keep);
        keep->pos = malloc(3 * src->n * sizeof(float));
        keep->nrm = malloc(3 * src->n * sizeof(float));
        keep->radius = malloc(src->n * sizeof(float));
        if (!keep->pos || !keep->nrm || !keep->radius) {
            spr_cloud_free(keep);
            spr_cloud_free(&chunk);
            return spr__fail(err, SPR_E_NOMEM, "stream: out of memory for the centres, normals and radii of %zu splats", src->n);
        }
        keep->n = src->n;
        keep->flags = src->flags;
    }
    spr_bounds_acc acc;
    spr_bounds_begin(&acc);
    for (size_t first = 0; first < src->n && !r; first += src->chunk) {
        size_t m = src->n - first < src->chunk ? src->n - first : src->chunk;
        spr_progress_report(prog, "reading", first, src->n);
        if ((r = src->read(src->user, first, m, &chunk, err))) break;
        spr_bounds_add(&acc, &chunk);
        if (keep) {
            const spr_cloud to = spr_cloud_view(keep, first, m);
            memcpy(to.pos, chunk.pos, 3 * m * sizeof(float));
            memcpy(to.nrm, chunk.nrm, 3 * m * sizeof(float));
            memcpy(to.radius, chunk.radius, m * sizeof(float));
        }
    }
    spr_progress_report(prog, "reading", src->n, src->n);
    spr_cloud_free(&chunk);
    if (r) {
        if (keep) spr_cloud_free(keep);
        return r;
    }
    spr_bounds_end(&acc, &src->bounds);
    return SPR_OK;
}

void spr_cloud_color_by_normal(spr_cloud *c)
{
    for (size_t i = 0; i < 3 * c->n; i++) c->color[i] = 0.5f * c->nrm[i] + 0.5f;
}

double spr_cloud_default_eps(const spr_cloud *c)
{
    spr_bounds b;
    spr_cloud_bounds(c, &b);
    return spr_bounds_default_eps(&b);
}

double spr_bounds_default_eps(const spr_bounds *b) { return 2.0 * b->mean_radius; }

double spr_cloud_stream_ms(const spr_cloud *c, int threads, double *sum)
{
    const double t0 = spr_now_ms();
    const long n = (long)c->n;
    double acc = 0.0;
#pragma omp parallel for num_threads(threads > 0 ? threads : omp_get_num_procs()) schedule(static) reduction(+ : acc)
    for (long i = 0; i < n; i++) {
        const size_t k = (size_t)i;
        float s = c->pos[3 * k] + c->pos[3 * k + 1] + c->pos[3 * k + 2];
        s += c->nrm[3 * k] + c->nrm[3 * k + 1] + c->nrm[3 * k + 2];
        s += c->color[3 * k] + c->color[3 * k + 1] + c->color[3 * k + 2];
        s += c->radius[k] + c->alpha[k];
        acc += s;
    }
    *sum = acc;
    return spr_now_ms() - t0;
}

spr_result spr__cloud_finish(spr_cloud *c, const char *path, size_t first, double opacity, spr_error *err)
{
    if (!(c->flags & SPR_SRC_COLORS)) spr_cloud_color_by_normal(c);
    if (opacity > 0.0) {
        if (!(opacity <= 1.0)) return spr__fail(err, SPR_E_ARG, "%s: opacity %g outside (0, 1]", path, opacity);
        for (size_t i = 0; i < c->n; i++) c->alpha[i] = (float)opacity;
    }
    return spr__cloud_validate_from(c, path, first, err);
}

/* The real spherical harmonics of degree ≤ 3 at the unit direction (x, y,
 * z), with the constants and signs of the 3D Gaussian Splatting training
 * code (utils/sh_utils.py, KHR_gaussian_splatting Appendix A). */
static void sh_basis(double x, double y, double z, double Y[16])
{
    const double xx = x * x, yy = y * y, zz = z * z;
    Y[0] = 0.28209479177387814;
    Y[1] = -0.4886025119029199 * y;
    Y[2] = 0.4886025119029199 * z;
    Y[3] = -0.4886025119029199 * x;
    Y[4] = 1.0925484305920792 * x * y;
    Y[5] = -1.0925484305920792 * y * z;
    Y[6] = 0.31539156525252005 * (2.0 * zz - xx - yy);
    Y[7] = -1.0925484305920792 * x * z;
    Y[8] = 0.5462742152960396 * (xx - yy);
    Y[9] = -0.5900435899266435 * y * (3.0 * xx - yy);
    Y[10] = 2.890611442640554 * x * y * z;
    Y[11] = -0.4570457994644658 * y * (4.0 * zz - xx - yy);
    Y[12] = 0.3731763325901154 * z * (2.0 * zz - 3.0 * xx - 3.0 * yy);
    Y[13] = -0.4570457994644658 * x * (4.0 * zz - xx - yy);
    Y[14] = 1.445305721320277 * z * (xx - yy);
    Y[15] = -0.5900435899266435 * x * (xx - 3.0 * yy);
}

/* The basis of sh_basis and its derivative in the direction's components (taken as independent: the caller
 * projects onto the sphere's tangent), dY[k][a] = ∂Y_k/∂(x, y, z)_a, each Y_k = c_k·(its polynomial). */
static void sh_basis_grad(double x, double y, double z, double Y[16], double dY[16][3])
{
    sh_basis(x, y, z, Y);
    const double xx = x * x, yy = y * y, zz = z * z;
    const double c1 = -0.4886025119029199, c2 = 0.4886025119029199, c4 = 1.0925484305920792, c5 = -1.0925484305920792,
                 c6 = 0.31539156525252005, c8 = 0.5462742152960396, c9 = -0.5900435899266435, c10 = 2.890611442640554,
                 c11 = -0.4570457994644658, c12 = 0.3731763325901154, c14 = 1.445305721320277;
    const double d[16][3] = {
        {0, 0, 0},
        {0, c1, 0},
        {0, 0, c2},
        {c1, 0, 0},
        {c4 * y, c4 * x, 0},
        {0, c5 * z, c5 * y},
        {-2.0 * c6 * x, -2.0 * c6 * y, 4.0 * c6 * z},
        {c5 * z, 0, c5 * x},
        {2.0 * c8 * x, -2.0 * c8 * y, 0},
        {6.0 * c9 * x * y, c9 * (3.0 * xx - 3.0 * yy), 0},
        {c10 * y * z, c10 * x * z, c10 * x * y},
        {-2.0 * c11 * x * y, c11 * (4.0 * zz - xx - 3.0 * yy), 8.0 * c11 * y * z},
        {-6.0 * c12 * x * z, -6.0 * c12 * y * z, c12 * (6.0 * zz - 3.0 * xx - 3.0 * yy)},
        {c11 * (4.0 * zz - 3.0 * xx - yy), -2.0 * c11 * x * y, 8.0 * c11 * x * z},
        {2.0 * c14 * x * z, -2.0 * c14 * y * z, c14 * (xx - yy)},
        {c9 * (3.0 * xx - 3.0 * yy), -6.0 * c9 * x * y, 0},
    };
    memcpy(dY, d, sizeof d);
}

double spr_unorm8(double x, int mode)
{
    if (!mode) return x;
    x = x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x;
    if (mode == SPR_Q8_HALVED) {
        const double k = floor(x * 255.0 + 0.5), h = 2.0 * nearbyint(0.5 * k) / 255.0;
        return h > 1.0 ? 1.0 : h;
    }
    return (mode == SPR_Q8_FLOOR ? floor(x * 255.0) : floor(x * 255.0 + 0.5)) / 255.0;
}

/* Colour of every splat from its coefficients, seen from eye (or along
 * view_dir), clamped to [0, hi] (hi < 0: below only); at most the first
 * kmax coefficients; dc8: the DC part (0.5 + Y_0·sh_0) stored in 8 bits
 * before the rest is added. */
static void sh_eval(const spr_cloud *c, const double eye[3], const double *view_dir, double hi, int kmax, int dc8, int post8, float *color)
{
    const int K = c->sh_k > kmax ? kmax : c->sh_k;
#pragma omp parallel for schedule(static)
    for (long i = 0; i < (long)c->n; i++) {
        double d[3], l = 0.0, Y[16];
        for (int k = 0; k < 3; k++) {
            d[k] = view_dir ? view_dir[k] : (double)c->pos[3 * i + k] - eye[k];
            l += d[k] * d[k];
        }
        l = sqrt(l);
        if (!(l > 0.0)) l = 1.0, d[0] = d[1] = 0.0, d[2] = 1.0; /* the eye on the centre: any direction */
        sh_basis(d[0] / l, d[1] / l, d[2] / l, Y);
        const float *s = c->sh + (size_t)i * (size_t)c->sh_k * 3;
        for (int ch = 0; ch < 3; ch++) {
            double v = 0.5;
            for (int k = 0; k < K; k++) {
                v += Y[k] * s[3 * k + ch];
                if (k == 0) v = spr_unorm8(v, dc8);
            }
            color[3 * i + ch] = (float)spr_unorm8(v < 0.0 ? 0.0 : hi >= 0.0 && v > hi ? hi : v, post8);
        }
    }
}

void spr_cloud_sh_colors(const spr_cloud *c, const double eye[3], const double *view_dir, float *color)
{
    if (!c->sh || c->sh_k < 1) return;
    sh_eval(c, eye, view_dir, 1.0, 16, 0, 0, color);
}

void spr_cloud_gauss_colors(const spr_cloud *c, const double eye[3], float *color) { spr_cloud_gauss_colors_as(c, eye, 3, 0, 0, 0, color); }

void spr_cloud_gauss_colors_as(const spr_cloud *c, const double eye[3], int sh_max, int dc8, int post8, int clamp_hi, float *color)
{
    if (!c->sh || c->sh_k < 1) {
        for (size_t i = 0; i < 3 * c->n; i++) {
            const double v = spr_unorm8(c->color[i], dc8);
            color[i] = (float)spr_unorm8(clamp_hi && v > 1.0 ? 1.0 : v, post8);
        }
        return;
    }
    sh_eval(c, eye, NULL, clamp_hi ? 1.0 : -1.0, (sh_max + 1) * (sh_max + 1), dc8, post8, color);
}

void spr_cloud_gauss_colors_bwd(const spr_cloud *c, const double eye[3], int sh_max, size_t i, const float vc[3], double *vsh, double vmu[3])
{
    const int K = c->sh_k > (sh_max + 1) * (sh_max + 1) ? (sh_max + 1) * (sh_max + 1) : c->sh_k;
    for (int k = 0; k < 3 * K; k++) vsh[k] = 0.0;
    vmu[0] = vmu[1] = vmu[2] = 0.0;
    if (!c->sh || K < 1) return;
    double p[3], l = 0.0, Y[16], dY[16][3], d[3];
    for (int a = 0; a < 3; a++) {
        p[a] = (double)c->pos[3 * i + a] - eye[a];
        l += p[a] * p[a];
    }
    l = sqrt(l);
    const int at_eye = !(l > 0.0);
    if (at_eye) l = 1.0, p[0] = p[1] = 0.0, p[2] = 1.0; /* as sh_eval: any direction, which does not move with μ */
    for (int a = 0; a < 3; a++) d[a] = p[a] / l;
    sh_basis_grad(d[0], d[1], d[2], Y, dY);
    const float *s = c->sh + i * (size_t)c->sh_k * 3;
    double vd[3] = {0.0, 0.0, 0.0};
    for (int ch = 0; ch < 3; ch++) {
        double v = 0.5;
        for (int k = 0; k < K; k++) v += Y[k] * s[3 * k + ch];
        if (v < 0.0) continue; /* max(0, ·): no gradient where it clamps */
        for (int k = 0; k < K; k++) {
            vsh[3 * k + ch] = Y[k] * vc[ch];
            for (int a = 0; a < 3; a++) vd[a] += vc[ch] * s[3 * k + ch] * dY[k][a];
        }
    }
    if (at_eye) return;
    const double dot = vd[0] * d[0] + vd[1] * d[1] + vd[2] * d[2];
    for (int a = 0; a < 3; a++) vmu[a] = (vd[a] - dot * d[a]) / l;
}

void spr__surfel_frame(const spr_cloud *c, size_t i, double q[4], double *ru, double *rv)
{
    const float *nf = c->nrm + 3 * i;
    double n[3] = {nf[0], nf[1], nf[2]}, u[3], v[3];
    *ru = *rv = c->radius[i];
    if (c->ell && c->ell[4 * i + 3] != c->radius[i]) {
        for (int k = 0; k < 3; k++) u[k] = c->ell[4 * i + k];
        *rv = c->ell[4 * i + 3];
    } else {
        int ax = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0 : fabs(n[1]) <= fabs(n[2]) ? 1 : 2;
        double e[3] = {ax == 0, ax == 1, ax == 2};
        u[0] = n[1] * e[2] - n[2] * e[1], u[1] = n[2] * e[0] - n[0] * e[2], u[2] = n[0] * e[1] - n[1] * e[0];
    }
    double lu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int k = 0; k < 3; k++) u[k] /= lu;
    v[0] = n[1] * u[2] - n[2] * u[1], v[1] = n[2] * u[0] - n[0] * u[2], v[2] = n[0] * u[1] - n[1] * u[0];
    spr__quat_of_columns(u, v, n, q);
}
