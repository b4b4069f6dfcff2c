/* test_shade.c — SPEC §4.3 (deferred shading), §6.3 (environment effects),
 * §6.4 (depth peeling) and [ZP] §6.3's image error, on hand scenes whose
 * expected values are worked out here in double from the formulas of the
 * SPEC, independently of the shared arithmetic. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "spr_envmap.h"
#include "spr_image.h"
#include "test_util.h"

static const float *px(const spr_render_result *r, int x, int y) { return r->rgba + 4 * (y * r->width + x); }

/* Depth peeling with one layer of opaque splats is pbr2p1, bit for bit:
 * the layer's α = Σ w·1 / Σ w = 1 exactly, so 1·c + 0·background = c. */
START_TEST(depthpeel_one_layer_is_pbr2p1)
{
    tu_bunny bn;
    tu_bunny_scene(&bn, 200, 150, 0.4);
    spr_render_desc d = {.algo = SPR_ALGO_PBR2P1, .background = {0.2f, 0.3f, 0.4f}};
    spr_render_result a, b;
    tu_render(&bn.view, &bn.cloud, &d, 2, &a);
    d.algo = SPR_ALGO_DEPTHPEEL;
    d.layers = 1;
    tu_render(&bn.view, &bn.cloud, &d, 2, &b);
    ck_assert_mem_eq(a.rgba, b.rgba, (size_t)a.width * a.height * 4 * sizeof(float));
    ck_assert_int_eq(b.n_passes, 4); /* visibility, blend, layer, composite */
    spr_render_result_free(&a);
    spr_render_result_free(&b);
    tu_bunny_free(&bn);
}
END_TEST

/* Three layers red (t = 0.5), green (0.625), blue (0.75), α = 0.5, constant
 * kernel, black background: back to front blue → (0, 0, 0.5), green →
 * (0, 0.5, 0.25), red → (0.5, 0.25, 0.125); two layers leave blue out:
 * (0.5, 0.25, 0); one layer: (0.5, 0, 0).  Submission order is irrelevant. */
START_TEST(depthpeel_layers_back_to_front)
{
    spr_view v;
    tu_hand_view(4, 4, &v);
    spr_cloud c;
    tu_cloud(&c, 3, (double[]){0, 0, -0.5, 0, 0, 0, 0, 0, -0.25}, 0.5f); /* blue, red, green */
    tu_set_color(&c, 0, 0, 0, 1);
    tu_set_color(&c, 1, 1, 0, 0);
    tu_set_color(&c, 2, 0, 1, 0);
    static const struct { int L; float rgb[3]; } cases[] = {
        {8, {0.5f, 0.25f, 0.125f}}, {3, {0.5f, 0.25f, 0.125f}}, {2, {0.5f, 0.25f, 0.0f}}, {1, {0.5f, 0.0f, 0.0f}}};
    for (int i = 0; i < 4; i++) {
        spr_render_desc d = {.algo = SPR_ALGO_DEPTHPEEL, .eps = 0.1, .alpha = 0.5f, .kernel = SPR_KERNEL_CONSTANT, .layers = cases[i].L};
        spr_render_result r;
        tu_render(&v, &c, &d, 1, &r);
        const float *q = px(&r, 2, 1);
        ck_assert_msg(q[0] == cases[i].rgb[0] && q[1] == cases[i].rgb[1] && q[2] == cases[i].rgb[2] && q[3] == 1.0f,
                      "L = %d: (%g, %g, %g, %g)", cases[i].L, q[0], q[1], q[2], q[3]);
        ck_assert_float_eq(px(&r, 0, 0)[3], 0.0f);
        spr_render_result_free(&r);
    }
    spr_cloud_free(&c);
}
END_TEST

/* Phong (SPEC §4.3) on one splat facing the camera (n = +z; the hand
 * camera's eye space is world space): light along +z, ka 0.25, kd 0.5,
 * ks 0.125: n·L = 1, R·V = 1, so c·0.75 + 0.125 = (0.875, 0.5, 0.3125)
 * exactly, for pbr2p1 and deferred, for either side of the splat.  Light
 * (0, 1, 1)/√2 with exponent 2: n·L = R·V = 1/√2, spec = ½:
 * c·(0.25 + 0.5/√2) + 0.0625.  Light from behind: c·ka. */
START_TEST(phong_by_hand)
{
    spr_view v;
    tu_hand_view(4, 4, &v);
    for (int side = 0; side < 2; side++)
        for (int al = 0; al < 2; al++) {
            spr_cloud c;
            tu_cloud(&c, 1, (double[]){0, 0, 0}, 0.5f);
            tu_set_color(&c, 0, 1.0f, 0.5f, 0.25f);
            c.nrm[2] = side ? -1.0f : 1.0f;
            spr_render_desc d = {.algo = al ? SPR_ALGO_DEFERRED : SPR_ALGO_PBR2P1, .eps = 0.1};
            spr_shading_defaults(&d.shade);
            d.shade.model = SPR_SHADE_PHONG;
            d.shade.light_eye[0] = 0, d.shade.light_eye[1] = 0, d.shade.light_eye[2] = 1;
            d.shade.ka = 0.25, d.shade.kd = 0.5, d.shade.ks = 0.125, d.shade.exponent = 7;
            spr_render_result r;
            tu_render(&v, &c, &d, 1, &r);
            const float *q = px(&r, 1, 2);
            ck_assert_msg(q[0] == 0.875f && q[1] == 0.5f && q[2] == 0.3125f, "side %d algo %d: (%g, %g, %g)", side, al, q[0], q[1], q[2]);
            ck_assert_float_eq(px(&r, 0, 0)[0], 0.0f); /* background unshaded */
            spr_render_result_free(&r);
            d.shade.light_eye[1] = 1;
            d.shade.exponent = 2;
            tu_render(&v, &c, &d, 1, &r);
            q = px(&r, 1, 2);
            const double s = 1.0 / sqrt(2.0), lit = 0.25 + 0.5 * s, col[3] = {1.0, 0.5, 0.25};
            for (int ch = 0; ch < 3; ch++)
                ck_assert_msg(fabs(q[ch] - (col[ch] * lit + 0.0625)) < 2e-6, "oblique light, channel %d: %.9g, expected %.9g", ch, q[ch],
                              col[ch] * lit + 0.0625);
            spr_render_result_free(&r);
            d.shade.light_eye[1] = 0, d.shade.light_eye[2] = -1;
            tu_render(&v, &c, &d, 1, &r);
            q = px(&r, 1, 2);
            ck_assert_msg(q[0] == 0.25f && q[1] == 0.125f && q[2] == 0.0625f, "light behind: (%g, %g, %g)", q[0], q[1], q[2]);
            spr_render_result_free(&r);
            spr_cloud_free(&c);
        }
}
END_TEST

/* ---- environment effects (SPEC §6.3) ---- */

enum { ENV_S = 63 }; /* odd: a ray along an axis meets the middle of a texel */

/* A cube map whose texel (i, j) of face f has colour ((f+1)/8, (i+½)/63, (j+½)/63),
 * so every value tells which texel a ray reached. */
static void coded_env(spr_envmap *e)
{
    e->size = ENV_S;
    e->texels = malloc(6 * ENV_S * ENV_S * 4 * sizeof(float));
    ck_assert_ptr_nonnull(e->texels);
    for (int f = 0; f < 6; f++)
        for (int j = 0; j < ENV_S; j++)
            for (int i = 0; i < ENV_S; i++) {
                float *t = e->texels + ((f * ENV_S + j) * ENV_S + i) * 4;
                t[0] = (float)(f + 1) / 8.0f;
                t[1] = ((float)i + 0.5f) / (float)ENV_S;
                t[2] = ((float)j + 0.5f) / (float)ENV_S;
                t[3] = 1.0f;
            }
}

/* GL's cube map rule in double (OpenGL 4.5 §8.13, table 8.19): the
 * expected texel colour along direction d, channel ch. */
static double env_expect(const double d[3], int ch)
{
    double ax = fabs(d[0]), ay = fabs(d[1]), az = fabs(d[2]), ma, sc, tc;
    int f;
    if (ax >= ay && ax >= az) f = d[0] > 0 ? 0 : 1, ma = ax, sc = d[0] > 0 ? -d[2] : d[2], tc = -d[1];
    else if (ay >= az) f = d[1] > 0 ? 2 : 3, ma = ay, sc = d[0], tc = d[1] > 0 ? d[2] : -d[2];
    else f = d[2] > 0 ? 4 : 5, ma = az, sc = d[2] > 0 ? d[0] : -d[0], tc = -d[1];
    int i = (int)floor((sc / ma + 1.0) * 0.5 * ENV_S), j = (int)floor((tc / ma + 1.0) * 0.5 * ENV_S);
    i = i < 0 ? 0 : i > ENV_S - 1 ? ENV_S - 1 : i;
    j = j < 0 ? 0 : j > ENV_S - 1 ? ENV_S - 1 : j;
    return ch == 0 ? (f + 1) / 8.0 : ch == 1 ? (i + 0.5) / ENV_S : (j + 0.5) / ENV_S;
}

/* The expected transparent2 pixel (SPEC §6.3) for unit normal n facing the
 * view ray v = (0, 0, −1), front colour cf with opacity a, the other layers'
 * C_O (over a zero background) and layer count l, refraction ratio eta. */
static double env_pixel(const double n[3], const double cf[3], double a, const double co[3], int l, double alpha, double eta,
                        int multi, int ch, double *fresnel)
{
    const double v[3] = {0, 0, -1};
    double cos_i = -(n[0] * v[0] + n[1] * v[1] + n[2] * v[2]);
    double r[3], t[3];
    for (int k = 0; k < 3; k++) r[k] = v[k] + 2.0 * cos_i * n[k];
    double R = env_expect(r, ch);
    double e = pow(eta, multi ? l + 1 : 1), sin2_t = e * e * (1.0 - cos_i * cos_i), T;
    if (sin2_t >= 1.0) {
        T = R;
    } else {
        double cos_t = sqrt(1.0 - sin2_t);
        for (int k = 0; k < 3; k++) t[k] = e * v[k] + (e * cos_i - cos_t) * n[k];
        T = env_expect(t, ch);
    }
    double f0 = ((1.0 - eta) / (1.0 + eta)) * ((1.0 - eta) / (1.0 + eta));
    double F = f0 + (1.0 - f0) * pow(1.0 - cos_i, 5.0);
    if (fresnel) *fresnel = F;
    double behind = co[ch] + pow(1.0 - alpha, l) * T;
    return F * R + (1.0 - F) * (a * cf[ch] + (1.0 - a) * behind);
}

/* Parallel splats through (−¼, −¼, z_k) with normal n, colours col[k], α, into
 * transparent2 with the coded cube map; the pixel (1, 1) of the 4×4 hand view. */
static void env_render(const double n[3], int m, const double *z, const double (*col)[3], float alpha, double eta, int multi,
                       float out[4])
{
    spr_view v;
    tu_hand_view(4, 4, &v);
    spr_cloud c;
    double xyz[9] = {0};
    for (int k = 0; k < m; k++) xyz[3 * k] = -0.25, xyz[3 * k + 1] = -0.25, xyz[3 * k + 2] = z[k]; /* on pixel (1, 1)'s ray */
    tu_cloud(&c, (size_t)m, xyz, 0.8f);
    for (int k = 0; k < m; k++) {
        for (int q = 0; q < 3; q++) c.nrm[3 * k + q] = (float)n[q];
        tu_set_color(&c, (size_t)k, (float)col[k][0], (float)col[k][1], (float)col[k][2]);
    }
    spr_envmap env;
    coded_env(&env);
    spr_render_desc d = {.algo = SPR_ALGO_TRANSPARENT2, .eps = 0.1, .alpha = alpha, .kernel = SPR_KERNEL_CONSTANT};
    spr_shading_defaults(&d.shade);
    d.shade.env = &env;
    d.shade.eta[0] = d.shade.eta[1] = d.shade.eta[2] = eta;
    d.shade.multilayer = multi;
    spr_render_result r;
    tu_render(&v, &c, &d, 1, &r);
    memcpy(out, px(&r, 1, 1), 4 * sizeof(float));
    spr_render_result_free(&r);
    spr_envmap_free(&env);
    spr_cloud_free(&c);
}

/* Schlick's Fresnel at normal and grazing incidence: a black opaque splat
 * (α = 1) shows F·R only, so F = I/R.  Normal incidence: F = F0 =
 * ((1 − η)/(1 + η))² = 1/9 for η = ½; at cos θ_I = 0.01, F = F0 + (1 − F0)·0.99⁵. */
START_TEST(fresnel_normal_and_grazing)
{
    static const double black[1][3] = {{0, 0, 0}}, zero[3] = {0, 0, 0};
    const double z0 = 0.0;
    for (int g = 0; g < 2; g++) {
        double n[3] = {0, 0, 1};
        if (g) n[1] = sqrt(1.0 - 0.01 * 0.01), n[2] = 0.01;
        float o[4];
        env_render(n, 1, &z0, black, 1.0f, 0.5, 1, o);
        double F;
        for (int ch = 0; ch < 3; ch++) {
            double want = env_pixel(n, black[0], 1.0, zero, 0, 1.0, 0.5, 1, ch, &F);
            ck_assert_msg(fabs(o[ch] - want) < 2e-5, "%s incidence, channel %d: %.7g, expected %.7g", g ? "grazing" : "normal", ch, o[ch], want);
        }
        double want_F = g ? 1.0 / 9.0 + (8.0 / 9.0) * pow(0.99, 5.0) : 1.0 / 9.0;
        ck_assert_msg(fabs(F - want_F) < 1e-12, "Schlick F %.9g, expected %.9g", F, want_F);
        double R = env_expect((double[]){2 * n[2] * n[0], 2 * n[2] * n[1], -1 + 2 * n[2] * n[2]}, 0);
        ck_assert_msg(fabs(o[0] / R - want_F) < 2e-5, "%s: measured F = %.7g, Schlick %.7g", g ? "grazing" : "normal", o[0] / R, want_F);
    }
}
END_TEST

/* Absorption (Eq. 15) and multi-layer refraction (Eq. 16) with the layer
 * count l = round(α_total/α) from the other layers' added alpha: planes with
 * normal (0, 0.6, 0.8) (cos θ_I = 0.8), α = ½, η = ½, front plane red; one
 * plane behind (l = 1: absorption ½, sin θ_T = η²·sin θ_I) and two planes
 * behind (l = 2: ¼, η³); single-layer mode refracts with η alone. */
START_TEST(absorption_and_refraction)
{
    const double n[3] = {0, 0.6, 0.8};
    static const double col[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const double z[3] = {0.0, -0.3, -0.6};
    for (int behind = 1; behind <= 2; behind++)
        for (int multi = 0; multi < 2; multi++) {
            float o[4];
            env_render(n, 1 + behind, z, col, 0.5f, 0.5, multi, o);
            /* C_O: the planes behind, back to front over zero with α = ½ */
            double co[3] = {0, 0, 0};
            for (int k = behind; k >= 1; k--)
                for (int ch = 0; ch < 3; ch++) co[ch] = 0.5 * col[k][ch] + 0.5 * co[ch];
            for (int ch = 0; ch < 3; ch++) {
                double want = env_pixel(n, col[0], 0.5, co, behind, 0.5, 0.5, multi, ch, NULL);
                ck_assert_msg(fabs(o[ch] - want) < 2e-5, "%d behind, %s, channel %d: %.7g, expected %.7g", behind,
                              multi ? "multi" : "single", ch, o[ch], want);
            }
        }
    /* the two modes must differ where η^(l+1) moves the refracted ray to another texel */
    float a[4], b[4];
    env_render(n, 3, z, col, 0.5f, 0.5, 0, a);
    env_render(n, 3, z, col, 0.5f, 0.5, 1, b);
    ck_assert_msg(a[0] != b[0] || a[1] != b[1] || a[2] != b[2], "single and multi-layer refraction agree");
}
END_TEST

/* Six PNG faces load in GL's cube-map orientation: texel (i, j) of a face
 * is column i of row j counted from the top of the picture.  Each 2×2 face
 * has its top-left pixel coloured (f/8, 1, 0) and the others grey. */
START_TEST(envmap_faces_from_png)
{
    char dir[] = "/tmp/spr_env_XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(dir));
    static const char *const face[6] = {"px", "nx", "py", "ny", "pz", "nz"};
    for (int f = 0; f < 6; f++) {
        float img[2 * 2 * 3];
        for (int k = 0; k < 12; k++) img[k] = 0.2f;
        float *top_left = img + (1 * 2 + 0) * 3; /* memory rows start at the bottom */
        top_left[0] = (float)f / 8.0f, top_left[1] = 1.0f, top_left[2] = 0.0f;
        char path[256];
        snprintf(path, sizeof path, "%s/%s.png", dir, face[f]);
        spr_error err;
        ck_assert_int_eq(spr_write_png(path, img, 2, 2, 3, &err), SPR_OK);
    }
    spr_envmap e;
    spr_error err = {0};
    ck_assert_msg(spr_envmap_load(dir, &e, &err) == SPR_OK, "%s", err.msg);
    ck_assert_int_eq(e.size, 2);
    for (int f = 0; f < 6; f++) {
        const float *t = e.texels + (size_t)f * 2 * 2 * 4; /* texel (0, 0) */
        ck_assert_msg(fabsf(t[0] - spr_to_u8((float)f / 8.0f) / 255.0f) < 1e-7f && t[1] == 1.0f && t[2] == 0.0f,
                      "face %s: texel (0,0) = (%g, %g, %g)", face[f], t[0], t[1], t[2]);
        ck_assert_float_eq(t[4 * 3 + 1], spr_to_u8(0.2f) / 255.0f); /* texel (1, 1): grey */
    }
    spr_envmap_free(&e);
    char path[256];
    snprintf(path, sizeof path, "%s/nz.png", dir);
    remove(path);
    ck_assert_int_ne(spr_envmap_load(dir, &e, &err), SPR_OK); /* a face missing: an error naming it */
    ck_assert_ptr_nonnull(strstr(err.msg, "nz.png"));
    for (int f = 0; f < 5; f++) {
        snprintf(path, sizeof path, "%s/%s.png", dir, face[f]);
        remove(path);
    }
    rmdir(dir);
}
END_TEST

/* [ZP] §6.3's ε on 8-bit values: two 2×1 images differing by 10 in one
 * red and 20 in one green: ε = (10 + 20)/2 = 15, max 20, mean 30/6 = 5. */
START_TEST(zp_eps_by_hand)
{
    float a[6] = {0, 0, 0, 1, 1, 1}, b[6] = {10.0f / 255.0f, 0, 0, 1, 1.0f - 20.0f / 255.0f, 1};
    spr_image_diff_stats st;
    float heat[6];
    ck_assert_int_eq(spr_image_diff(a, 3, b, 3, 2, 1, NULL, &st, heat), SPR_OK);
    ck_assert_double_eq(st.zp_eps, 15.0);
    ck_assert_int_eq(st.max_abs, 20);
    ck_assert_double_eq(st.mean_abs, 5.0);
    ck_assert_uint_eq(st.differing, 2);
    ck_assert_float_eq(heat[3], 1.0f); /* the largest difference is white */
    ck_assert_float_eq(heat[5], 1.0f);
    ck_assert_float_eq(heat[2], 0.0f); /* half of it: red, no blue */
    ck_assert_uint_eq(st.pixels, 2);
    /* pixel 0 of b is not black (10/255 red), pixel 1 not either: nothing on the background */
    ck_assert_uint_eq(st.bg_pixels, 0);
    ck_assert_double_eq(st.zp_eps_bg, 0.0);
    const float white[3] = {1, 1, 1};
    ck_assert_int_eq(spr_image_diff(b, 3, a, 3, 2, 1, white, &st, NULL), SPR_OK); /* a's pixel 1 is white: its 20 counts */
    ck_assert_uint_eq(st.bg_pixels, 1);
    ck_assert_double_eq(st.zp_eps_bg, 10.0);
}
END_TEST

Suite *make_shade_suite(void)
{
    Suite *s = suite_create("shade");
    TCase *tc = tcase_create("all");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, depthpeel_one_layer_is_pbr2p1);
    tcase_add_test(tc, depthpeel_layers_back_to_front);
    tcase_add_test(tc, phong_by_hand);
    tcase_add_test(tc, fresnel_normal_and_grazing);
    tcase_add_test(tc, absorption_and_refraction);
    tcase_add_test(tc, zp_eps_by_hand);
    tcase_add_test(tc, envmap_faces_from_png);
    suite_add_tcase(s, tc);
    return s;
}
