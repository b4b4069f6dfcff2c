/* texture.c — domain textures with radial basis functions (SPEC §7.5,
 * [R] §3.3.2).  The texture covers the support rectangle with square texels
 * of texel_factor × the domain's mean radius; texel (x, y) has its centre at
 * (umin + (x + ½)·h, vmin + (y + ½)·h).  Every projected point p spreads
 * φ_p(d) over the texels within w·r_p (constant, linear 1 − d/(w·r_p), or
 * the shared gauss polynomial of SPEC §3.1 in ρ = d/(w·r_p), i.e. σ =
 * w·r_p/3); f = Σ φ_p, colour Σ φ_p·g(p), alpha Σ φ_p·φ_j(p), normalised
 * per texel where f ≥ 1 (Eq. 3.3) or f > 0 (Eq. 3.4).  "Extend colour"
 * ([R] §3.3.4) gives texels no point reached the colour of the nearest
 * projected point, alpha staying 0.  Host-side, sums in double. */
#include "spr_domain.h"
#include "spr_arith_c.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void spr_texture_free(spr_texture *t)
{
    free(t->rgba);
    memset(t, 0, sizeof *t);
}

static double rbf(spr_rbf shape, double d, double support)
{
    if (!(d <= support)) return 0.0;
    const double rho = support > 0.0 ? d / support : 0.0;
    switch (shape) {
    case SPR_RBF_CONSTANT: return 1.0;
    case SPR_RBF_LINEAR: return 1.0 - rho;
    case SPR_RBF_GAUSS:
    default: {
        const float r = (float)rho;
        return spr_kernel_weight(SPR_KERNEL_GAUSS, r * r, r);
    }
    }
}

spr_result spr_texture_size(const spr_cloud *c, const uint32_t *idx, size_t m, const spr_polygon *pg, const spr_texture_desc *td,
                            double *texel, double *w, double *h, spr_error *err)
{
    if (m == 0) return spr__fail(err, SPR_E_VALUE, "texture: empty domain");
    if (!(td->texel_factor > 0.0) || !(td->width > 0.0)) return spr__fail(err, SPR_E_ARG, "texture: texel size and width must be > 0");
    double rmean = 0.0;
    for (size_t a = 0; a < m; a++) rmean += c->radius[idx[a]];
    rmean /= (double)m;
    const double t = td->texel_factor * rmean;
    const double wu = pg->umax - pg->umin, wv = pg->vmax - pg->vmin;
    *texel = t, *w = ceil(wu / t), *h = ceil(wv / t);
    if (!(*w >= 1.0 && *h >= 1.0) || *w * *h > 16777216.0)
        return spr__fail(err, SPR_E_TOO_LARGE, "texture: %g × %g texels (texel %g) for a %g × %g rectangle", *w, *h, t, wu, wv);
    return SPR_OK;
}

spr_result spr_texture_radial(const spr_cloud *c, const uint32_t *idx, const double *phi, size_t m, const spr_polygon *pg,
                              const spr_texture_desc *td, spr_texture *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    double h, W, H;
    spr_result sr = spr_texture_size(c, idx, m, pg, td, &h, &W, &H, err);
    if (sr) return sr;
    out->w = (int)W;
    out->h = (int)H;
    out->texel = h;
    const size_t nt = (size_t)out->w * (size_t)out->h;
    double *acc = calloc(nt * 5, sizeof *acc); /* f, r, g, b, alpha */
    double *pu = malloc(m * 2 * sizeof *pu);
    out->rgba = calloc(nt * 4, sizeof *out->rgba);
    if (!acc || !pu || !out->rgba) {
        free(acc);
        free(pu);
        spr_texture_free(out);
        return spr__fail(err, SPR_E_NOMEM, "texture: out of memory for %zu texels", nt);
    }
    for (size_t a = 0; a < m; a++) {
        const float *p = c->pos + 3 * (size_t)idx[a];
        const double q[3] = {p[0] - pg->centroid[0], p[1] - pg->centroid[1], p[2] - pg->centroid[2]};
        const double u = q[0] * pg->u[0] + q[1] * pg->u[1] + q[2] * pg->u[2], v = q[0] * pg->v[0] + q[1] * pg->v[1] + q[2] * pg->v[2];
        pu[2 * a] = u, pu[2 * a + 1] = v;
        const double s = td->width * c->radius[idx[a]];
        const int x0 = (int)floor((u - s - pg->umin) / h), x1 = (int)floor((u + s - pg->umin) / h);
        const int y0 = (int)floor((v - s - pg->vmin) / h), y1 = (int)floor((v + s - pg->vmin) / h);
        const double basis = phi ? phi[a] : 1.0;
        const float *g = c->color + 3 * (size_t)idx[a];
        for (int y = y0 < 0 ? 0 : y0; y <= y1 && y < out->h; y++)
            for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < out->w; x++) {
                const double tu = pg->umin + (x + 0.5) * h, tv = pg->vmin + (y + 0.5) * h;
                const double f = rbf(td->shape, sqrt((tu - u) * (tu - u) + (tv - v) * (tv - v)), s);
                if (f == 0.0) continue;
                double *t = acc + 5 * ((size_t)y * out->w + x);
                t[0] += f, t[1] += f * g[0], t[2] += f * g[1], t[3] += f * g[2], t[4] += f * basis;
            }
    }
    for (size_t i = 0; i < nt; i++) {
        const double *t = acc + 5 * i;
        const double f = t[0];
        const int norm = td->normalize == SPR_NORM_GE1 ? f >= 1.0 : f > 0.0;
        for (int k = 0; k < 4; k++) out->rgba[4 * i + k] = (float)(norm ? t[k + 1] / f : t[k + 1]);
        if (td->extend_color && f == 0.0) { /* the nearest projected point's colour */
            const double tu = pg->umin + ((double)(i % (size_t)out->w) + 0.5) * h, tv = pg->vmin + ((double)(i / (size_t)out->w) + 0.5) * h;
            size_t best = 0;
            double bd = INFINITY;
            for (size_t a = 0; a < m; a++) {
                const double d = (pu[2 * a] - tu) * (pu[2 * a] - tu) + (pu[2 * a + 1] - tv) * (pu[2 * a + 1] - tv);
                if (d < bd) bd = d, best = a;
            }
            for (int k = 0; k < 3; k++) out->rgba[4 * i + k] = c->color[3 * (size_t)idx[best] + k];
        }
    }
    free(acc);
    free(pu);
    return SPR_OK;
}
