/* test_domain.c — SPEC §7.1–7.3: local analysis, the multi-scale soft
 * decomposition (partition of unity at every level), domains, and the
 * sparse product they rest on, against hand values. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "spr_domain.h"
#include "spr_algo.h"
#include "spr_swrast.h"
#include "test_util.h"

/* [[1 2] [0 3]] · [[4 0] [5 6]] = [[14 12] [15 18]] exactly; the row
 * [1, 0.001] times the identity with drop 0.01 keeps one entry, rescaled to
 * the row's former sum 1.001. */
START_TEST(csr_product_by_hand)
{
    size_t pa[3] = {0, 2, 3}, pb[3] = {0, 1, 3};
    uint32_t ca[3] = {0, 1, 1}, cb[3] = {0, 0, 1};
    double va[3] = {1, 2, 3}, vb[3] = {4, 5, 6};
    spr_csr A = {2, 2, pa, ca, va}, Bm = {2, 2, pb, cb, vb}, C;
    spr_error err;
    ck_assert_int_eq(spr_csr_mul(&A, &Bm, 0.0, &C, &err), SPR_OK);
    ck_assert_uint_eq(C.ptr[2], 4);
    double want[4] = {14, 12, 15, 18};
    for (int x = 0; x < 4; x++) ck_assert_double_eq(C.val[x], want[x]);
    ck_assert_uint_eq(C.col[0], 0);
    ck_assert_uint_eq(C.col[1], 1);
    spr_csr_free(&C);
    size_t pi[3] = {0, 1, 2}, pr[2] = {0, 2};
    uint32_t ci[2] = {0, 1}, cr[2] = {0, 1};
    double vi[2] = {1, 1}, vr[2] = {1, 0.001};
    spr_csr R = {1, 2, pr, cr, vr}, I = {2, 2, pi, ci, vi};
    ck_assert_int_eq(spr_csr_mul(&R, &I, 0.01, &C, &err), SPR_OK);
    ck_assert_uint_eq(C.ptr[1], 1);
    ck_assert_double_eq_tol(C.val[0], 1.001, 1e-15);
    spr_csr_free(&C);
}
END_TEST

/* A flat grid has σ = 0 and normals ±z; on a unit sphere σ is small and
 * the normals radial. */
START_TEST(local_analysis_flat_and_sphere)
{
    spr_cloud c;
    ck_assert_int_eq(spr_cloud_alloc(&c, 400), SPR_OK);
    for (int i = 0; i < 400; i++) c.pos[3 * i] = (float)(i % 20), c.pos[3 * i + 1] = (float)(i / 20), c.pos[3 * i + 2] = 0.0f;
    spr_local la;
    spr_error err;
    ck_assert_int_eq(spr_local_analysis(&c, 10, 1, NULL, &la, &err), SPR_OK);
    for (int i = 0; i < 400; i++) {
        ck_assert_double_le(la.sigma[i], 1e-12);
        ck_assert_double_ge(fabs(la.normal[3 * i + 2]), 1.0 - 1e-6);
    }
    spr_local_free(&la);
    spr_cloud_free(&c);
    c = tu_builtin("builtin:sphere", 4000);
    ck_assert_int_eq(spr_local_analysis(&c, 10, 2, NULL, &la, &err), SPR_OK);
    double worst = 0.0, smax = 0.0;
    for (size_t i = 0; i < c.n; i++) {
        const float *p = c.pos + 3 * i, *n = la.normal + 3 * i;
        double dot = fabs(p[0] * n[0] + p[1] * n[1] + p[2] * n[2]);
        if (1.0 - dot > worst) worst = 1.0 - dot;
        if (la.sigma[i] > smax) smax = la.sigma[i];
    }
    printf("domain: sphere 4000, k = 10: largest 1 - |n·radial| %.2g, largest sigma %.3g\n", worst, smax);
    ck_assert_double_le(worst, 1e-3);
    ck_assert_double_le(smax, 0.01);
    spr_local_free(&la);
    spr_cloud_free(&c);
}
END_TEST

/* Every level: entries ≥ 0, every row sums to 1 within 1e-6 (SPEC §7.2),
 * regions growing from level 0 (coarsest) on; strict domains cover every
 * point; thresholded domains hold exactly the points with φ ≥ K.  On the
 * octahedron (cube) some level has 8 (6) regions and none of its strict
 * domains holds points of two faces (the faces come from the coordinates). */
static int octa_face(const float *p) { return (p[0] < 0) + 2 * (p[1] < 0) + 4 * (p[2] < 0); }
static int cube_face(const float *p)
{
    int ax = fabsf(p[0]) >= fabsf(p[1]) && fabsf(p[0]) >= fabsf(p[2]) ? 0 : fabsf(p[1]) >= fabsf(p[2]) ? 1 : 2;
    return 2 * ax + (p[ax] < 0);
}

static void check_levels(const char *name, const spr_cloud *c, int (*face_of)(const float *), size_t faces)
{
    int found = 0;
    spr_decomp_desc d;
    spr_decomp_defaults(&d);
    d.threads = 2;
    spr_decomp dc;
    spr_error err = {0};
    ck_assert_msg(spr_decompose(c, &d, &dc, &err) == SPR_OK, "%s: %s", name, err.msg);
    ck_assert_int_ge(dc.levels, 2);
    char counts[2048] = "";
    size_t o = 0;
    int32_t *dom = malloc(c->n * sizeof *dom);
    double worst_all = 0.0;
    for (int l = 0; l < dc.levels; l++) {
        const spr_csr *B = &dc.basis[l];
        ck_assert_uint_eq(B->rows, c->n);
        ck_assert_uint_eq(B->cols, dc.regions[l]);
        if (l > 0) ck_assert_uint_gt(dc.regions[l], dc.regions[l - 1]);
        double worst = 0.0;
        for (size_t i = 0; i < B->rows; i++) {
            double s = 0.0;
            for (size_t p = B->ptr[i]; p < B->ptr[i + 1]; p++) {
                ck_assert_msg(B->val[p] >= 0.0, "%s level %d: phi %g < 0", name, l, B->val[p]);
                s += B->val[p];
            }
            if (fabs(s - 1.0) > worst) worst = fabs(s - 1.0);
        }
        ck_assert_msg(worst <= 1e-6, "%s level %d: partition of unity off by %g", name, l, worst);
        if (worst > worst_all) worst_all = worst;
        spr_domain_strict(B, dom);
        for (size_t i = 0; i < c->n; i++) ck_assert(dom[i] >= 0 && (size_t)dom[i] < dc.regions[l]);
        spr_csr T;
        ck_assert_int_eq(spr_domain_members(B, 0, 0.01, &T, &err), SPR_OK);
        size_t want = 0;
        for (size_t p = 0; p < B->ptr[B->rows]; p++) want += B->val[p] >= 0.01;
        ck_assert_uint_eq(T.ptr[T.rows], want);
        spr_csr_free(&T);
        ck_assert_int_eq(spr_domain_members(B, 1, 0.01, &T, &err), SPR_OK); /* strict: each point once, in its argmax row */
        ck_assert_uint_eq(T.ptr[T.rows], c->n);
        for (size_t j = 0; j < T.rows; j++)
            for (size_t q = T.ptr[j]; q < T.ptr[j + 1]; q++) ck_assert_int_eq(dom[T.col[q]], (int32_t)j);
        spr_csr_free(&T);
        /* ridge respect on the flat-faced built-ins: strict domains holding points of two faces */
        int impure = -1;
        if (face_of) {
            impure = 0;
            int32_t *first = malloc(dc.regions[l] * sizeof *first);
            for (size_t j = 0; j < dc.regions[l]; j++) first[j] = -1;
            unsigned char *mixed = calloc(dc.regions[l], 1);
            for (size_t i = 0; i < c->n; i++) {
                int f = face_of(c->pos + 3 * i);
                if (first[dom[i]] < 0) first[dom[i]] = f;
                else if (first[dom[i]] != f && !mixed[dom[i]]) mixed[dom[i]] = 1, impure++;
            }
            free(first);
            free(mixed);
        }
        o += (size_t)snprintf(counts + o, sizeof counts - o, "%s%zu", l ? " " : "", dc.regions[l]);
        if (impure >= 0) o += (size_t)snprintf(counts + o, sizeof counts - o, "(%d mixed)", impure);
        if (faces && dc.regions[l] == faces && impure == 0) found = 1;
    }
    printf("domain: %s, %zu points: %d levels, regions %s, largest |sum phi - 1| %.2g (analysis %.0f ms, coarsening and basis %.0f ms)\n",
           name, c->n, dc.levels, counts, worst_all, dc.ms_analysis, dc.ms_coarsen);
    free(dom);
    spr_decomp_free(&dc);
    /* issue 11: at the level with one region per flat face, no strict domain crosses a crease */
    if (faces) ck_assert_msg(found, "%s: no level of %zu regions whose strict domains each stay on one face", name, faces);
}

START_TEST(partition_of_unity_every_level)
{
    static const char *const models[] = {"builtin:octahedron", "builtin:cube", "builtin:torus", "builtin:sphere"};
    for (int m = 0; m < 4; m++) {
        spr_cloud c = tu_model(models[m], 8000);
        check_levels(models[m], &c, m == 0 ? octa_face : m == 1 ? cube_face : NULL, m == 0 ? 8 : m == 1 ? 6 : 0);
        spr_cloud_free(&c);
    }
    spr_cloud c = tu_model("meshes/bunny00.off", 0);
    check_levels("bunny00.off", &c, NULL, 0);
    spr_cloud_free(&c);
}
END_TEST

/* Strict and thresholded domains of a hand basis: rows (0.6, 0.4),
 * (0.5, 0.5) (tie: the lower region), (0.005, 0.995). */
START_TEST(domains_by_hand)
{
    size_t ptr[4] = {0, 2, 4, 6};
    uint32_t col[6] = {0, 1, 0, 1, 0, 1};
    double val[6] = {0.6, 0.4, 0.5, 0.5, 0.005, 0.995};
    spr_csr B = {3, 2, ptr, col, val};
    int32_t dom[3];
    spr_domain_strict(&B, dom);
    ck_assert_int_eq(dom[0], 0);
    ck_assert_int_eq(dom[1], 0);
    ck_assert_int_eq(dom[2], 1);
    spr_csr T;
    spr_error err;
    ck_assert_int_eq(spr_domain_members(&B, 0, 0.01, &T, &err), SPR_OK);
    ck_assert_uint_eq(T.rows, 2);
    ck_assert_uint_eq(T.ptr[1], 2); /* region 0: points 0, 1 (not 2: 0.005 < 0.01) */
    ck_assert_uint_eq(T.ptr[2], 5); /* region 1: points 0, 1, 2 */
    ck_assert_uint_eq(T.col[0], 0);
    ck_assert_uint_eq(T.col[1], 1);
    ck_assert_uint_eq(T.col[4], 2);
    spr_csr_free(&T);
}
END_TEST

/* A level whose textures would take more than 2^25 texels is refused
 * before any texture is made: a flat 20 × 20 grid (spacing 1) of splats of
 * radius 0.00516 in three domains that each hold every point.  Each
 * rectangle is about 19 × 1.05 ≈ 19.96 a side, each texture
 * ceil(19.96/0.00516)² ≈ 1.5·10⁷ texels (under one texture's 2^24), the
 * three 4.5·10⁷ > 2^25: one error, at once, nothing allocated. */
START_TEST(level_texel_budget_refused_early)
{
    spr_cloud c;
    ck_assert_int_eq(spr_cloud_alloc(&c, 400), SPR_OK);
    size_t ptr[401];
    uint32_t col[1200];
    double val[1200];
    for (int i = 0; i < 400; i++) {
        c.pos[3 * i] = (float)(i % 20), c.pos[3 * i + 1] = (float)(i / 20), c.pos[3 * i + 2] = 0.0f;
        c.radius[i] = 0.00516f;
        ptr[i] = 3 * (size_t)i;
        for (int d = 0; d < 3; d++) col[3 * i + d] = (uint32_t)d, val[3 * i + d] = 1.0 / 3.0;
    }
    ptr[400] = 1200;
    spr_csr B = {400, 3, ptr, col, val};
    spr_prims_desc pd;
    spr_prims_defaults(&pd);
    spr_rects rects;
    spr_prims_stats st;
    spr_error err = {0};
    const double t0 = spr_now_ms();
    ck_assert_int_eq(spr_domain_prims(&c, &B, &pd, &rects, &st, &err), SPR_E_TOO_LARGE);
    const double ms = spr_now_ms() - t0;
    printf("domain: texel budget: %s (%.0f ms)\n", err.msg, ms);
    ck_assert_msg(strstr(err.msg, "3 textures would take") && strstr(err.msg, "--texel") && !strchr(err.msg, '\n'), "%s", err.msg);
    ck_assert_msg(ms < 2000.0, "refused after %.0f ms: the textures were made first", ms);
    ck_assert_ptr_null(rects.f);
    spr_cloud_free(&c);
}
END_TEST

/* A flat 20×10 grid (spacing 1, z = 0.3, normals +z, radius 0.5) is one
 * rectangle with zero error: normal +z, u along x, extents 19 × 9 grown by
 * 5% to 19.95 × 9.45 about the centre, or 21 × 10.5 with the radii.
 * Tilted to the normal (0, 0.6, 0.8), the error stays at float rounding. */
START_TEST(flat_square_one_rectangle)
{
    for (int tilt = 0; tilt < 2; tilt++) {
        spr_cloud c;
        ck_assert_int_eq(spr_cloud_alloc(&c, 200), SPR_OK);
        uint32_t idx[200];
        for (int i = 0; i < 200; i++) {
            double x = i % 20, y = i / 20, z = 0.3;
            double p[3] = {x, tilt ? y * 0.8 - z * 0.6 : y, tilt ? y * 0.6 + z * 0.8 : z};
            for (int d = 0; d < 3; d++) c.pos[3 * i + d] = (float)p[d];
            c.nrm[3 * i] = 0.0f, c.nrm[3 * i + 1] = tilt ? -0.6f : 0.0f, c.nrm[3 * i + 2] = tilt ? 0.8f : 1.0f;
            c.radius[i] = 0.5f;
            idx[i] = (uint32_t)i;
        }
        spr_polygon pg;
        spr_error err;
        for (int rad = 0; rad < 2; rad++) {
            ck_assert_int_eq(spr_support_polygon(&c, idx, NULL, 200, 0.05, rad, &pg, &err), SPR_OK);
            const double want_n[3] = {0, tilt ? -0.6 : 0, tilt ? 0.8 : 1};
            for (int d = 0; d < 3; d++) ck_assert_double_eq_tol(pg.normal[d], want_n[d], 1e-6);
            ck_assert_double_eq_tol(fabs(pg.u[0]), 1.0, 1e-9);
            double cross_ok = fabs(pg.v[0] - (pg.normal[1] * pg.u[2] - pg.normal[2] * pg.u[1])) + fabs(pg.v[1] - (pg.normal[2] * pg.u[0] - pg.normal[0] * pg.u[2]));
            ck_assert_double_le(cross_ok, 1e-12);
            const double hu = rad ? 10.5 : 9.975, hv = rad ? 5.25 : 4.725;
            ck_assert_double_eq_tol(pg.umin, -hu, 1e-5);
            ck_assert_double_eq_tol(pg.umax, hu, 1e-5);
            ck_assert_double_eq_tol(pg.vmin, -hv, 1e-5);
            ck_assert_double_eq_tol(pg.vmax, hv, 1e-5);
            ck_assert_double_le(pg.error, tilt ? 1e-6 : 1e-12);
            ck_assert_double_le(pg.flatness, tilt ? 1e-12 : 1e-20);
        }
        printf("domain: flat grid%s: error %.3g (normalised %.3g), rectangle %.4f..%.4f × %.4f..%.4f\n", tilt ? " tilted" : "", pg.error,
               pg.error_norm, pg.umin, pg.umax, pg.vmin, pg.vmax);
        spr_cloud_free(&c);
    }
}
END_TEST

/* One point at the origin (radius 1, colour (0.2, 0.4, 0.6), basis value
 * 1) on a 4 × 4 rectangle with texel 0.25 and support w·r = 1.5: with
 * Eq. 3.3 (normalise where f ≥ 1) every texel's alpha is the kernel at its
 * distance d — 1 − d/1.5 (linear), 1 (constant), exp(−ρ²/(2·(1/3)²)) with
 * ρ = d/1.5 (gauss, to the polynomial's 1e-6) — and its colour the kernel
 * times the point's colour; with Eq. 3.4 (f > 0) alpha is 1 and the colour
 * the point's wherever the kernel is positive; outside the support alpha is
 * 0, and with "extend colour" the colour is still the point's. */
START_TEST(radial_texture_of_one_point)
{
    spr_cloud c;
    ck_assert_int_eq(spr_cloud_alloc(&c, 1), SPR_OK);
    c.radius[0] = 1.0f;
    c.color[0] = 0.2f, c.color[1] = 0.4f, c.color[2] = 0.6f;
    spr_polygon pg = {.centroid = {0, 0, 0}, .normal = {0, 0, 1}, .u = {1, 0, 0}, .v = {0, 1, 0}, .umin = -2, .umax = 2, .vmin = -2, .vmax = 2};
    uint32_t idx = 0;
    double phi = 1.0;
    for (int shape = 0; shape < 3; shape++)
        for (int norm = 0; norm < 2; norm++) {
            spr_texture_desc td = {0.25, 1.5, (spr_rbf)shape, (spr_rbf_norm)norm, 1};
            spr_texture t;
            spr_error err;
            ck_assert_int_eq(spr_texture_radial(&c, &idx, &phi, 1, &pg, &td, &t, &err), SPR_OK);
            ck_assert_int_eq(t.w, 16);
            ck_assert_int_eq(t.h, 16);
            for (int y = 0; y < 16; y++)
                for (int x = 0; x < 16; x++) {
                    const double tu = -2 + (x + 0.5) * 0.25, tv = -2 + (y + 0.5) * 0.25, d = sqrt(tu * tu + tv * tv), rho = d / 1.5;
                    double k = d > 1.5 ? 0.0 : shape == SPR_RBF_CONSTANT ? 1.0 : shape == SPR_RBF_LINEAR ? 1.0 - rho : exp(-rho * rho * 4.5);
                    const float *q = t.rgba + 4 * (y * 16 + x);
                    const double want_a = norm == SPR_NORM_GE1 ? k : (k > 0.0 ? 1.0 : 0.0);
                    ck_assert_msg(fabs(q[3] - want_a) < 2e-6, "shape %d norm %d texel (%d,%d): alpha %.7g, kernel %.7g", shape, norm, x, y,
                                  q[3], want_a);
                    const double cscale = k > 0.0 ? want_a : 1.0; /* extend colour: the point's colour where f = 0 */
                    for (int ch = 0; ch < 3; ch++)
                        ck_assert_msg(fabs(q[ch] - cscale * c.color[ch]) < 2e-6, "shape %d norm %d texel (%d,%d) channel %d: %.7g", shape,
                                      norm, x, y, ch, q[ch]);
                }
            spr_texture_free(&t);
        }
    spr_cloud_free(&c);
}
END_TEST

/* Merging (SPEC §7.6) on the cube: from a level with more regions than
 * faces, merging flat domains whose normals agree (dot > 0.9) stops at the
 * six faces (neighbouring faces' normals are at 90°), strict domains stay on
 * one face and the merged basis is still a partition of unity; the faces
 * share no point, so lifting the limits merges nothing more, while on the
 * sphere, where neighbouring regions overlap, everything becomes one. */
START_TEST(merge_flat_domains_of_the_cube)
{
    spr_cloud c = tu_model("builtin:cube", 6000);
    spr_decomp dc;
    spr_decomp_desc d;
    spr_decomp_defaults(&d);
    spr_error err = {0};
    ck_assert_msg(spr_decompose(&c, &d, &dc, &err) == SPR_OK, "%s", err.msg);
    int l = 0;
    while (l < dc.levels && dc.regions[l] < 24) l++;
    ck_assert_int_lt(l, dc.levels);
    spr_csr M;
    size_t merges;
    ck_assert_int_eq(spr_domain_merge(&c, &dc.basis[l], 0.01, 0.05, 0.9, &M, &merges, &err), SPR_OK);
    printf("domain: cube level %d, %zu regions -> %zu after %zu merges\n", l, dc.regions[l], M.cols, merges);
    ck_assert_uint_eq(M.cols, 6);
    int32_t *dom = malloc(c.n * sizeof *dom);
    spr_domain_strict(&M, dom);
    int face_of_region[6] = {-1, -1, -1, -1, -1, -1};
    for (size_t i = 0; i < c.n; i++) {
        double s = 0.0;
        for (size_t q = M.ptr[i]; q < M.ptr[i + 1]; q++) s += M.val[q];
        ck_assert_double_le(fabs(s - 1.0), 1e-6);
        const int f = cube_face(c.pos + 3 * i);
        if (face_of_region[dom[i]] < 0) face_of_region[dom[i]] = f;
        ck_assert_int_eq(face_of_region[dom[i]], f);
    }
    spr_csr_free(&M);
    /* the faces share no point (the coupling across a right angle is 0): no limits merge nothing more */
    ck_assert_int_eq(spr_domain_merge(&c, &dc.basis[l], 0.01, 2.0, -2.0, &M, &merges, &err), SPR_OK);
    ck_assert_uint_eq(M.cols, 6);
    spr_csr_free(&M);
    free(dom);
    spr_decomp_free(&dc);
    spr_cloud_free(&c);
    /* the octahedron's faces do overlap across their 109° creases: the
     * normal limit alone stops the merging at the eight faces */
    c = tu_model("builtin:octahedron", 8000);
    ck_assert_msg(spr_decompose(&c, &d, &dc, &err) == SPR_OK, "%s", err.msg);
    l = 0;
    while (l < dc.levels && dc.regions[l] < 24) l++;
    ck_assert_int_eq(spr_domain_merge(&c, &dc.basis[l], 0.01, 0.05, 0.9, &M, &merges, &err), SPR_OK);
    printf("domain: octahedron level %d, %zu regions -> %zu after %zu merges\n", l, dc.regions[l], M.cols, merges);
    ck_assert_uint_eq(M.cols, 8);
    spr_csr_free(&M);
    ck_assert_int_eq(spr_domain_merge(&c, &dc.basis[l], 0.01, 2.0, -2.0, &M, &merges, &err), SPR_OK);
    ck_assert_uint_eq(M.cols, 1);
    spr_csr_free(&M);
    spr_decomp_free(&dc);
    spr_cloud_free(&c);
    /* on the sphere every region overlaps its neighbours: no limits merge all */
    c = tu_model("builtin:sphere", 4000);
    ck_assert_msg(spr_decompose(&c, &d, &dc, &err) == SPR_OK, "%s", err.msg);
    l = 0;
    while (l < dc.levels && dc.regions[l] < 8) l++;
    ck_assert_int_eq(spr_domain_merge(&c, &dc.basis[l], 0.01, 2.0, -2.0, &M, &merges, &err), SPR_OK);
    printf("domain: sphere level %d, %zu regions -> %zu after %zu merges without limits\n", l, dc.regions[l], M.cols, merges);
    ck_assert_uint_eq(M.cols, 1);
    for (size_t i = 0; i < c.n; i++) ck_assert_double_le(fabs(M.val[M.ptr[i]] - 1.0), 1e-6);
    spr_csr_free(&M);
    spr_decomp_free(&dc);
    spr_cloud_free(&c);
}
END_TEST

/* The affine texture reproduces a linear colour ramp exactly (to float
 * storage) at every texel centre inside the triangulation: a 10 × 10 grid
 * (spacing 1, radius 0.8, so every Delaunay edge is kept) coloured
 * r = 0.05·x + 0.02·y + 0.1, g = 0.5, b = 0.03·x, basis 1. */
START_TEST(affine_texture_reproduces_a_ramp)
{
    spr_cloud c;
    ck_assert_int_eq(spr_cloud_alloc(&c, 100), SPR_OK);
    uint32_t idx[100];
    for (int i = 0; i < 100; i++) {
        const double x = i % 10, y = i / 10;
        c.pos[3 * i] = (float)x, c.pos[3 * i + 1] = (float)y, c.pos[3 * i + 2] = 0.0f;
        c.radius[i] = 0.8f;
        c.color[3 * i] = (float)(0.05 * x + 0.02 * y + 0.1), c.color[3 * i + 1] = 0.5f, c.color[3 * i + 2] = (float)(0.03 * x);
        idx[i] = (uint32_t)i;
    }
    spr_polygon pg;
    spr_error err;
    ck_assert_int_eq(spr_support_polygon(&c, idx, NULL, 100, 0.05, 1, &pg, &err), SPR_OK);
    spr_texture_desc td = {0.3, 1.0, SPR_RBF_LINEAR, SPR_NORM_GT0, 0};
    spr_texture t;
    size_t ntri;
    ck_assert_msg(spr_texture_affine(&c, idx, NULL, 100, &pg, &td, &t, &ntri, &err) == SPR_OK, "%s", err.msg);
    ck_assert_uint_eq(ntri, 162); /* 81 cells, two triangles each */
    int inside = 0;
    double worst = 0.0;
    for (int y = 0; y < t.h; y++)
        for (int x = 0; x < t.w; x++) {
            const double tu = pg.umin + (x + 0.5) * t.texel, tv = pg.vmin + (y + 0.5) * t.texel;
            double X = pg.centroid[0] + tu * pg.u[0] + tv * pg.v[0], Y = pg.centroid[1] + tu * pg.u[1] + tv * pg.v[1];
            if (!(X > 1e-9 && X < 9 - 1e-9 && Y > 1e-9 && Y < 9 - 1e-9)) continue;
            inside++;
            const float *q = t.rgba + 4 * ((size_t)y * t.w + x);
            const double want[4] = {0.05 * X + 0.02 * Y + 0.1, 0.5, 0.03 * X, 1.0};
            for (int k = 0; k < 4; k++)
                if (fabs(q[k] - want[k]) > worst) worst = fabs(q[k] - want[k]);
        }
    printf("domain: affine ramp, %d×%d texels, %d inside the triangulation, largest error %.2g\n", t.w, t.h, inside, worst);
    ck_assert_int_gt(inside, 1000);
    ck_assert_double_le(worst, 2e-7);
    spr_texture_free(&t);
    spr_cloud_free(&c);
}
END_TEST

/* One rectangle of the hand scenes: centre (0, 0, z), half side 1, normal
 * ±z, one texel (colour, alpha) over the whole rectangle. */
static void hand_rect(spr_rects *r, int k, float z, float nz, const float rgba[4])
{
    float *f = r->f + (size_t)k * SPR_RECT_FLOATS;
    f[SPR_RECT_C + 2] = z;
    f[SPR_RECT_N + 2] = nz;
    f[SPR_RECT_U] = 1.0f;
    f[SPR_RECT_V + 1] = nz; /* v = n × u */
    f[SPR_RECT_UMIN] = f[SPR_RECT_VMIN] = -1.0f;
    f[SPR_RECT_UMAX] = f[SPR_RECT_VMAX] = 1.0f;
    f[SPR_RECT_TEXEL] = 2.0f;
    uint32_t *I = r->i + (size_t)k * SPR_RECTI_COUNT;
    I[SPR_RECTI_TW] = I[SPR_RECTI_TH] = 1;
    I[SPR_RECTI_OFF] = (uint32_t)k;
    I[SPR_RECTI_DOMAIN] = (uint32_t)k;
    memcpy(r->texels + 4 * (size_t)k, rgba, 4 * sizeof(float));
    spr_rects_link(r, (size_t)k, (size_t)k); /* its own neighbour */
}

/* Render the hand rectangles with algo on the CPU, 9×9 from (0, 0, 5)
 * towards the origin; the centre pixel's colour into px. */
static void hand_render(const spr_rects *r, spr_algo algo, const float bg[3], float px[4])
{
    spr_camera_desc cam;
    spr_camera_defaults(&cam);
    cam.width = cam.height = 9;
    cam.eye[2] = 5.0;
    cam.have_eye = cam.have_target = 1;
    cam.near_plane = 1.0;
    cam.far_plane = 10.0;
    spr_view v;
    spr_error err = {0};
    ck_assert_msg(spr_view_make(&cam, &v, &err) == SPR_OK, "%s", err.msg);
    spr_cloud c = tu_builtin("builtin:sphere", 100);
    spr_backend *b = spr_swrast_create(1, &err);
    ck_assert_ptr_nonnull(b);
    spr_render_desc d;
    memset(&d, 0, sizeof d);
    d.algo = algo;
    d.rects = r;
    d.sampling = SPR_SAMPLE_NEAREST;
    memcpy(d.background, bg, sizeof d.background);
    spr_render_result out;
    ck_assert_msg(spr_render(b, &v, &c, &d, &out, &err) == SPR_OK, "%s", err.msg);
    memcpy(px, out.rgba + 4 * (4 * 9 + 4), 4 * sizeof(float));
    spr_render_result_free(&out);
    spr_backend_destroy(b);
    spr_cloud_free(&c);
}

/* SPEC 7.7 prefix by hand: A (z = 0, red, α ½) and B (z = −0.1, green,
 * α ½) are neighbours, C (z = −0.5, blue, α 1) is not; the centre pixel
 * is A + B = (½·1, ½·1, 0) exactly, C left out, whatever the order. */
START_TEST(prefix_sums_the_front_and_its_neighbour)
{
    spr_rects r;
    spr_error err = {0};
    ck_assert_int_eq(spr_rects_alloc(&r, 3, 3, &err), SPR_OK);
    hand_rect(&r, 0, -0.5f, 1.0f, (const float[4]){0, 0, 1, 1}); /* C first in the set: the order must not matter */
    hand_rect(&r, 1, 0.0f, 1.0f, (const float[4]){1, 0, 0, 0.5f});
    hand_rect(&r, 2, -0.1f, 1.0f, (const float[4]){0, 1, 0, 0.5f});
    spr_rects_link(&r, 1, 2);
    float px[4];
    hand_render(&r, SPR_ALGO_DOMAIN_PREFIX, (const float[3]){0, 0, 0}, px);
    ck_assert_msg(px[0] == 0.5f && px[1] == 0.5f && px[2] == 0.0f && px[3] == 1.0f, "prefix: %g %g %g %g", px[0], px[1], px[2], px[3]);
    /* blendall sums all three: (½, ½, 1) */
    hand_render(&r, SPR_ALGO_DOMAIN_BLENDALL, (const float[3]){0, 0, 0}, px);
    ck_assert_msg(px[0] == 0.5f && px[1] == 0.5f && px[2] == 1.0f, "blendall: %g %g %g", px[0], px[1], px[2]);
    spr_rects_free(&r);
}
END_TEST

/* SPEC 7.7 darkback by hand: a front face (z = −0.5, white, α 1) behind a
 * back face (z = 0, normal −z): back to front, the front face adds white,
 * then the back face resets the pixel to black — black, not the
 * background; soft subtracts α = 1 and clamps: black too. */
START_TEST(darkback_hard_blackens_behind_a_back_face)
{
    spr_rects r;
    spr_error err = {0};
    ck_assert_int_eq(spr_rects_alloc(&r, 2, 2, &err), SPR_OK);
    hand_rect(&r, 0, -0.5f, 1.0f, (const float[4]){1, 1, 1, 1});
    hand_rect(&r, 1, 0.0f, -1.0f, (const float[4]){1, 1, 1, 1});
    const float bg[3] = {0.25f, 0.5f, 0.75f};
    float px[4];
    hand_render(&r, SPR_ALGO_DOMAIN_DARKBACK_HARD, bg, px);
    ck_assert_msg(px[0] == 0.0f && px[1] == 0.0f && px[2] == 0.0f && px[3] == 1.0f, "hard: %g %g %g %g", px[0], px[1], px[2], px[3]);
    hand_render(&r, SPR_ALGO_DOMAIN_DARKBACK_SOFT, bg, px);
    ck_assert_msg(px[0] == 0.0f && px[1] == 0.0f && px[2] == 0.0f, "soft: %g %g %g", px[0], px[1], px[2]);
    r.n = 1; /* without the back face the pixel is white */
    hand_render(&r, SPR_ALGO_DOMAIN_DARKBACK_HARD, bg, px);
    ck_assert_msg(px[0] == 1.0f && px[1] == 1.0f && px[2] == 1.0f, "front only: %g %g %g", px[0], px[1], px[2]);
    r.n = 2;
    spr_rects_free(&r);
}
END_TEST

Suite *make_domain_suite(void)
{
    Suite *s = suite_create("domain");
    TCase *tc = tcase_create("all");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, csr_product_by_hand);
    tcase_add_test(tc, local_analysis_flat_and_sphere);
    tcase_add_test(tc, partition_of_unity_every_level);
    tcase_add_test(tc, domains_by_hand);
    tcase_add_test(tc, flat_square_one_rectangle);
    tcase_add_test(tc, level_texel_budget_refused_early);
    tcase_add_test(tc, radial_texture_of_one_point);
    tcase_add_test(tc, merge_flat_domains_of_the_cube);
    tcase_add_test(tc, affine_texture_reproduces_a_ramp);
    tcase_add_test(tc, prefix_sums_the_front_and_its_neighbour);
    tcase_add_test(tc, darkback_hard_blackens_behind_a_back_face);
    suite_add_tcase(s, tc);
    return s;
}
