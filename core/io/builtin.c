/* builtin.c — procedural models available with no file (SPEC §1).
 *
 * Each generator is deterministic (lattices, no random numbers); radii then
 * come from the radius rule like any file without radii.
 *   sphere      Fibonacci lattice on the unit sphere, coloured by normal
 *   torus       R = 1, r = 0.35 parameter grid, axis tilted 60° from +y toward +z
 *               (so the default +z view sees the hole), coloured by normal
 *   octahedron  |x|+|y|+|z| = 1, m² sub-triangle centroids per face, a colour per face ([R] §1.4)
 *   planes      two parallel 2×2 squares at z = 0 (red) and z = −0.5 (blue), α = 0.5
 *   cube        [−1,1]³, m×m cell centres per face, a colour per face
 */
#include "spr_io.h"

#include <math.h>
#include <string.h>

const char *const spr_builtin_names[] = {"sphere", "torus", "octahedron", "planes", "cube", NULL};

static const float face_colors[8][3] = {
    {0.90f, 0.30f, 0.25f}, {0.25f, 0.70f, 0.30f}, {0.25f, 0.45f, 0.90f}, {0.95f, 0.80f, 0.25f},
    {0.70f, 0.35f, 0.85f}, {0.25f, 0.80f, 0.80f}, {0.95f, 0.55f, 0.20f}, {0.60f, 0.60f, 0.60f}};

static void put(spr_cloud *c, size_t i, double x, double y, double z, double nx, double ny, double nz, const float *col)
{
    c->pos[3 * i] = (float)x; c->pos[3 * i + 1] = (float)y; c->pos[3 * i + 2] = (float)z;
    c->nrm[3 * i] = (float)nx; c->nrm[3 * i + 1] = (float)ny; c->nrm[3 * i + 2] = (float)nz;
    spr__normalize3(c->nrm + 3 * i);
    if (col) memcpy(c->color + 3 * i, col, 3 * sizeof(float));
}

spr_result spr__builtin(const char *name, size_t n, spr_cloud *c, spr_error *err)
{
    if (n < 16 || n > SPR_MAX_SPLATS)
        return spr__fail(err, SPR_E_ARG, "builtin:%s: --points %zu outside 16..%u", name, n, SPR_MAX_SPLATS);
    spr_result r;
    if (!strcmp(name, "sphere")) {
        if ((r = spr_cloud_alloc(c, n))) return spr__fail(err, r, "builtin:sphere: out of memory");
        double ga = M_PI * (3.0 - sqrt(5.0));
        for (size_t i = 0; i < n; i++) {
            double y = 1.0 - 2.0 * (i + 0.5) / n, rr = sqrt(1.0 - y * y), th = ga * i;
            put(c, i, rr * cos(th), y, rr * sin(th), rr * cos(th), y, rr * sin(th), NULL);
        }
        spr_cloud_color_by_normal(c);
    } else if (!strcmp(name, "torus")) {
        const double R = 1.0, rt = 0.35;
        size_t nv = (size_t)floor(sqrt(n * rt / R)), nu;
        if (nv < 3) nv = 3;
        nu = n / nv;
        if ((r = spr_cloud_alloc(c, nu * nv))) return spr__fail(err, r, "builtin:torus: out of memory");
        for (size_t a = 0; a < nu; a++)
            for (size_t b = 0; b < nv; b++) {
                double u = 2.0 * M_PI * a / nu, v = 2.0 * M_PI * (b + 0.5 * (a & 1)) / nv;
                double nx = cos(v) * cos(u), ny = sin(v), nz = cos(v) * sin(u);
                double px = (R + rt * cos(v)) * cos(u), py = rt * sin(v), pz = (R + rt * cos(v)) * sin(u);
                const double ct = 0.5, st = 0.86602540378443865; /* cos, sin 60° */
                put(c, a * nv + b, px, py * ct - pz * st, py * st + pz * ct, nx, ny * ct - nz * st, ny * st + nz * ct, NULL);
            }
        spr_cloud_color_by_normal(c);
    } else if (!strcmp(name, "octahedron")) {
        size_t m = (size_t)floor(sqrt(n / 8.0));
        if (m < 1) m = 1;
        if ((r = spr_cloud_alloc(c, 8 * m * m))) return spr__fail(err, r, "builtin:octahedron: out of memory");
        size_t i = 0;
        for (int f = 0; f < 8; f++) {
            double sx = f & 1 ? -1 : 1, sy = f & 2 ? -1 : 1, sz = f & 4 ? -1 : 1;
            for (size_t a = 0; a < m; a++)
                for (size_t b = 0; a + b < m; b++)
                    for (int up = 0; up < 2; up++) {
                        if (!up && a + b + 1 >= m) continue;
                        double off = up ? 1.0 / 3.0 : 2.0 / 3.0;
                        double u = (a + off) / m, v = (b + off) / m;
                        double w = 1.0 - u - v;
                        put(c, i++, sx * u, sy * v, sz * w, sx, sy, sz, face_colors[f]);
                    }
        }
        c->n = i;
    } else if (!strcmp(name, "planes")) {
        size_t m = (size_t)floor(sqrt(n / 2.0));
        if (m < 2) m = 2;
        if ((r = spr_cloud_alloc(c, 2 * m * m))) return spr__fail(err, r, "builtin:planes: out of memory");
        static const float red[3] = {0.9f, 0.2f, 0.15f}, blue[3] = {0.15f, 0.3f, 0.9f};
        for (int pl = 0; pl < 2; pl++)
            for (size_t a = 0; a < m; a++)
                for (size_t b = 0; b < m; b++) {
                    size_t i = (size_t)pl * m * m + a * m + b;
                    put(c, i, -1.0 + 2.0 * (b + 0.5) / m, -1.0 + 2.0 * (a + 0.5) / m, pl ? -0.5 : 0.0, 0, 0, 1, pl ? blue : red);
                    c->alpha[i] = 0.5f;
                }
    } else if (!strcmp(name, "cube")) {
        size_t m = (size_t)floor(sqrt(n / 6.0));
        if (m < 2) m = 2;
        if ((r = spr_cloud_alloc(c, 6 * m * m))) return spr__fail(err, r, "builtin:cube: out of memory");
        size_t i = 0;
        for (int f = 0; f < 6; f++) {
            int ax = f / 2;
            double s = f & 1 ? -1.0 : 1.0;
            for (size_t a = 0; a < m; a++)
                for (size_t b = 0; b < m; b++) {
                    double p[3], nn[3] = {0, 0, 0};
                    p[ax] = s;
                    p[(ax + 1) % 3] = -1.0 + 2.0 * (a + 0.5) / m;
                    p[(ax + 2) % 3] = -1.0 + 2.0 * (b + 0.5) / m;
                    nn[ax] = s;
                    put(c, i++, p[0], p[1], p[2], nn[0], nn[1], nn[2], face_colors[f]);
                }
        }
    } else {
        return spr__fail(err, SPR_E_ARG, "builtin:%s: unknown model (sphere, torus, octahedron, planes, cube)", name);
    }
    c->flags = SPR_SRC_NORMALS | SPR_SRC_COLORS | SPR_SRC_ALPHA;
    return SPR_OK;
}
