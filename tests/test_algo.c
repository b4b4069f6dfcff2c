/* test_algo.c — SPEC §4.1/§4.2 on hand scenes, Voronoi depth, and the
 * deferred-vs-pbr2p1 agreement on the real bunny. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "spr_fragment.h"
#include "spr_image.h"
#include "test_util.h"
#include <omp.h>

/* Hand camera, 4×4: splat A at z = 0 (t = 0.5) red, splat B at z = zb blue,
 * both r = 0.5 around the axis, so both cover pixels (1..2, 1..2) with the
 * same ρ² = 0.5 and weight w. */
static void two_layers(spr_cloud *c, double zb)
{
    tu_cloud(c, 2, (double[]){0, 0, 0, 0, 0, zb}, 0.5f);
    tu_set_color(c, 0, 1, 0, 0);
    tu_set_color(c, 1, 0, 0, 1);
}

static void groups_one_each(spr_groups *g, int a_group)
{
    int32_t labels[2] = {a_group, 1 - a_group};
    spr_error err;
    ck_assert_int_eq(spr_groups_from_labels(labels, 2, 2, g, &err), SPR_OK);
}

static const float *px(const spr_render_result *r, int x, int y) { return r->rgba + 4 * (y * r->width + x); }

START_TEST(pbr2p1_blends_inside_eps_only)
{
    spr_view v;
    tu_hand_view(4, 4, &v);
    spr_render_desc d = {.algo = SPR_ALGO_PBR2P1, .eps = 0.25, .background = {0.5f, 0.5f, 0.5f}}; /* ε_t = 0.125 */
    spr_cloud c;
    spr_render_result r;
    two_layers(&c, -0.2); /* B at t = 0.6 ≤ 0.5 + 0.125: same surface */
    tu_render(&v, &c, &d, 1, &r);
    ck_assert_float_eq(r.eps_t, 0.125f);
    ck_assert_double_eq_tol(px(&r, 1, 1)[0], 0.5, 1e-6); /* (w·red + w·blue)/(2w) */
    ck_assert_double_eq_tol(px(&r, 1, 1)[2], 0.5, 1e-6);
    ck_assert_float_eq(px(&r, 0, 0)[0], 0.5f);          /* background */
    ck_assert_float_eq(px(&r, 0, 0)[3], 0.0f);
    spr_render_result_free(&r);
    spr_cloud_free(&c);
    two_layers(&c, -0.5); /* B at t = 0.75 > 0.625: hidden */
    tu_render(&v, &c, &d, 1, &r);
    ck_assert_float_eq(px(&r, 2, 2)[0], 1.0f);
    ck_assert_float_eq(px(&r, 2, 2)[2], 0.0f);
    spr_render_result_free(&r);
    spr_cloud_free(&c);
}
END_TEST

/* zbuffer: the nearer splat's colour exactly, with no blending even where
 * the farther one is within ε; background elsewhere. */
START_TEST(zbuffer_keeps_the_nearest_splat)
{
    spr_view v;
    tu_hand_view(4, 4, &v);
    spr_render_desc d = {.algo = SPR_ALGO_ZBUFFER, .background = {0.5f, 0.5f, 0.5f}};
    spr_cloud c;
    spr_render_result r;
    two_layers(&c, 0.1); /* B (blue) at t = 0.45, in front of A (red) at 0.5 */
    tu_render(&v, &c, &d, 1, &r);
    for (int y = 1; y <= 2; y++)
        for (int x = 1; x <= 2; x++) {
            ck_assert_float_eq(px(&r, x, y)[0], 0.0f);
            ck_assert_float_eq(px(&r, x, y)[2], 1.0f);
            ck_assert_float_eq(px(&r, x, y)[3], 1.0f);
        }
    ck_assert_float_eq(px(&r, 0, 0)[0], 0.5f);
    ck_assert_float_eq(px(&r, 0, 0)[3], 0.0f);
    ck_assert_int_eq(r.n_passes, 2);
    spr_render_result_free(&r);
    spr_cloud_free(&c);
}
END_TEST

/* transparent1 (SPEC §6.1), hand camera 4×4, one group, black background,
 * α = 0.5: two coplanar splats covering the same pixels blend once, not
 * twice (the second has the same z̃ and fails LESS): red over black =
 * (0.5, 0, 0), alpha 0.5·0.5 = 0.25.  Two layers, blue at t = 0.75 behind
 * red at t = 0.5, blend back to front whatever the submission order and the
 * ordering method: blue first (0, 0, 0.5), then red (0.5, 0, 0.25). */
START_TEST(transparent1_culls_within_a_layer_and_blends_back_to_front)
{
    spr_view v;
    tu_hand_view(4, 4, &v);
    spr_cloud c;
    spr_render_result r;
    spr_render_desc d = {.algo = SPR_ALGO_TRANSPARENT1, .eps = 0.1, .alpha = 0.5f}; /* ε_t = 0.05: t 0.5 and 0.75 fall in different z̃ cells */
    two_layers(&c, 0.0); /* coplanar: both at t = 0.5 */
    tu_render(&v, &c, &d, 1, &r);
    for (int y = 1; y <= 2; y++)
        for (int x = 1; x <= 2; x++) {
            const float *q = px(&r, x, y);
            ck_assert_float_eq(q[0], 0.5f);
            ck_assert_float_eq(q[1], 0.0f);
            ck_assert_float_eq(q[2], 0.0f);
            ck_assert_float_eq(q[3], 0.25f);
        }
    ck_assert_uint_eq(r.passes[0].stats.passed, 4); /* 8 fragments, the coplanar four culled */
    ck_assert_uint_eq(r.passes[0].stats.generated, 8);
    spr_render_result_free(&r);
    spr_cloud_free(&c);
    for (int order = 0; order < 2; order++)
        for (int flip = 0; flip < 2; flip++) {
            /* blue behind (z = −0.5, t = 0.75); flip lists it first or second */
            tu_cloud(&c, 2, flip ? (double[]){0, 0, -0.5, 0, 0, 0} : (double[]){0, 0, 0, 0, 0, -0.5}, 0.5f);
            tu_set_color(&c, flip ? 1 : 0, 1, 0, 0);
            tu_set_color(&c, flip ? 0 : 1, 0, 0, 1);
            d.order = order ? SPR_ORDER_SORT : SPR_ORDER_BSP;
            tu_render(&v, &c, &d, 1, &r);
            const float *q = px(&r, 1, 2);
            ck_assert_msg(q[0] == 0.5f && q[1] == 0.0f && q[2] == 0.25f, "order %d flip %d: (%g, %g, %g)", order, flip, q[0], q[1], q[2]);
            spr_render_result_free(&r);
            spr_cloud_free(&c);
        }
}
END_TEST

/* A frame's host work (the back-to-front order here) runs on the CPU
 * backend's own thread count, its host_threads, through OpenMP's default,
 * which spr_render restores: the caller's default is the same afterwards,
 * and the image the same on 1 and 3 threads. */
START_TEST(frame_host_work_on_the_backend_threads)
{
    spr_error err;
    spr_backend *b1 = spr_swrast_create(1, &err), *b3 = spr_swrast_create(3, &err);
    ck_assert_ptr_nonnull(b1);
    ck_assert_ptr_nonnull(b3);
    ck_assert_int_eq(b1->host_threads, 1);
    ck_assert_int_eq(b3->host_threads, 3);
    spr_view v;
    tu_hand_view(4, 4, &v);
    spr_cloud c;
    two_layers(&c, 0.25);
    spr_render_desc d = {.algo = SPR_ALGO_TRANSPARENT1, .eps = 0.1, .alpha = 0.5f};
    const int caller = omp_get_max_threads();
    omp_set_num_threads(5);
    spr_render_result r1, r3;
    ck_assert_int_eq(spr_render(b1, &v, &c, &d, &r1, &err), SPR_OK);
    ck_assert_int_eq(omp_get_max_threads(), 5);
    ck_assert_int_eq(spr_render(b3, &v, &c, &d, &r3, &err), SPR_OK);
    ck_assert_int_eq(omp_get_max_threads(), 5);
    ck_assert_mem_eq(r1.rgba, r3.rgba, 16 * 4 * sizeof(float));
    omp_set_num_threads(caller);
    spr_render_result_free(&r1);
    spr_render_result_free(&r3);
    spr_cloud_free(&c);
    spr_backend_destroy(b1);
    spr_backend_destroy(b3);
}
END_TEST

/* transparent2 (SPEC §6.2) with α = 1 is `deferred`, bit for bit: α_F =
 * Σ w·1 / Σ w = 1 exactly, so I = 1·C_F + 0·C_O = C_F, and C_F is the §4.2
 * composite; the background where nothing is drawn.  Checked on the real
 * bunny with MGC groups and Voronoi depth.  With α = 0.5 on the hand scene
 * of two layers (red in front at t = 0.5, blue behind at 0.75, one group):
 * α_F = 0.5, C_F = red, C_O = blue over black = (0, 0, 0.5), so
 * I = 0.5·(1, 0, 0) + 0.5·(0, 0, 0.5) = (0.5, 0, 0.25). */
START_TEST(transparent2_with_opaque_splats_is_deferred)
{
    tu_bunny bn;
    tu_bunny_scene(&bn, 200, 150, 0.4);
    spr_render_desc d = {.algo = SPR_ALGO_DEFERRED, .voronoi = 1, .groups = &bn.groups};
    spr_render_result a, b;
    tu_render(&bn.view, &bn.cloud, &d, 2, &a);
    d.algo = SPR_ALGO_TRANSPARENT2;
    d.alpha = 1.0f;
    tu_render(&bn.view, &bn.cloud, &d, 2, &b);
    ck_assert_mem_eq(a.rgba, b.rgba, (size_t)a.width * a.height * 4 * sizeof(float));
    spr_render_result_free(&a);
    spr_render_result_free(&b);
    tu_bunny_free(&bn);
    spr_view v;
    tu_hand_view(4, 4, &v);
    spr_cloud c;
    spr_render_result r;
    two_layers(&c, -0.5);
    spr_render_desc t = {.algo = SPR_ALGO_TRANSPARENT2, .eps = 0.1, .alpha = 0.5f, .kernel = SPR_KERNEL_CONSTANT};
    tu_render(&v, &c, &t, 1, &r);
    const float *q = px(&r, 2, 1);
    ck_assert_msg(q[0] == 0.5f && q[1] == 0.0f && q[2] == 0.25f && q[3] == 1.0f, "(%g, %g, %g, %g)", q[0], q[1], q[2], q[3]);
    ck_assert_float_eq(px(&r, 0, 0)[3], 0.0f);
    spr_render_result_free(&r);
    spr_cloud_free(&c);
}
END_TEST

START_TEST(deferred_composite_inside_and_beyond_eps)
{
    spr_view v;
    tu_hand_view(4, 4, &v);
    for (int order = 0; order < 2; order++) {
        spr_groups g;
        groups_one_each(&g, order);
        spr_render_desc d = {.algo = SPR_ALGO_DEFERRED, .eps = 0.25, .groups = &g};
        spr_cloud c;
        spr_render_result r;
        two_layers(&c, -0.2);
        tu_render(&v, &c, &d, 2, &r);
        ck_assert_int_eq(r.K, 2);
        ck_assert_int_eq(r.n_passes, 3); /* two geometry passes, one composite */
        /* (w1·c1 + w2·c2)/(w1 + w2), with w1 = w2 here */
        float w = spr_kernel_weight(SPR_KERNEL_GAUSS, 0.5f, sqrtf(0.5f));
        ck_assert_double_eq_tol(px(&r, 1, 2)[0], (w * 1.0 + w * 0.0) / (w + w), 1e-6);
        ck_assert_double_eq_tol(px(&r, 1, 2)[2], (w * 0.0 + w * 1.0) / (w + w), 1e-6);
        spr_render_result_free(&r);
        spr_cloud_free(&c);
        two_layers(&c, -0.5);
        tu_render(&v, &c, &d, 2, &r);
        ck_assert_float_eq(px(&r, 1, 2)[0], 1.0f); /* the farther group is dropped */
        ck_assert_float_eq(px(&r, 1, 2)[2], 0.0f);
        spr_render_result_free(&r);
        spr_cloud_free(&c);
        spr_groups_free(&g);
    }
}
END_TEST

START_TEST(deferred_composite_unequal_weights)
{
    /* A centred on pixel (1,1), B on pixel (2,2): at pixel (1,1) w_A = w(0),
     * w_B = w(ρ² = 0.5/0.64) — the composite is the weighted mean. */
    spr_view v;
    tu_hand_view(4, 4, &v);
    spr_cloud c;
    tu_cloud(&c, 2, (double[]){-0.25, -0.25, 0, 0.25, 0.25, -0.1}, 0.8f);
    tu_set_color(&c, 0, 0.2f, 0.4f, 0.6f);
    tu_set_color(&c, 1, 0.9f, 0.1f, 0.5f);
    spr_groups g;
    groups_one_each(&g, 0);
    spr_render_desc d = {.algo = SPR_ALGO_DEFERRED, .eps = 0.5, .groups = &g, .kernel = SPR_KERNEL_EPANECHNIKOV};
    spr_render_result r;
    tu_render(&v, &c, &d, 1, &r);
    double w1 = 1.0, w2 = 1.0 - (0.25 + 0.25) / 0.64;
    double c1[3] = {0.2, 0.4, 0.6}, c2[3] = {0.9, 0.1, 0.5};
    for (int k = 0; k < 3; k++) ck_assert_double_eq_tol(px(&r, 1, 1)[k], (w1 * c1[k] + w2 * c2[k]) / (w1 + w2), 1e-6);
    spr_render_result_free(&r);
    spr_groups_free(&g);
    spr_cloud_free(&c);
}
END_TEST

START_TEST(voronoi_nearer_centre_wins_farther_layer_never)
{
    /* 16×16 hand view (pixel 0.125).  A at x = −0.25 and B at x = +0.25 in
     * one layer and one group (both r = 0.6); C far behind (z = −0.9),
     * submitted first and centred at the origin so it is nearer its own
     * centre than A or B everywhere. */
    spr_view v;
    tu_hand_view(16, 16, &v);
    spr_cloud c;
    tu_cloud(&c, 3, (double[]){0, 0, -0.9, -0.25, 0, 0, 0.25, 0, 0}, 0.6f);
    c.radius[0] = 0.9f;
    spr_render_desc d = {.algo = SPR_ALGO_DEFERRED, .voronoi = 1, .eps = 0.2, .kernel = SPR_KERNEL_CONSTANT};
    tu_set_color(&c, 0, 0, 0, 1);
    tu_set_color(&c, 1, 1, 0, 0);
    tu_set_color(&c, 2, 0, 1, 0);
    spr_render_result r;
    tu_render(&v, &c, &d, 2, &r);
    int checked = 0;
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++) {
            double wx = -1.0 + (x + 0.5) / 8.0, wy = -1.0 + (y + 0.5) / 8.0;
            double da = hypot(wx + 0.25, wy) / 0.6, db = hypot(wx - 0.25, wy) / 0.6;
            if (da >= 0.999 && db >= 0.999) continue; /* only pixels inside A or B */
            const float *p = px(&r, x, y);
            ck_assert_msg(p[2] == 0.0f, "far layer won at (%d,%d)", x, y);
            if (da < 0.999 && db < 0.999) {
                int want_a = da < db;
                ck_assert_msg(p[0] == (want_a ? 1.0f : 0.0f) && p[1] == (want_a ? 0.0f : 1.0f),
                              "pixel (%d,%d): splat %s should win", x, y, want_a ? "A" : "B");
                checked++;
            }
        }
    ck_assert_int_gt(checked, 20);
    spr_render_result_free(&r);
    /* Without Voronoi the first submitted of A and B wins everywhere they overlap. */
    d.voronoi = 0;
    tu_render(&v, &c, &d, 2, &r);
    ck_assert_float_eq(px(&r, 9, 8)[0], 1.0f); /* x = 0.1875: nearer B, but A came first */
    spr_render_result_free(&r);
    spr_cloud_free(&c);
}
END_TEST

START_TEST(bunny_deferred_matches_pbr2p1)
{
    tu_bunny bn;
    tu_bunny_scene(&bn, 512, 512, 0.4);
    spr_render_desc dd = {.algo = SPR_ALGO_DEFERRED, .voronoi = 1, .groups = &bn.groups};
    spr_render_desc dp = {.algo = SPR_ALGO_PBR2P1};
    spr_render_result rd, rp;
    tu_render(&bn.view, &bn.cloud, &dd, 2, &rd);
    tu_render(&bn.view, &bn.cloud, &dp, 2, &rp);
    size_t covered = 0, holes = 0;
    double sum = 0.0;
    for (size_t i = 0; i < (size_t)rd.width * rd.height; i++) {
        if (rp.rgba[4 * i + 3] > 0.0f && !(rd.rgba[4 * i + 3] > 0.0f)) holes++;
        if (!(rp.rgba[4 * i + 3] > 0.0f && rd.rgba[4 * i + 3] > 0.0f)) continue;
        covered++;
        for (int k = 0; k < 3; k++) sum += fabs((double)spr_to_u8(rd.rgba[4 * i + k]) - spr_to_u8(rp.rgba[4 * i + k]));
    }
    double mean = sum / (3.0 * covered);
    printf("algo: bunny deferred (MGC c=0.4, K=%d, Voronoi) vs pbr2p1: mean |diff| %.3f/255 over %zu covered pixels, "
           "%zu pixels covered only by pbr2p1\n", bn.groups.K, mean, covered, holes);
    ck_assert_double_lt(mean, 2.0);
    ck_assert_uint_eq(holes, 0);
    spr_render_result_free(&rd);
    spr_render_result_free(&rp);
    tu_bunny_free(&bn);
}
END_TEST

Suite *make_algo_suite(void)
{
    Suite *s = suite_create("algo");
    TCase *tc = tcase_create("algo");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, pbr2p1_blends_inside_eps_only);
    tcase_add_test(tc, zbuffer_keeps_the_nearest_splat);
    tcase_add_test(tc, transparent1_culls_within_a_layer_and_blends_back_to_front);
    tcase_add_test(tc, frame_host_work_on_the_backend_threads);
    tcase_add_test(tc, transparent2_with_opaque_splats_is_deferred);
    tcase_add_test(tc, deferred_composite_inside_and_beyond_eps);
    tcase_add_test(tc, deferred_composite_unequal_weights);
    tcase_add_test(tc, voronoi_nearer_centre_wins_farther_layer_never);
    tcase_add_test(tc, bunny_deferred_matches_pbr2p1);
    suite_add_tcase(s, tc);
    return s;
}
