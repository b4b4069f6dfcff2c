/* affine.c — domain textures with linear affine basis functions (SPEC §7.5,
 * [R] §3.3.3): the projected points are triangulated (qhull's 2D Delaunay,
 * "d Qbb Qt"), triangles with an edge longer than the sum of its two
 * endpoints' radii are removed (they bridge concavities and holes), and a
 * texel whose centre lies in a triangle takes the barycentric interpolation
 * of the corners' colours and basis values.  Texels outside every triangle
 * but within a point's radius take the radial linear texture there (Eq.
 * 3.4), texels beyond the nearest colour with "extend colour".  Fewer than
 * three points, or points qhull finds degenerate (collinear), give the
 * radial texture instead. */
#include "spr_domain.h"

#include <libqhull_r/qhull_ra.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The kept Delaunay triangles of the m 2D points xy: 3 indices each. */
static spr_result delaunay(const double *xy, size_t m, const double *radius, uint32_t **tri, size_t *nt, spr_error *err)
{
    *tri = NULL;
    *nt = 0;
    qhT qh_qh;
    qhT *qh = &qh_qh;
    QHULL_LIB_CHECK
    qh_zero(qh, NULL);
    double *pts = malloc(m * 2 * sizeof *pts);
    if (!pts) return spr__fail(err, SPR_E_NOMEM, "affine texture: out of memory");
    memcpy(pts, xy, m * 2 * sizeof *pts);
    char flags[] = "qhull d Qbb Qt Qz"; /* Qz: a point at infinity keeps cocircular inputs triangulable */
    int exitcode = qh_new_qhull(qh, 2, (int)m, pts, False, flags, NULL, NULL);
    spr_result r = SPR_OK;
    if (!exitcode) {
        size_t cap = 0;
        facetT *facet;
        FORALLfacets {
            if (facet->upperdelaunay) continue;
            uint32_t v[3];
            int k = 0;
            vertexT *vertex, **vertexp;
            FOREACHvertex_(facet->vertices) {
                if (k < 3) v[k] = (uint32_t)qh_pointid(qh, vertex->point);
                k++;
            }
            if (k != 3 || v[0] >= m || v[1] >= m || v[2] >= m) continue;
            int keep = 1; /* long edges removed */
            for (int e = 0; e < 3 && keep; e++) {
                const uint32_t a = v[e], b = v[(e + 1) % 3];
                const double dx = xy[2 * a] - xy[2 * b], dy = xy[2 * a + 1] - xy[2 * b + 1];
                keep = sqrt(dx * dx + dy * dy) <= radius[a] + radius[b];
            }
            if (!keep) continue;
            if (*nt == cap) {
                cap = cap ? 2 * cap : 64;
                uint32_t *nt2 = realloc(*tri, cap * 3 * sizeof *nt2);
                if (!nt2) { r = spr__fail(err, SPR_E_NOMEM, "affine texture: out of memory"); break; }
                *tri = nt2;
            }
            memcpy(*tri + 3 * *nt, v, sizeof v);
            (*nt)++;
        }
    }
    int curlong, totlong;
    qh_freeqhull(qh, !qh_ALL);
    qh_memfreeshort(qh, &curlong, &totlong);
    free(pts);
    if (r) { free(*tri); *tri = NULL; *nt = 0; }
    if (exitcode) *nt = 0; /* degenerate input: no triangle, the caller falls back */
    return r;
}

spr_result spr_texture_affine(const spr_cloud *c, const uint32_t *idx, const double *phi, size_t m, const spr_polygon *pg,
                              const spr_texture_desc *td, spr_texture *out, size_t *triangles, spr_error *err)
{
    *triangles = 0;
    /* the radial linear texture with Eq. 3.4 first: it fills what no triangle covers */
    spr_texture_desc rd = *td;
    rd.shape = SPR_RBF_LINEAR;
    rd.normalize = SPR_NORM_GT0;
    rd.width = 1.0;
    spr_result r = spr_texture_radial(c, idx, phi, m, pg, &rd, out, err);
    if (r || m < 3) return r;
    double *xy = malloc(m * 2 * sizeof *xy), *rad = malloc(m * sizeof *rad);
    if (!xy || !rad) { free(xy); free(rad); spr_texture_free(out); return spr__fail(err, SPR_E_NOMEM, "affine texture: out of memory"); }
    for (size_t a = 0; a < m; a++) {
        const float *p = c->pos + 3 * (size_t)idx[a];
        const double q[3] = {p[0] - pg->centroid[0], p[1] - pg->centroid[1], p[2] - pg->centroid[2]};
        xy[2 * a] = q[0] * pg->u[0] + q[1] * pg->u[1] + q[2] * pg->u[2];
        xy[2 * a + 1] = q[0] * pg->v[0] + q[1] * pg->v[1] + q[2] * pg->v[2];
        rad[a] = c->radius[idx[a]];
    }
    uint32_t *tri;
    size_t nt;
    r = delaunay(xy, m, rad, &tri, &nt, err);
    const double h = out->texel;
    for (size_t t = 0; !r && t < nt; t++) {
        const uint32_t *v = tri + 3 * t;
        const double ax = xy[2 * v[0]], ay = xy[2 * v[0] + 1], bx = xy[2 * v[1]], by = xy[2 * v[1] + 1], cx = xy[2 * v[2]], cy = xy[2 * v[2] + 1];
        const double det = (by - cy) * (ax - cx) + (cx - bx) * (ay - cy);
        if (det == 0.0) continue;
        const double lo_u = fmin(ax, fmin(bx, cx)), hi_u = fmax(ax, fmax(bx, cx)), lo_v = fmin(ay, fmin(by, cy)), hi_v = fmax(ay, fmax(by, cy));
        const int x0 = (int)floor((lo_u - pg->umin) / h - 0.5), x1 = (int)ceil((hi_u - pg->umin) / h - 0.5);
        const int y0 = (int)floor((lo_v - pg->vmin) / h - 0.5), y1 = (int)ceil((hi_v - pg->vmin) / h - 0.5);
        for (int y = y0 < 0 ? 0 : y0; y <= y1 && y < out->h; y++)
            for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < out->w; x++) {
                const double tu = pg->umin + (x + 0.5) * h, tv = pg->vmin + (y + 0.5) * h;
                const double l0 = ((by - cy) * (tu - cx) + (cx - bx) * (tv - cy)) / det;
                const double l1 = ((cy - ay) * (tu - cx) + (ax - cx) * (tv - cy)) / det;
                const double l2 = 1.0 - l0 - l1;
                if (l0 < 0.0 || l1 < 0.0 || l2 < 0.0) continue; /* on an edge: either triangle gives the same value */
                float *o = out->rgba + 4 * ((size_t)y * out->w + x);
                for (int k = 0; k < 3; k++)
                    o[k] = (float)(l0 * c->color[3 * (size_t)idx[v[0]] + k] + l1 * c->color[3 * (size_t)idx[v[1]] + k] +
                                   l2 * c->color[3 * (size_t)idx[v[2]] + k]);
                const double p0 = phi ? phi[v[0]] : 1.0, p1 = phi ? phi[v[1]] : 1.0, p2 = phi ? phi[v[2]] : 1.0;
                o[3] = (float)(l0 * p0 + l1 * p1 + l2 * p2);
            }
    }
    *triangles = nt;
    free(tri);
    free(xy);
    free(rad);
    if (r) spr_texture_free(out);
    return r;
}
