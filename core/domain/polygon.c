/* polygon.c — support polygons of domains (SPEC §7.4, [R] §3.1–3.2).
 *
 *   plane:     weighted PCA (weights φ_j(p)) about the weighted centroid; the
 *              normal is the λ0 eigenvector, turned to agree with the
 *              weighted mean of the points' normals
 *   rectangle: the points projected onto the plane (optionally grown by
 *              their radii), the weighted 2D PCA of the projections gives
 *              the axes u, v (v = n × u), the bounding rectangle is enlarged
 *              about its centre by `enlarge` (0.05 = 5% wider and taller)
 *   error:     mean distance point ↔ projection over the domain's points,
 *              and that divided by their mean radius ([R] Table 5.2)
 * All host-side double arithmetic; the rectangle's corners are what a
 * renderer receives.
 */
#include "spr_domain.h"
#include "spr_pca.h"

#include <math.h>
#include <string.h>

spr_result spr_support_polygon(const spr_cloud *c, const uint32_t *idx, const double *phi, size_t m, double enlarge, int with_radii,
                               spr_polygon *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    double W = 0.0, cen[3] = {0, 0, 0}, nav[3] = {0, 0, 0};
    for (size_t a = 0; a < m; a++) {
        const double w = phi ? phi[a] : 1.0;
        const float *p = c->pos + 3 * (size_t)idx[a], *n = c->nrm + 3 * (size_t)idx[a];
        W += w;
        for (int d = 0; d < 3; d++) cen[d] += w * p[d], nav[d] += w * n[d];
    }
    if (m < 3 || !(W > 0.0)) return spr__fail(err, SPR_E_VALUE, "support polygon: %zu points of total weight %g", m, W);
    for (int d = 0; d < 3; d++) cen[d] /= W;
    double A[6] = {0};
    for (size_t a = 0; a < m; a++) {
        const double w = phi ? phi[a] : 1.0;
        const float *p = c->pos + 3 * (size_t)idx[a];
        const double q[3] = {p[0] - cen[0], p[1] - cen[1], p[2] - cen[2]};
        A[0] += w * q[0] * q[0]; A[1] += w * q[0] * q[1]; A[2] += w * q[0] * q[2];
        A[3] += w * q[1] * q[1]; A[4] += w * q[1] * q[2]; A[5] += w * q[2] * q[2];
    }
    double ev[3], evec[9];
    spr_eigen3_sym(A, ev, evec);
    double n[3] = {evec[0], evec[1], evec[2]}, e1[3] = {evec[3], evec[4], evec[5]}, e2[3] = {evec[6], evec[7], evec[8]};
    if (n[0] * nav[0] + n[1] * nav[1] + n[2] * nav[2] < 0.0)
        for (int d = 0; d < 3; d++) n[d] = -n[d];
    /* 2D weighted PCA of the projections in the (e1, e2) frame */
    double s11 = 0.0, s12 = 0.0, s22 = 0.0, err_sum = 0.0, r_sum = 0.0;
    for (size_t a = 0; a < m; a++) {
        const double w = phi ? phi[a] : 1.0;
        const float *p = c->pos + 3 * (size_t)idx[a];
        const double q[3] = {p[0] - cen[0], p[1] - cen[1], p[2] - cen[2]};
        const double x = q[0] * e1[0] + q[1] * e1[1] + q[2] * e1[2], y = q[0] * e2[0] + q[1] * e2[1] + q[2] * e2[2];
        s11 += w * x * x, s12 += w * x * y, s22 += w * y * y;
        err_sum += fabs(q[0] * n[0] + q[1] * n[1] + q[2] * n[2]);
        r_sum += c->radius[idx[a]];
    }
    const double th = 0.5 * atan2(2.0 * s12, s11 - s22), ct = cos(th), st = sin(th);
    double u[3], v[3];
    for (int d = 0; d < 3; d++) u[d] = ct * e1[d] + st * e2[d];
    v[0] = n[1] * u[2] - n[2] * u[1];
    v[1] = n[2] * u[0] - n[0] * u[2];
    v[2] = n[0] * u[1] - n[1] * u[0];
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t a = 0; a < m; a++) {
        const float *p = c->pos + 3 * (size_t)idx[a];
        const double q[3] = {p[0] - cen[0], p[1] - cen[1], p[2] - cen[2]};
        const double x = q[0] * u[0] + q[1] * u[1] + q[2] * u[2], y = q[0] * v[0] + q[1] * v[1] + q[2] * v[2];
        const double r = with_radii ? c->radius[idx[a]] : 0.0;
        if (x - r < lo[0]) lo[0] = x - r;
        if (x + r > hi[0]) hi[0] = x + r;
        if (y - r < lo[1]) lo[1] = y - r;
        if (y + r > hi[1]) hi[1] = y + r;
    }
    for (int k = 0; k < 2; k++) { /* grow about the centre */
        const double mid = 0.5 * (lo[k] + hi[k]), half = 0.5 * (hi[k] - lo[k]) * (1.0 + enlarge);
        lo[k] = mid - half;
        hi[k] = mid + half;
    }
    memcpy(out->centroid, cen, sizeof cen);
    memcpy(out->normal, n, sizeof n);
    memcpy(out->u, u, sizeof u);
    memcpy(out->v, v, sizeof v);
    out->umin = lo[0], out->umax = hi[0], out->vmin = lo[1], out->vmax = hi[1];
    out->points = m;
    out->error = err_sum / (double)m;
    out->error_norm = r_sum > 0.0 ? out->error / (r_sum / (double)m) : 0.0;
    out->flatness = ev[0] + ev[1] + ev[2] > 0.0 ? ev[0] / (ev[0] + ev[1] + ev[2]) : 0.0;
    return SPR_OK;
}
