/* test_camera.c — SPEC §2–§3.3 formulas against values worked out by hand. */
#include <math.h>
#include <stdlib.h>
#include "spr_fragment.h"
#include "test_util.h"

START_TEST(hand_camera_rays)
{
    spr_view v;
    tu_hand_view(4, 4, &v);
    ck_assert_float_eq(v.ndc_sx, 0.5f);
    float o0[3], d[3];
    spr_pixel_ray(&v, 1, 1, o0, d); /* centre (1.5·0.5 − 1) = −0.25 */
    ck_assert_float_eq(o0[0], -0.25f);
    ck_assert_float_eq(o0[1], -0.25f);
    ck_assert_float_eq(o0[2], 1.0f);
    ck_assert_float_eq(d[0], 0.0f);
    ck_assert_float_eq(d[1], 0.0f);
    ck_assert_float_eq(d[2], -2.0f);
    spr_pixel_ray(&v, 3, 0, o0, d);
    ck_assert_float_eq(o0[0], 0.75f);
    ck_assert_float_eq(o0[1], -0.75f);
    ck_assert_float_eq(spr_view_eps_t(&v, 0.25), 0.125f);
}
END_TEST

START_TEST(ray_disk_by_hand)
{
    float o0[3] = {-0.25f, -0.25f, 1.0f}, d[3] = {0, 0, -2}, p[3] = {0, 0, 0}, n[3] = {0, 0, 1};
    float t, rho2, den;
    ck_assert(spr_ray_disk(o0, d, p, n, 0.5f, &t, &rho2, &den));
    ck_assert_float_eq(den, -2.0f);      /* front-facing */
    ck_assert_float_eq(t, 0.5f);         /* ((p − o0)·n)/den = −1/−2 */
    ck_assert_float_eq(rho2, 0.5f);      /* (0.0625 + 0.0625)/0.25 */
    /* closed disk: ρ² = 1 exactly is covered */
    float o1[3] = {0.5f, 0.0f, 1.0f};
    ck_assert(spr_ray_disk(o1, d, p, n, 0.5f, &t, &rho2, &den));
    ck_assert_float_eq(rho2, 1.0f);
    /* just outside */
    float o2[3] = {0.5f, 0.0625f, 1.0f};
    ck_assert(!spr_ray_disk(o2, d, p, n, 0.5f, &t, &rho2, &den));
    /* exactly edge-on: den = 0, no fragment */
    float ne[3] = {1, 0, 0};
    ck_assert(!spr_ray_disk(o0, d, p, ne, 0.5f, &t, &rho2, &den));
    ck_assert_float_eq(den, 0.0f);
    /* behind the camera (z = 3 > eye z = 2): t = (1 − 3)/2 < 0 */
    float pb[3] = {0, 0, 3};
    ck_assert(!spr_ray_disk(o0, d, pb, n, 5.0f, &t, &rho2, &den));
    /* beyond the far plane: t > 1 */
    float pf[3] = {0, 0, -1.5f};
    ck_assert(!spr_ray_disk(o0, d, pf, n, 5.0f, &t, &rho2, &den));
    /* back-facing: den > 0 */
    float nb[3] = {0, 0, -1};
    ck_assert(spr_ray_disk(o0, d, p, nb, 0.5f, &t, &rho2, &den));
    ck_assert_float_gt(den, 0.0f);
}
END_TEST

START_TEST(perspective_depth_is_linear_in_eye_depth)
{
    spr_camera_desc c;
    spr_camera_defaults(&c);
    c.eye[2] = 5.0;
    c.fov_deg = 60.0;
    c.near_plane = 1.0;
    c.far_plane = 9.0;
    c.width = c.height = 1;
    spr_view v;
    spr_error err;
    ck_assert_int_eq(spr_view_make(&c, &v, &err), SPR_OK);
    float o0[3], d[3];
    spr_pixel_ray(&v, 0, 0, o0, d);
    ck_assert_double_eq_tol(o0[2], 4.0, 1e-6);
    ck_assert_double_eq_tol(d[2], -8.0, 1e-5);
    float n[3] = {0, 0, 1}, t, rho2, den;
    for (int i = 0; i <= 4; i++) {
        float p[3] = {0, 0, (float)(4.0 - 2.0 * i)}; /* eye depth 1 + 2i */
        ck_assert(spr_ray_disk(o0, d, p, n, 0.1f, &t, &rho2, &den));
        ck_assert_double_eq_tol(t, 0.25 * i, 1e-6);
    }
}
END_TEST

START_TEST(depth_test_values_by_hand)
{
    spr_view v;
    tu_hand_view(4, 4, &v);
    spr_bounds b = {{-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}, 0.0, 0.0, 0.0};
    spr_lowres L;
    spr_lowres_make(&v, &b, 0.125f, 0.0, &L);
    /* t = (1 − z)/2 over z ∈ [−0.5, 0.5] → [0.25, 0.75]; n = ceil(0.5/0.125) = 4 */
    ck_assert_float_eq(L.d_min, 0.25f);
    ck_assert_float_eq(L.d_max, 0.75f);
    ck_assert_float_eq(L.n, 4.0f);
    ck_assert_float_eq(L.inv_n, 0.25f);
    spr_pass_state s;
    spr_pass_state_defaults(&s);
    s.lowres = L;
    s.eps_t = 0.125f;
    s.depth_value = SPR_DEPTH_PLAIN;
    ck_assert_float_eq(spr_test_value(&s, 0.5f, 0.5f), 0.5f);
    s.depth_value = SPR_DEPTH_EPS_OFFSET;
    ck_assert_float_eq(spr_test_value(&s, 0.5f, 0.5f), 0.625f);
    s.depth_value = SPR_DEPTH_LOWRES; /* floor((0.25/0.5)·4)·0.25 = 0.5; floor(1.6)·0.25 */
    ck_assert_float_eq(spr_test_value(&s, 0.5f, 0.5f), 0.5f);
    ck_assert_float_eq(spr_test_value(&s, 0.45f, 0.5f), 0.25f);
    s.depth_value = SPR_DEPTH_VORONOI; /* z̃ + ρ/n */
    ck_assert_float_eq(spr_test_value(&s, 0.5f, 0.5f), 0.625f);
    /* clamped to the depth range like gl_FragDepth */
    s.depth_value = SPR_DEPTH_EPS_OFFSET;
    ck_assert_float_eq(spr_test_value(&s, 0.95f, 0.0f), 1.0f);
}
END_TEST

START_TEST(pixel_rect_is_conservative)
{
    spr_camera_desc c;
    spr_camera_defaults(&c);
    c.eye[0] = 0.3; c.eye[1] = 0.2; c.eye[2] = 3.0;
    c.near_plane = 0.5;
    c.far_plane = 6.0;
    c.fov_deg = 50.0;
    c.width = 64;
    c.height = 48;
    spr_view v;
    spr_error err;
    ck_assert_int_eq(spr_view_make(&c, &v, &err), SPR_OK);
    srand(7);
    size_t covered_in = 0;
    double area_ell = 0.0, area_circle = 0.0;
    for (int s = 0; s < 1200; s++) {
        float p[3], n[3], r = 0.05f + 0.5f * rand() / (float)RAND_MAX;
        for (int k = 0; k < 3; k++) { p[k] = 4.0f * rand() / (float)RAND_MAX - 2.0f; n[k] = rand() / (float)RAND_MAX - 0.5f; }
        spr__normalize3(n);
        /* every other splat an ellipse: a random tangent u (up to 1e-4 off the plane, as files may
         * hold it), r_v from 0.001 r to r */
        float e[4] = {0.0f, 0.0f, 0.0f, r};
        if (s & 1) {
            float a[3];
            for (int k = 0; k < 3; k++) a[k] = rand() / (float)RAND_MAX - 0.5f;
            float an = a[0] * n[0] + a[1] * n[1] + a[2] * n[2];
            for (int k = 0; k < 3; k++) a[k] -= an * n[k] - 1e-4f * n[k];
            spr__normalize3(a);
            for (int k = 0; k < 3; k++) e[k] = a[k];
            e[3] = r * (s % 4 == 1 ? 0.001f + 0.01f * rand() / (float)RAND_MAX : rand() / (float)RAND_MAX);
            if (!(e[3] > 0.0f)) e[3] = r * 0.5f;
        }
        int x0 = 0, y0 = 0, x1 = -1, y1 = -1, cx0 = 0, cy0 = 0, cx1 = -1, cy1 = -1;
        int any = spr_splat_pixel_rect_ell(&v, p, n, e, r, &x0, &y0, &x1, &y1);
        if ((s & 1) && spr_splat_pixel_rect(&v, p, n, r, &cx0, &cy0, &cx1, &cy1)) { /* the ellipse's box inside the circle's */
            ck_assert(!any || (x0 >= cx0 && x1 <= cx1 && y0 >= cy0 && y1 <= cy1));
            if (any) area_ell += (double)(x1 - x0 + 1) * (y1 - y0 + 1);
            area_circle += (double)(cx1 - cx0 + 1) * (cy1 - cy0 + 1);
        }
        for (int y = 0; y < c.height; y++)
            for (int x = 0; x < c.width; x++) {
                float o0[3], d[3], t, rho2, den;
                spr_pixel_ray(&v, x, y, o0, d);
                if (!spr_ray_ellipse(o0, d, p, n, e, r, &t, &rho2, &den)) continue;
                covered_in++;
                if (!(any && x >= x0 && x <= x1 && y >= y0 && y <= y1))
                    ck_abort_msg("splat %d covers (%d,%d) outside its rectangle", s, x, y);
            }
    }
    ck_assert_uint_gt(covered_in, 20000);
    printf("camera: ellipses' rectangles cover %.0f pixels where their bounding circles' cover %.0f\n", area_ell, area_circle);
    ck_assert(area_ell < 0.8 * area_circle);
}
END_TEST

Suite *make_camera_suite(void)
{
    Suite *s = suite_create("camera");
    TCase *tc = tcase_create("camera");
    tcase_add_test(tc, hand_camera_rays);
    tcase_add_test(tc, ray_disk_by_hand);
    tcase_add_test(tc, perspective_depth_is_linear_in_eye_depth);
    tcase_add_test(tc, depth_test_values_by_hand);
    tcase_add_test(tc, pixel_rect_is_conservative);
    suite_add_tcase(s, tc);
    return s;
}
