/* overlap.c — the fixed disk sample pattern and the areas built on it. */
#include "spr_overlap.h"

#include <math.h>
#include <pthread.h>

static double pattern[SPR_DISK_SAMPLES][2];
/* the same pattern as columns u, v and u² + v² (for the vectorised count) */
static double pat_u[SPR_DISK_SAMPLES], pat_v[SPR_DISK_SAMPLES], pat_w[SPR_DISK_SAMPLES];
/* ρ_k: the radius of ring k (every sample of the ring has u² + v² = ρ_k², up to rounding) */
static double ring_rho[SPR_DISK_RINGS];
static pthread_once_t pattern_once = PTHREAD_ONCE_INIT;

static void make_pattern(void)
{
    for (int a = 0; a < 16; a++)
        for (int b = 0; b < 16; b++) {
            double rho = ring_rho[a] = sqrt((a + 0.5) / 16.0), th = 2.0 * M_PI * (b + 0.5 * (a & 1) + 0.5) / 16.0;
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
 * (spr_overlap_areas), ring by ring.  On ring k every sample has
 * u² + v² = ρ_k², so h lies within h0 ± ρ_k √(a² + b²) and the projected
 * distance to p_j within d_⊥ ± ρ_k r_i: a ring wholly outside (or inside)
 * both tests, by a margin far above their rounding (whole_pair), counts 0
 * (or 16) without its samples; the others are sampled.  Branch-free within
 * a ring so the compiler vectorises it; the count is an integer, so any
 * vector width gives the same number.  AVX2 where the CPU has it (no FMA:
 * the same roundings as the scalar loop). */
typedef struct pair_bounds { double ah0, Rh, dperp, slack; } pair_bounds;
/* The samples at radius ρ of the pattern decided together: every one (n),
 * none (0), or −1 when they must be tested one by one. */
static inline int decided(const pair_bounds *pb, double rho, double ri, double rj, double eps, int n)
{
    if (pb->ah0 - rho * pb->Rh > eps + pb->slack || pb->dperp - rho * ri > rj + pb->slack) return 0;
    if (pb->ah0 + rho * pb->Rh < eps - pb->slack && pb->dperp + rho * ri < rj - pb->slack) return n;
    return -1;
}
/* The samples of ring k that count, one by one (branch-free, so the
 * compiler vectorises it inside its callers' clones). */
static inline int64_t ring_hits(int k, double h0, double a, double b, double D2, double c1, double c2, double ri2, double rj2, double eps)
{
    const double *u = pat_u + k * (SPR_DISK_SAMPLES / SPR_DISK_RINGS), *v = pat_v + k * (SPR_DISK_SAMPLES / SPR_DISK_RINGS),
                 *w = pat_w + k * (SPR_DISK_SAMPLES / SPR_DISK_RINGS);
    int64_t ring = 0;
    for (int s = 0; s < SPR_DISK_SAMPLES / SPR_DISK_RINGS; s++) {
        double h = h0 + u[s] * a + v[s] * b;
        double q2 = D2 + u[s] * c1 + v[s] * c2 + ri2 * w[s];
        ring += (fabs(h) <= eps) & (q2 - h * h <= rj2);
    }
    return ring;
}

__attribute__((target_clones("avx2", "default")))
static int count_hits(double h0, double a, double b, double D2, double c1, double c2, double ri, double rj, double eps, const pair_bounds *pb)
{
    const double ri2 = ri * ri, rj2 = rj * rj;
    int64_t hit = 0;
    for (int k = 0; k < SPR_DISK_RINGS; k++) {
        const int whole = decided(pb, ring_rho[k], ri, rj, eps, SPR_DISK_SAMPLES / SPR_DISK_RINGS);
        hit += whole >= 0 ? whole : ring_hits(k, h0, a, b, D2, c1, c2, ri2, rj2, eps);
    }
    return (int)hit;
}

/* Whether a sample of the pair counts, ring by ring as count_hits, stopping
 * at the first ring with a hit: the same per-sample arithmetic, so it says
 * "none" exactly when count_hits counts 0. */
__attribute__((target_clones("avx2", "default")))
static int any_hit(double h0, double a, double b, double D2, double c1, double c2, double ri, double rj, double eps, const pair_bounds *pb)
{
    const double ri2 = ri * ri, rj2 = rj * rj;
    for (int k = 0; k < SPR_DISK_RINGS; k++) {
        const int whole = decided(pb, ring_rho[k], ri, rj, eps, SPR_DISK_SAMPLES / SPR_DISK_RINGS);
        if (whole > 0 || (whole < 0 && ring_hits(k, h0, a, b, D2, c1, c2, ri2, rj2, eps))) return 1;
    }
    return 0;
}

void spr__disk_frame(const float *n, double e1[3], double e2[3])
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

/* Samples of disk i (radius ri, frame e1, e2) as columns x, y, z. */
static void samples(const spr_cloud *c, size_t i, double ri, const double e1[3], const double e2[3], double *x, double *y, double *z)
{
    pthread_once(&pattern_once, make_pattern);
    double *col[3] = {x, y, z};
    for (int s = 0; s < SPR_DISK_SAMPLES; s++)
        for (int k = 0; k < 3; k++) col[k][s] = c->pos[3 * i + k] + ri * (pattern[s][0] * e1[k] + pattern[s][1] * e2[k]);
}

/* The terms of disk i (p_i, radius ri, frame e1, e2) against disk j's plane
 * (p_j, n_j), with D = p_i − p_j: a sample x = p_i + r_i(u e1 + v e2) has
 * h = h0 + u a + v b. */
typedef struct pair_terms { double D[3], h0, a, b, D2; } pair_terms;
static void pair_terms_of(const float *pi, double ri, const double e1[3], const double e2[3], const float *pj, const float *nj, pair_terms *t)
{
    for (int k = 0; k < 3; k++) t->D[k] = (double)pi[k] - pj[k];
    t->h0 = t->D[0] * nj[0] + t->D[1] * nj[1] + t->D[2] * nj[2];
    t->a = ri * (e1[0] * nj[0] + e1[1] * nj[1] + e1[2] * nj[2]);
    t->b = ri * (e2[0] * nj[0] + e2[1] * nj[1] + e2[2] * nj[2]);
    t->D2 = t->D[0] * t->D[0] + t->D[1] * t->D[1] + t->D[2] * t->D[2];
}

/* Whole pairs decided without sampling, with a margin far above the rounding
 * of the per-sample tests (and of unit normals stored as floats): every
 * sample has u² + v² < 1, so h lies within h0 ± √(a² + b²) and the projected
 * distance to p_j within |D_⊥| ± r_i.  0: no sample counts; SPR_DISK_SAMPLES:
 * every one does; -1: the samples decide. */
static int whole_pair(const pair_terms *t, double ri, double rj, double eps, pair_bounds *pb)
{
    pb->ah0 = fabs(t->h0);
    pb->Rh = sqrt(t->a * t->a + t->b * t->b);
    pb->dperp = sqrt(t->D2 - t->h0 * t->h0 > 0.0 ? t->D2 - t->h0 * t->h0 : 0.0);
    pb->slack = 1e-6 * (sqrt(t->D2) + ri + rj + eps);
    return decided(pb, 1.0, ri, rj, eps, SPR_DISK_SAMPLES);
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
    spr__disk_frame(c->nrm + 3 * i, e1, e2);
    const float *pi = c->pos + 3 * i;
    for (size_t k = 0; k < m; k++) {
        size_t j = js[k];
        if (k + 4 < m) { /* the neighbours are scattered over the cloud: their data fetched ahead (a hint, no arithmetic) */
            size_t jn = js[k + 4];
            __builtin_prefetch(c->pos + 3 * jn);
            __builtin_prefetch(c->nrm + 3 * jn);
            __builtin_prefetch(c->radius + jn);
        }
        pair_terms t;
        pair_terms_of(pi, ri, e1, e2, c->pos + 3 * j, c->nrm + 3 * j, &t);
        double rj = c->radius[j];
        pair_bounds pb;
        int hit = whole_pair(&t, ri, rj, eps, &pb);
        if (hit < 0) {
            const double *D = t.D;
            double c1 = 2.0 * ri * (D[0] * e1[0] + D[1] * e1[1] + D[2] * e1[2]), c2 = 2.0 * ri * (D[0] * e2[0] + D[1] * e2[1] + D[2] * e2[2]);
            hit = count_hits(t.h0, t.a, t.b, t.D2, c1, c2, ri, rj, eps, &pb);
        }
        out[k] = (float)(M_PI * (ri * ri) * hit / SPR_DISK_SAMPLES);
    }
}

void spr_overlap_row_init(spr_overlap_row *row, const spr_cloud *c, size_t i, double eps)
{
    pthread_once(&pattern_once, make_pattern);
    row->c = c;
    row->i = i;
    row->eps = eps;
    row->ri = c->radius[i];
    spr__disk_frame(c->nrm + 3 * i, row->e1, row->e2);
    /* a sample's area as out[] of spr_overlap_areas rounds it for one hit */
    row->tiny = !((float)(M_PI * (row->ri * row->ri) * 1 / SPR_DISK_SAMPLES) > 0.0f);
}

int spr_overlap_row_positive(const spr_overlap_row *row, size_t j)
{
    const spr_cloud *c = row->c;
    if (row->tiny) { /* one sample's area rounds to 0: count them all */
        const uint32_t jj = (uint32_t)j;
        float a;
        spr_overlap_areas(c, row->i, &jj, 1, row->eps, &a);
        return a > 0.0f;
    }
    const double ri = row->ri, *e1 = row->e1, *e2 = row->e2;
    pair_terms t;
    pair_terms_of(c->pos + 3 * row->i, ri, e1, e2, c->pos + 3 * j, c->nrm + 3 * j, &t);
    const double rj = c->radius[j];
    pair_bounds pb;
    const int hit = whole_pair(&t, ri, rj, row->eps, &pb);
    if (hit >= 0) return hit > 0;
    const double *D = t.D;
    const double c1 = 2.0 * ri * (D[0] * e1[0] + D[1] * e1[1] + D[2] * e1[2]), c2 = 2.0 * ri * (D[0] * e2[0] + D[1] * e2[1] + D[2] * e2[2]);
    return any_hit(t.h0, t.a, t.b, t.D2, c1, c2, ri, rj, row->eps, &pb);
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
    double e1[3], e2[3];
    spr__disk_frame(c->nrm + 3 * i, e1, e2);
    double x[SPR_DISK_SAMPLES], y[SPR_DISK_SAMPLES], z[SPR_DISK_SAMPLES];
    samples(c, i, ri, e1, e2, x, y, z);
    /* a sample counts once whichever neighbour covers it; neighbours that
     * cannot reach the disk (whole_pair) are passed over */
    unsigned char cov[SPR_DISK_SAMPLES] = {0};
    int hit = 0;
    for (size_t k = 0; k < m && hit < SPR_DISK_SAMPLES; k++) {
        size_t j = cover[k];
        if (j == i) continue;
        double rj = (double)c->radius[j] * cover_scale;
        pair_terms t;
        pair_terms_of(c->pos + 3 * i, ri, e1, e2, c->pos + 3 * j, c->nrm + 3 * j, &t);
        pair_bounds pb;
        if (whole_pair(&t, ri, rj, eps, &pb) == 0) continue;
        hit = cover_mask(x, y, z, c->pos + 3 * j, c->nrm + 3 * j, rj * rj, eps, cov);
    }
    return M_PI * ri * ri * hit / SPR_DISK_SAMPLES;
}
