/* builtin.c — procedural models available with no file (SPEC §1).
 *
 * Each generator is deterministic (lattices, no random numbers); radii then
 * come from the radius rule like any file without radii.
 *   sphere      Fibonacci lattice on the unit sphere, coloured by normal
 *   torus       R = 1, r = 0.35 parameter grid, axis tilted 60° from +y toward +z
 *               (so the default +z view sees the hole), coloured by normal
 *   octahedron  |x|+|y|+|z| = 1, m² sub-triangle centroids per face, a colour per face ([R] §1.4)
 *   planes      two parallel 2×2 squares at z = 0 (red) and z = −0.5 (blue), α = 0.5
 *   spheres     two nested spheres, radius 1 (⅔ of the points, pale blue) and 0.5
 *               (⅓, orange), α = 0.5: four transparent layers through the middle
 *   cube        [−1,1]³, m×m cell centres per face, a colour per face
 */
#include "spr_io.h"

#include "spr_util.h"

#include <math.h>
#include <string.h>

const char *const spr_builtin_names[] = {"sphere", "torus", "octahedron", "planes", "cube", "spheres", NULL};

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

/* m points of a Fibonacci lattice on the sphere (centre (x, y, z), radius
 * R) into splats first … first + m − 1, normals outward. */
static void fibonacci_sphere(spr_cloud *c, size_t first, size_t m, double x, double y, double z, double R, const float *col)
{
    const double ga = M_PI * (3.0 - sqrt(5.0));
    for (size_t i = 0; i < m; i++) {
        double v = 1.0 - 2.0 * (i + 0.5) / m, rr = sqrt(1.0 - v * v), th = ga * i;
        double nx = rr * cos(th), nz = rr * sin(th);
        put(c, first + i, x + R * nx, y + R * v, z + R * nz, nx, v, nz, col);
    }
}

spr_result spr__builtin(const char *name, size_t n, spr_cloud *c, spr_error *err)
{
    if (n < 16 || n > SPR_MAX_SPLATS)
        return spr__fail(err, SPR_E_ARG, "builtin:%s: --points %zu outside 16..%u", name, n, SPR_MAX_SPLATS);
    spr_result r;
    if (!strcmp(name, "sphere")) {
        if ((r = spr_cloud_alloc(c, n))) return spr__fail(err, r, "builtin:sphere: out of memory");
        fibonacci_sphere(c, 0, n, 0.0, 0.0, 0.0, 1.0, NULL);
        spr_cloud_color_by_normal(c);
    } else if (!strcmp(name, "spheres")) {
        if ((r = spr_cloud_alloc(c, n))) return spr__fail(err, r, "builtin:spheres: out of memory");
        static const float pale[3] = {0.55f, 0.75f, 0.95f}, orange[3] = {0.95f, 0.55f, 0.15f};
        size_t outer = 2 * n / 3; /* equal density on both: area ratio 4 : 1, so ⅔ : ⅓ is a little denser inside */
        fibonacci_sphere(c, 0, outer, 0.0, 0.0, 0.0, 1.0, pale);
        fibonacci_sphere(c, outer, n - outer, 0.0, 0.0, 0.0, 0.5, orange);
        for (size_t i = 0; i < n; i++) c->alpha[i] = 0.5f;
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
        return spr__fail(err, SPR_E_ARG, "builtin:%s: unknown model (sphere, torus, octahedron, planes, cube, spheres)", name);
    }
    c->flags = SPR_SRC_NORMALS | SPR_SRC_COLORS | SPR_SRC_ALPHA;
    return SPR_OK;
}

/* Small opaque balls inside a closed model (SPEC §6, [ZP] Fig. 17–19): ball
 * radius 2.5% of the box diagonal; candidate centres q = p − 2.5·r_b·n_p
 * below surface points p taken in a fixed pseudo-random order; q is kept
 * when the nearest surface point m lies at least 1.5·r_b away and q is on
 * its inner side ((q − m)·n_m < 0: normals point outward) and q is 6·r_b
 * from every ball kept.  Each ball: 400 splats on a Fibonacci lattice, one
 * colour per ball, α = 1. */
spr_result spr__add_balls(spr_cloud *c, int nballs, spr_error *err)
{
    if (nballs <= 0) return SPR_OK;
    if (nballs > 64) return spr__fail(err, SPR_E_ARG, "--balls %d: at most 64", nballs);
    enum { PER_BALL = 400, TRIES = 4096 };
    spr_bounds b;
    spr_cloud_bounds(c, &b);
    double dg = 0.0;
    for (int k = 0; k < 3; k++) dg += ((double)b.hi[k] - b.lo[k]) * ((double)b.hi[k] - b.lo[k]);
    const double rb = 0.025 * sqrt(dg), sr = rb * sqrt(8.0 / PER_BALL);
    double centre[64][3];
    int kept = 0;
    uint64_t seed = 0x5eed0ba11ull;
    const size_t n = c->n;
    for (int t = 0; t < TRIES && kept < nballs; t++) {
        size_t i = (size_t)(spr__splitmix64(&seed) % n);
        const float *p = c->pos + 3 * i, *nn = c->nrm + 3 * i;
        double q[3];
        for (int k = 0; k < 3; k++) q[k] = p[k] - 2.5 * rb * nn[k];
        int ok = 1;
        for (int j = 0; j < kept && ok; j++) {
            double d2 = 0.0;
            for (int k = 0; k < 3; k++) d2 += (q[k] - centre[j][k]) * (q[k] - centre[j][k]);
            ok = d2 >= 36.0 * rb * rb;
        }
        if (!ok) continue;
        size_t m = 0;
        double best = INFINITY;
        for (size_t s = 0; s < n; s++) {
            const float *ps = c->pos + 3 * s;
            double dx = q[0] - ps[0], dy = q[1] - ps[1], dz = q[2] - ps[2], d2 = dx * dx + dy * dy + dz * dz;
            if (d2 < best) best = d2, m = s;
        }
        const float *pm = c->pos + 3 * m, *nm = c->nrm + 3 * m;
        double side = (q[0] - pm[0]) * nm[0] + (q[1] - pm[1]) * nm[1] + (q[2] - pm[2]) * nm[2];
        if (best < 2.25 * rb * rb || !(side < 0.0)) continue;
        memcpy(centre[kept++], q, sizeof q);
    }
    if (kept < nballs)
        return spr__fail(err, SPR_E_ARG, "--balls %d: found room for only %d balls inside the model (are its normals outward?)", nballs, kept);
    if (c->sh && c->sh_k > 1) return spr__fail(err, SPR_E_ARG, "--balls: not with view-dependent colours (--sh-degree above 0)");
    spr_cloud o;
    spr_result r = spr_cloud_alloc(&o, n + (size_t)nballs * PER_BALL);
    if (!r && c->ell && (r = spr_cloud_alloc_ell(&o))) spr_cloud_free(&o);
    if (r) return spr__fail(err, r, "--balls: out of memory");
    memcpy(o.pos, c->pos, 3 * n * sizeof(float));
    memcpy(o.nrm, c->nrm, 3 * n * sizeof(float));
    memcpy(o.color, c->color, 3 * n * sizeof(float));
    memcpy(o.radius, c->radius, n * sizeof(float));
    memcpy(o.alpha, c->alpha, n * sizeof(float));
    for (int j = 0; j < nballs; j++) {
        size_t first = n + (size_t)j * PER_BALL;
        fibonacci_sphere(&o, first, PER_BALL, centre[j][0], centre[j][1], centre[j][2], rb, face_colors[j % 8]);
        for (size_t i = first; i < first + PER_BALL; i++) o.radius[i] = (float)sr;
    }
    if (o.ell) { /* the model's ellipses, the balls' circles */
        memcpy(o.ell, c->ell, 4 * n * sizeof(float));
        for (size_t i = n; i < o.n; i++) o.ell[4 * i] = o.ell[4 * i + 1] = o.ell[4 * i + 2] = 0.0f, o.ell[4 * i + 3] = o.radius[i];
    }
    o.flags = c->flags;
    o.gauss_cut = c->gauss_cut;
    spr_cloud_free(c);
    *c = o;
    return SPR_OK;
}
