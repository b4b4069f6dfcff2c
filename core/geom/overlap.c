/* overlap.c — the fixed disk sample pattern and the areas built on it. */
#include "spr_overlap.h"

#include <math.h>
#include <pthread.h>

static double pattern[SPR_DISK_SAMPLES][2];
static pthread_once_t pattern_once = PTHREAD_ONCE_INIT;

static void make_pattern(void)
{
    for (int a = 0; a < 16; a++)
        for (int b = 0; b < 16; b++) {
            double rho = sqrt((a + 0.5) / 16.0), th = 2.0 * M_PI * (b + 0.5 * (a & 1) + 0.5) / 16.0;
            pattern[16 * a + b][0] = rho * cos(th);
            pattern[16 * a + b][1] = rho * sin(th);
        }
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

static int covers(const spr_cloud *c, size_t j, double rj, double eps, const double x[3])
{
    const float *p = c->pos + 3 * j, *n = c->nrm + 3 * j;
    double q[3] = {x[0] - p[0], x[1] - p[1], x[2] - p[2]};
    double h = q[0] * n[0] + q[1] * n[1] + q[2] * n[2];
    if (fabs(h) > eps) return 0;
    for (int k = 0; k < 3; k++) q[k] -= h * n[k];
    return q[0] * q[0] + q[1] * q[1] + q[2] * q[2] <= rj * rj;
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
        const float *pj = c->pos + 3 * j, *nj = c->nrm + 3 * j;
        double D[3] = {(double)pi[0] - pj[0], (double)pi[1] - pj[1], (double)pi[2] - pj[2]};
        double h0 = D[0] * nj[0] + D[1] * nj[1] + D[2] * nj[2];
        double a = ri * (e1[0] * nj[0] + e1[1] * nj[1] + e1[2] * nj[2]), b = ri * (e2[0] * nj[0] + e2[1] * nj[1] + e2[2] * nj[2]);
        double D2 = D[0] * D[0] + D[1] * D[1] + D[2] * D[2];
        double c1 = 2.0 * ri * (D[0] * e1[0] + D[1] * e1[1] + D[2] * e1[2]), c2 = 2.0 * ri * (D[0] * e2[0] + D[1] * e2[1] + D[2] * e2[2]);
        double rj2 = (double)c->radius[j] * c->radius[j], ri2 = ri * ri;
        int hit = 0;
        for (int s = 0; s < SPR_DISK_SAMPLES; s++) {
            double u = pattern[s][0], v = pattern[s][1];
            double h = h0 + u * a + v * b;
            if (fabs(h) > eps) continue;
            double q2 = D2 + u * c1 + v * c2 + ri2 * (u * u + v * v);
            hit += q2 - h * h <= rj2;
        }
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

double spr_clipped_area(const spr_cloud *c, size_t i, double own_scale, const uint32_t *cover, size_t m, double cover_scale,
                        double eps)
{
    if (!m) return 0.0;
    double ri = (double)c->radius[i] * own_scale;
    double xs[SPR_DISK_SAMPLES][3];
    samples(c, i, ri, xs);
    int hit = 0;
    for (int s = 0; s < SPR_DISK_SAMPLES; s++)
        for (size_t k = 0; k < m; k++) {
            size_t j = cover[k];
            if (j == i) continue;
            if (covers(c, j, (double)c->radius[j] * cover_scale, eps, xs[s])) { hit++; break; }
        }
    return M_PI * ri * ri * hit / SPR_DISK_SAMPLES;
}
