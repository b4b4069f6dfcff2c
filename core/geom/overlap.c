/* overlap.c — the fixed disk sample pattern and the areas built on it. */
#include "spr_overlap.h"

#include <math.h>
#include <pthread.h>

static double pattern[SPR_DISK_SAMPLES][2];
/* the same pattern as columns u, v and u² + v² (for the vectorised count) */
static double pat_u[SPR_DISK_SAMPLES], pat_v[SPR_DISK_SAMPLES], pat_w[SPR_DISK_SAMPLES];
static pthread_once_t pattern_once = PTHREAD_ONCE_INIT;

static void make_pattern(void)
{
    for (int a = 0; a < 16; a++)
        for (int b = 0; b < 16; b++) {
            double rho = sqrt((a + 0.5) / 16.0), th = 2.0 * M_PI * (b + 0.5 * (a & 1) + 0.5) / 16.0;
            pattern[16 * a + b][0] = rho * cos(th);
            pattern[16 * a + b][1] = rho * sin(th);
        }
    for (int s = 0; s < SPR_DISK_SAMPLES; s++) {
        pat_u[s] = pattern[s][0];
        pat_v[s] = pattern[s][1];
        pat_w[s] = pattern[s][0] * pattern[s][0] + pattern[s][1] * pattern[s][1];
    }
}

/* The samples of one pair that count: |h| ≤ ε and |x − p_j|² − h² ≤ r_j²
 * (spr_overlap_areas).  Branch-free over columns so the compiler vectorises
 * it; the count is an integer, so any vector width gives the same number.
 * AVX2 where the CPU has it (no FMA: the same roundings as the scalar loop). */
__attribute__((target_clones("avx2", "default")))
static int count_hits(double h0, double a, double b, double D2, double c1, double c2, double ri2, double rj2, double eps)
{
    int hit = 0;
    for (int s = 0; s < SPR_DISK_SAMPLES; s++) {
        double h = h0 + pat_u[s] * a + pat_v[s] * b;
        double q2 = D2 + pat_u[s] * c1 + pat_v[s] * c2 + ri2 * pat_w[s];
        hit += (fabs(h) <= eps) & (q2 - h * h <= rj2);
    }
    return hit;
}

static void frame(const float *n, double e1[3], double e2[3])
{
    /* the axis least aligned with n, crossed with n */
    int k = 0;
    if (fabsf(n[1]) < fabsf(n[k])) k = 1;
    if (fabsf(n[2]) < fabsf(n[k])) k = 2;
    double a[3] = {0, 0, 0};
    a[k] = 1.0;
    e1[0] = a[1] * n[2] - a[2] * n[1];
    e1[1] = a[2] * n[0] - a[0] * n[2];
    e1[2] = a[0] * n[1] - a[1] * n[0];
    double l = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int i = 0; i < 3; i++) e1[i] /= l;
    e2[0] = n[1] * e1[2] - n[2] * e1[1];
    e2[1] = n[2] * e1[0] - n[0] * e1[2];
    e2[2] = n[0] * e1[1] - n[1] * e1[0];
}

/* Disk j (centre p, normal n) covers sample x when h = (x − p)·n has |h| ≤ ε
 * and x's projection onto the disk's plane lies within r_j of p.  Tested for
 * every sample (columns x, y, z), or-ed into cov; returns how many samples
 * are covered now.  Branch-free so the compiler vectorises it (AVX2 where the
 * CPU has it, no FMA: the same roundings as a scalar loop; the count is an
 * integer). */
__attribute__((target_clones("avx2", "default")))
static int cover_mask(const double *x, const double *y, const double *z, const float *p, const float *n, double rj2, double eps,
                      unsigned char *cov)
{
    const double px = p[0], py = p[1], pz = p[2], nx = n[0], ny = n[1], nz = n[2];
    int hit = 0;
    for (int s = 0; s < SPR_DISK_SAMPLES; s++) {
        double qx = x[s] - px, qy = y[s] - py, qz = z[s] - pz;
        double h = qx * nx + qy * ny + qz * nz;
        qx -= h * nx, qy -= h * ny, qz -= h * nz;
        cov[s] |= (fabs(h) <= eps) & (qx * qx + qy * qy + qz * qz <= rj2);
        hit += cov[s];
    }
    return hit;
}

/* Samples of disk i (radius ri) in a stack buffer: the frame is computed once. */
static void samples(const spr_cloud *c, size_t i, double ri, double (*xs)[3])
{
    pthread_once(&pattern_once, make_pattern);
    double e1[3], e2[3];
    frame(c->nrm + 3 * i, e1, e2);
    for (int s = 0; s < SPR_DISK_SAMPLES; s++)
        for (int k = 0; k < 3; k++) xs[s][k] = c->pos[3 * i + k] + ri * (pattern[s][0] * e1[k] + pattern[s][1] * e2[k]);
}

/* A_ij for every j of js: the samples of disk i are x = p_i + r_i(u e1 + v e2),
 * so with D = p_i − p_j both tests are linear/quadratic in (u, v):
 *     h      = D·n_j + r_i (u e1·n_j + v e2·n_j)
 *     |x−p_j|² = |D|² + 2 r_i (u D·e1 + v D·e2) + r_i² (u² + v²)
 * and a sample counts when |h| ≤ ε and |x − p_j|² − h² ≤ r_j². */
void spr_overlap_areas(const spr_cloud *c, size_t i, const uint32_t *js, size_t m, double eps, float *out)
{
    pthread_once(&pattern_once, make_pattern);
    double e1[3], e2[3], ri = c->radius[i];
    frame(c->nrm + 3 * i, e1, e2);
    const float *pi = c->pos + 3 * i;
    for (size_t k = 0; k < m; k++) {
        size_t j = js[k];
        if (k + 4 < m) { /* the neighbours are scattered over the cloud: their data fetched ahead (a hint, no arithmetic) */
            size_t jn = js[k + 4];
            __builtin_prefetch(c->pos + 3 * jn);
            __builtin_prefetch(c->nrm + 3 * jn);
            __builtin_prefetch(c->radius + jn);
        }
        const float *pj = c->pos + 3 * j, *nj = c->nrm + 3 * j;
        double D[3] = {(double)pi[0] - pj[0], (double)pi[1] - pj[1], (double)pi[2] - pj[2]};
        double h0 = D[0] * nj[0] + D[1] * nj[1] + D[2] * nj[2];
        double a = ri * (e1[0] * nj[0] + e1[1] * nj[1] + e1[2] * nj[2]), b = ri * (e2[0] * nj[0] + e2[1] * nj[1] + e2[2] * nj[2]);
        double D2 = D[0] * D[0] + D[1] * D[1] + D[2] * D[2];
        double c1 = 2.0 * ri * (D[0] * e1[0] + D[1] * e1[1] + D[2] * e1[2]), c2 = 2.0 * ri * (D[0] * e2[0] + D[1] * e2[1] + D[2] * e2[2]);
        double rj = c->radius[j], rj2 = rj * rj, ri2 = ri * ri;
        /* Whole pairs decided without sampling, with a margin far above the
         * rounding of the per-sample tests: every sample has u² + v² < 1, so
         * h lies within h0 ± √(a² + b²) and the projected distance to p_j
         * within |D_⊥| ± r_i. */
        const double Rh = sqrt(a * a + b * b), dperp = sqrt(D2 - h0 * h0 > 0.0 ? D2 - h0 * h0 : 0.0);
        const double slack = 1e-6 * (sqrt(D2) + ri + rj + eps);
        int hit;
        if (fabs(h0) - Rh > eps + slack || dperp - ri > rj + slack) hit = 0; /* no sample counts */
        else if (fabs(h0) + Rh < eps - slack && dperp + ri < rj - slack) hit = SPR_DISK_SAMPLES; /* every sample counts */
        else hit = count_hits(h0, a, b, D2, c1, c2, ri2, rj2, eps);
        out[k] = (float)(M_PI * ri2 * hit / SPR_DISK_SAMPLES);
    }
}

double spr_overlap_area(const spr_cloud *c, size_t i, size_t j, double eps)
{
    uint32_t jj = (uint32_t)j;
    float a;
    spr_overlap_areas(c, i, &jj, 1, eps, &a);
    return a;
}

/* 1 when disk j (radius rj) can cover no sample of disk i (radius ri, frame
 * e1, e2): the whole-pair bound of spr_overlap_areas, with the same margin far
 * above the rounding of the per-sample test, so dropping j changes no count. */
static int out_of_reach(const spr_cloud *c, size_t i, double ri, const double e1[3], const double e2[3], size_t j, double rj, double eps)
{
    const float *pi = c->pos + 3 * i, *pj = c->pos + 3 * j, *nj = c->nrm + 3 * j;
    double D[3] = {(double)pi[0] - pj[0], (double)pi[1] - pj[1], (double)pi[2] - pj[2]};
    double h0 = D[0] * nj[0] + D[1] * nj[1] + D[2] * nj[2];
    double a = ri * (e1[0] * nj[0] + e1[1] * nj[1] + e1[2] * nj[2]), b = ri * (e2[0] * nj[0] + e2[1] * nj[1] + e2[2] * nj[2]);
    double D2 = D[0] * D[0] + D[1] * D[1] + D[2] * D[2];
    const double Rh = sqrt(a * a + b * b), dperp = sqrt(D2 - h0 * h0 > 0.0 ? D2 - h0 * h0 : 0.0);
    const double slack = 1e-6 * (sqrt(D2) + ri + rj + eps);
    return fabs(h0) - Rh > eps + slack || dperp - ri > rj + slack;
}

double spr_clipped_area(const spr_cloud *c, size_t i, double own_scale, const uint32_t *cover, size_t m, double cover_scale,
                        double eps)
{
    if (!m) return 0.0;
    double ri = (double)c->radius[i] * own_scale;
    double xs[SPR_DISK_SAMPLES][3];
    samples(c, i, ri, xs);
    /* the neighbours that can reach the disk, in the given order (a sample
     * counts once whichever covers it, so the order does not change the count) */
    double e1[3], e2[3];
    frame(c->nrm + 3 * i, e1, e2);
    enum { NEAR_MAX = 512 };
    uint32_t near[NEAR_MAX];
    const uint32_t *js = cover;
    size_t nj = m;
    if (m <= NEAR_MAX) {
        nj = 0;
        for (size_t k = 0; k < m; k++) {
            size_t j = cover[k];
            if (j != i && !out_of_reach(c, i, ri, e1, e2, j, (double)c->radius[j] * cover_scale, eps)) near[nj++] = (uint32_t)j;
        }
        js = near;
        if (!nj) return 0.0;
    }
    double cx[SPR_DISK_SAMPLES], cy[SPR_DISK_SAMPLES], cz[SPR_DISK_SAMPLES];
    for (int s = 0; s < SPR_DISK_SAMPLES; s++) cx[s] = xs[s][0], cy[s] = xs[s][1], cz[s] = xs[s][2];
    unsigned char cov[SPR_DISK_SAMPLES] = {0};
    int hit = 0;
    for (size_t k = 0; k < nj && hit < SPR_DISK_SAMPLES; k++) {
        size_t j = js[k];
        if (j == i) continue;
        double rj = (double)c->radius[j] * cover_scale;
        hit = cover_mask(cx, cy, cz, c->pos + 3 * j, c->nrm + 3 * j, rj * rj, eps, cov);
    }
    return M_PI * ri * ri * hit / SPR_DISK_SAMPLES;
}
