/* test_gl.c — Tier A parity: the GL backend equals the CPU reference in
 * every plane of every pass (PARITY.md).  Runs without fork (one GL
 * context); the runner reports the suite skipped (77) when no GL context
 * can be created at all. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "spr_glbackend.h"
#include "spr_parity.h"
#include "spr_envmap.h"
#include "spr_domain.h"
#include "test_util.h"

static spr_backend *cpu, *gl;

static void setup(void)
{
    spr_error err = {0};
    spr_gl_desc gd;
    tu_gl_desc(&gd);
    cpu = spr_swrast_create(2, &err);
    gl = spr_gl_create(&gd, &err);
    ck_assert_msg(cpu && gl, "%s", err.msg);
}

static void teardown(void)
{
    spr_backend_destroy(cpu);
    spr_backend_destroy(gl);
}

static int cases, planes_checked;

static void expect_exact(const char *label, const spr_view *v, const spr_cloud *c, const spr_render_desc *d)
{
    spr_parity_report rep;
    spr_error err = {0};
    ck_assert_msg(spr_parity_run(cpu, gl, v, c, d, d, NULL, label, &rep, &err) == SPR_OK, "%s: %s", label, err.msg);
    int exact = spr_parity_exact(&rep);
    if (!exact) {
        printf("%s:\n", label);
        for (int i = 0; i < rep.n_planes; i++) {
            const spr_plane_diff *p = &rep.planes[i];
            if (!p->differing_pixels) continue;
            printf("  pass %d %s k=%d plane %d: %zu pixels, max ulp %llu, first (%d,%d): cpu %.9g gl %.9g\n", p->pass, p->pass_name,
                   p->group, p->plane, p->differing_pixels, (unsigned long long)p->max_ulp, p->first_x, p->first_y, p->first_ref,
                   p->first_test);
        }
        if (rep.stats_mismatches) printf("  %s\n", rep.first_stats_mismatch);
    }
    cases++;
    planes_checked += rep.n_planes;
    ck_assert_msg(exact, "%s: %d/%d planes bit-exact, max ulp %llu%s%s", label, rep.exact_planes, rep.n_planes, (unsigned long long)rep.max_ulp,
                  rep.stats_mismatches ? "; fragment counts differ: " : "", rep.stats_mismatches ? rep.first_stats_mismatch : "");
    spr_parity_report_free(&rep);
}

typedef struct config {
    const char *name;
    spr_algo algo;
    int groups; /* 0: none, 1: MGC, 2: hash K = 8 */
    int voronoi;
    float alpha;  /* > 0: --alpha */
    int shade;    /* Phong (SPEC 4.3) */
    int env;      /* environment effects (SPEC 6.3) with the sky cube map; 2: single layer, dispersion */
    int layers;   /* depthpeel */
} config;

static const config configs[] = {
    {"pbr2p1", SPR_ALGO_PBR2P1, 0, 0, 0, 0, 0, 0},
    {"deferred-mgc", SPR_ALGO_DEFERRED, 1, 0, 0, 0, 0, 0},
    {"deferred-mgc-voronoi", SPR_ALGO_DEFERRED, 1, 1, 0, 0, 0, 0},
    {"deferred-hash8", SPR_ALGO_DEFERRED, 2, 0, 0, 0, 0, 0},
    {"deferred-hash8-voronoi", SPR_ALGO_DEFERRED, 2, 1, 0, 0, 0, 0},
    {"pbr2p1-phong", SPR_ALGO_PBR2P1, 0, 0, 0, 1, 0, 0},
    {"deferred-mgc-phong", SPR_ALGO_DEFERRED, 1, 0, 0, 1, 0, 0},
    {"transparent1-hash8", SPR_ALGO_TRANSPARENT1, 2, 0, 0.5f, 0, 0, 0},
    {"transparent2-mgc-phong", SPR_ALGO_TRANSPARENT2, 1, 0, 0.5f, 1, 0, 0},
    {"transparent2-hash8-env", SPR_ALGO_TRANSPARENT2, 2, 0, 0.4f, 1, 1, 0},
    {"transparent2-mgc-env-single", SPR_ALGO_TRANSPARENT2, 1, 1, 0.6f, 0, 2, 0},
    {"depthpeel-3", SPR_ALGO_DEPTHPEEL, 0, 0, 0.5f, 0, 0, 3}};
static spr_envmap test_sky;
#define N_CONFIGS (int)(sizeof configs / sizeof configs[0])
#define N_OPAQUE_CONFIGS 5 /* the first rows: the other bunny views run only these */

typedef struct model_groups {
    spr_groups mgc, hash;
} model_groups;

static void make_groups(const spr_cloud *c, double cf, model_groups *mg)
{
    int32_t *lab = malloc(c->n * sizeof *lab);
    spr_group_stats st;
    spr_error err;
    spr_mgc_desc md;
    spr_mgc_defaults(&md);
    md.c = cf;
    ck_assert_int_eq(spr_group_mgc(c, &md, lab, &st, &err), SPR_OK);
    ck_assert_int_eq(spr_groups_from_labels(lab, c->n, st.K, &mg->mgc, &err), SPR_OK);
    spr_hash_desc hd;
    spr_hash_defaults(&hd);
    ck_assert_int_eq(spr_group_hash(c, &hd, lab, &st, &err), SPR_OK);
    ck_assert_int_eq(spr_groups_from_labels(lab, c->n, 8, &mg->hash, &err), SPR_OK);
    free(lab);
}

static void free_groups(model_groups *mg)
{
    spr_groups_free(&mg->mgc);
    spr_groups_free(&mg->hash);
}

static void some_configs(const char *scene, const spr_view *v, const spr_cloud *c, const model_groups *mg, spr_kernel kernel, int n)
{
    for (int i = 0; i < n; i++) {
        const config *cf = &configs[i];
        spr_render_desc d = {.algo = cf->algo, .voronoi = cf->voronoi, .kernel = kernel, .alpha = cf->alpha, .layers = cf->layers};
        d.groups = cf->groups == 1 ? &mg->mgc : cf->groups == 2 ? &mg->hash : NULL;
        spr_shading_defaults(&d.shade);
        if (cf->shade) d.shade.model = SPR_SHADE_PHONG;
        if (cf->env) {
            if (!test_sky.texels) {
                spr_error err;
                ck_assert_int_eq(spr_envmap_builtin("sky", 32, &test_sky, &err), SPR_OK);
            }
            d.shade.env = &test_sky;
            d.shade.multilayer = cf->env == 1;
            if (cf->env == 2) d.shade.eta[0] = 0.9, d.shade.eta[1] = 0.7, d.shade.eta[2] = 0.5;
        }
        char label[160];
        snprintf(label, sizeof label, "%s/%s/%s", scene, configs[i].name, spr_kernel_name(kernel));
        expect_exact(label, v, c, &d);
    }
}

/* Every configuration: the opaque five and the transparency/shading rows. */
static void all_configs(const char *scene, const spr_view *v, const spr_cloud *c, const model_groups *mg, spr_kernel kernel)
{
    some_configs(scene, v, c, mg, kernel, N_CONFIGS);
}

static void view_for(const spr_cloud *c, spr_camera_desc *cam, spr_view *v)
{
    spr_bounds bd;
    spr_cloud_bounds(c, &bd);
    spr_camera_frame(cam, &bd);
    spr_error err;
    ck_assert_msg(spr_view_make(cam, v, &err) == SPR_OK, "%s", err.msg);
}

/* The raw-call scenes: a 3000-splat sphere framed at 96×80. */
static spr_cloud sphere_scene(spr_view *v)
{
    spr_cloud c = tu_builtin("builtin:sphere", 3000);
    spr_camera_desc cam;
    spr_camera_defaults(&cam);
    cam.width = 96;
    cam.height = 80;
    view_for(&c, &cam, v);
    return c;
}

START_TEST(blend_modes_and_depth_funcs_match)
{
    /* Raw draws, every blend mode × depth function × output, on float targets:
     * PARITY.md rule 7 checked directly, not only through the algorithms. */
    spr_view v;
    spr_cloud c = sphere_scene(&v);
    for (size_t i = 0; i < c.n; i++) c.alpha[i] = (float)(i % 17) / 16.0f;
    size_t np = (size_t)v.width * v.height;
    float *a = malloc(np * 16), *b = malloc(np * 16);
    for (int blend = 0; blend < SPR_BLEND__COUNT * SPR_BLEND__COUNT; blend++) /* rgb × alpha blends */
        for (int func = 0; func < SPR_FUNC__COUNT; func++)
            for (int out = 0; out < SPR_OUT__COUNT; out++) {
                spr_backend *be[2] = {cpu, gl};
                int t[2];
                for (int k = 0; k < 2; k++) {
                    ck_assert_int_eq(spr_backend_set_view(be[k], &v), SPR_OK);
                    ck_assert_int_eq(spr_backend_target_create(be[k], SPR_PLANES_ALL, &t[k]), SPR_OK);
                    static const float bg[4] = {0.1f, 0.2f, 0.3f, 0.4f};
                    ck_assert_int_eq(spr_backend_clear(be[k], t[k], bg), SPR_OK);
                    spr_draw_desc d = {.cloud = &c};
                    spr_pass_state_defaults(&d.state);
                    d.state.blend = (spr_blend)(blend % SPR_BLEND__COUNT);
                    d.state.blend_alpha = (spr_blend)(blend / SPR_BLEND__COUNT);
                    d.state.depth_func = (spr_depth_func)func;
                    d.state.output = (spr_frag_output)out;
                    d.state.depth_write = func != SPR_FUNC_ALWAYS;
                    d.state.depth_value = SPR_DEPTH_EPS_OFFSET;
                    d.state.eps_t = 0.01f;
                    if (d.state.blend_alpha != SPR_BLEND_OVER && d.state.blend_alpha != SPR_BLEND_PREMUL) d.state.write_mask |= SPR_WRITE_OPACITY;
                    for (int rep = 0; rep < 2; rep++) /* twice: the second draw blends onto the first */
                        ck_assert_int_eq(spr_backend_draw(be[k], t[k], &d, NULL), SPR_OK);
                }
                for (int p = 0; p < SPR_PLANE__COUNT; p++) {
                    ck_assert_int_eq(spr_backend_read_plane(cpu, t[0], (spr_plane)p, a), SPR_OK);
                    ck_assert_int_eq(spr_backend_read_plane(gl, t[1], (spr_plane)p, b), SPR_OK);
                    size_t bytes = np * 4 * (size_t)spr_plane_channels((spr_plane)p);
                    ck_assert_msg(memcmp(a, b, bytes) == 0, "blend %d func %d output %d: plane %s differs", blend, func, out,
                                  spr_plane_name((spr_plane)p));
                }
                spr_backend_target_destroy(cpu, t[0]);
                spr_backend_target_destroy(gl, t[1]);
                cases++;
            }
    free(a);
    free(b);
    spr_cloud_free(&c);
}
END_TEST

START_TEST(bunny_six_views)
{
    spr_cloud c;
    tu_load("meshes/bunny00.off", &c);
    model_groups mg;
    make_groups(&c, 0.6, &mg);
    static const struct { const char *name; double eye[3], target[3], up[3], fov, ortho; } views[] = {
        {"front", {0, 0, 3.2}, {0, 0, 0}, {0, 1, 0}, 30, 0},
        {"back", {0.2, 0.1, -3.2}, {0, 0, 0}, {0, 1, 0}, 30, 0},
        {"side", {3.2, 0.3, 0.4}, {0, 0, 0}, {0, 1, 0}, 30, 0},
        {"top", {0.05, 3.2, 0.2}, {0, 0, 0}, {0, 0, -1}, 30, 0},
        {"grazing", {2.6, -0.46, 2.4}, {0, -0.3, 0}, {0, 1, 0}, 35, 0},
        {"closeup", {0.1, 0.1, 1.1}, {0.1, 0.1, 0}, {0, 1, 0}, 20, 0},
        {"ortho", {1.5, 1.0, 2.5}, {0, 0, 0}, {0, 1, 0}, 0, 1.2},
    };
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) {
        spr_camera_desc cam;
        spr_camera_defaults(&cam);
        cam.width = 192;
        cam.height = 160;
        memcpy(cam.eye, views[i].eye, sizeof cam.eye);
        memcpy(cam.target, views[i].target, sizeof cam.target);
        memcpy(cam.up, views[i].up, sizeof cam.up);
        cam.fov_deg = views[i].fov;
        cam.ortho_height = views[i].ortho;
        spr_view v;
        view_for(&c, &cam, &v);
        char scene[64];
        snprintf(scene, sizeof scene, "bunny-%s", views[i].name);
        some_configs(scene, &v, &c, &mg, (spr_kernel)(i % SPR_KERNEL__COUNT), i == 0 ? N_CONFIGS : N_OPAQUE_CONFIGS);
    }
    free_groups(&mg);
    spr_cloud_free(&c);
}
END_TEST

START_TEST(builtin_models)
{
    static const char *names[] = {"builtin:sphere", "builtin:torus", "builtin:octahedron", "builtin:cube", "builtin:spheres"};
    for (int m = 0; m < 5; m++) {
        spr_cloud c = tu_builtin(names[m], 8000);
        model_groups mg;
        make_groups(&c, 1.0, &mg);
        spr_camera_desc cam;
        spr_camera_defaults(&cam);
        cam.width = 160;
        cam.height = 160;
        cam.eye[0] = 2.0; cam.eye[1] = 2.5; cam.eye[2] = 4.5;
        spr_view v;
        view_for(&c, &cam, &v);
        all_configs(names[m] + 8, &v, &c, &mg, (spr_kernel)(m % SPR_KERNEL__COUNT));
        free_groups(&mg);
        spr_cloud_free(&c);
    }
}
END_TEST

/* A grid of n×n splats in the plane through `origin` spanned by u and w. */
static void grid(spr_cloud *c, size_t first, int n, const double origin[3], const double u[3], const double w[3],
                 const double nrm[3], float r, const float col[3])
{
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) {
            size_t i = first + (size_t)a * n + b;
            for (int k = 0; k < 3; k++) {
                c->pos[3 * i + k] = (float)(origin[k] + u[k] * (a - n / 2) + w[k] * (b - n / 2));
                c->nrm[3 * i + k] = (float)nrm[k];
                c->color[3 * i + k] = col[k];
            }
            spr__normalize3(c->nrm + 3 * i);
            c->radius[i] = r;
        }
}

START_TEST(adversarial_scenes)
{
    spr_error err;
    spr_camera_desc cam;
    spr_view v;
    model_groups mg;
    /* 1. splats nearly edge-on: the view direction lies almost in their plane */
    {
        spr_cloud c;
        ck_assert_int_eq(spr_cloud_alloc(&c, 1600), SPR_OK);
        grid(&c, 0, 40, (double[]){0, 0, 0}, (double[]){0.05, 0, 0}, (double[]){0, 0.0004, 0.05}, (double[]){0, 1, 0.0015}, 0.04f,
             (float[]){0.8f, 0.4f, 0.2f});
        for (size_t i = 0; i < c.n; i++) c.nrm[3 * i] = (float)((int)(i % 7) - 3) * 1e-4f, spr__normalize3(c.nrm + 3 * i);
        spr_camera_defaults(&cam);
        cam.width = cam.height = 160;
        cam.eye[0] = 0.01; cam.eye[1] = 0.03; cam.eye[2] = 3.0;
        view_for(&c, &cam, &v);
        make_groups(&c, 1.0, &mg);
        all_configs("edge-on", &v, &c, &mg, SPR_KERNEL_GAUSS);
        free_groups(&mg);
        spr_cloud_free(&c);
    }
    /* 2. splats crossing the near plane (and behind the eye) */
    {
        spr_cloud c;
        tu_load("meshes/bunny00.off", &c);
        spr_camera_defaults(&cam);
        cam.width = cam.height = 160;
        cam.eye[0] = 0.05; cam.eye[1] = 0.05; cam.eye[2] = 0.45;
        cam.near_plane = 0.12;
        cam.far_plane = 1.5;
        cam.fov_deg = 60;
        view_for(&c, &cam, &v);
        make_groups(&c, 0.6, &mg);
        all_configs("near-plane", &v, &c, &mg, SPR_KERNEL_EPANECHNIKOV);
        free_groups(&mg);
        spr_cloud_free(&c);
    }
    /* 3. one splat larger than the screen, with small ones in front */
    {
        spr_cloud c;
        ck_assert_int_eq(spr_cloud_alloc(&c, 101), SPR_OK);
        grid(&c, 0, 1, (double[]){0, 0, -0.5}, (double[]){0, 0, 0}, (double[]){0, 0, 0}, (double[]){0.2, 0.1, 1}, 60.0f,
             (float[]){0.2f, 0.5f, 0.9f});
        grid(&c, 1, 10, (double[]){0, 0, 0.2}, (double[]){0.12, 0, 0}, (double[]){0, 0.12, 0}, (double[]){0, 0, 1}, 0.07f,
             (float[]){0.9f, 0.8f, 0.1f});
        spr_camera_defaults(&cam);
        cam.width = cam.height = 128;
        cam.eye[2] = 3.0;
        cam.near_plane = 1.0;
        cam.far_plane = 6.0;
        view_for(&c, &cam, &v);
        make_groups(&c, 1.0, &mg);
        all_configs("huge-splat", &v, &c, &mg, SPR_KERNEL_LINEAR);
        free_groups(&mg);
        spr_cloud_free(&c);
    }
    /* 4. thousands of splats on one pixel */
    {
        spr_cloud c;
        ck_assert_int_eq(spr_cloud_alloc(&c, 5000), SPR_OK);
        for (size_t i = 0; i < c.n; i++) {
            c.pos[3 * i] = 0.001f * (float)(i % 5);
            c.pos[3 * i + 1] = 0.0f;
            c.pos[3 * i + 2] = -0.0001f * (float)(i % 97);
            c.nrm[3 * i] = 0; c.nrm[3 * i + 1] = 0; c.nrm[3 * i + 2] = 1;
            c.radius[i] = 0.02f;
            c.color[3 * i] = (float)(i % 13) / 12.0f;
            c.color[3 * i + 1] = (float)(i % 7) / 6.0f;
            c.color[3 * i + 2] = 0.5f;
        }
        spr_camera_defaults(&cam);
        cam.width = cam.height = 64;
        cam.eye[2] = 2.0;
        cam.ortho_height = 0.2;
        cam.fov_deg = 0;
        cam.near_plane = 1.0;
        cam.far_plane = 3.0;
        view_for(&c, &cam, &v);
        make_groups(&c, 1.0, &mg);
        all_configs("pixel-stack", &v, &c, &mg, SPR_KERNEL_GAUSS);
        free_groups(&mg);
        spr_cloud_free(&c);
    }
    /* 5. depth ties: identical grids at the same depth, a third offset */
    {
        spr_cloud c;
        ck_assert_int_eq(spr_cloud_alloc(&c, 3 * 400), SPR_OK);
        grid(&c, 0, 20, (double[]){0, 0, 0}, (double[]){0.1, 0, 0}, (double[]){0, 0.1, 0}, (double[]){0, 0, 1}, 0.08f,
             (float[]){1, 0, 0});
        grid(&c, 400, 20, (double[]){0, 0, 0}, (double[]){0.1, 0, 0}, (double[]){0, 0.1, 0}, (double[]){0, 0, 1}, 0.08f,
             (float[]){0, 1, 0});
        grid(&c, 800, 20, (double[]){0.05, 0.05, 0}, (double[]){0.1, 0, 0}, (double[]){0, 0.1, 0}, (double[]){0, 0, 1}, 0.08f,
             (float[]){0, 0, 1});
        spr_camera_defaults(&cam);
        cam.width = cam.height = 128;
        view_for(&c, &cam, &v);
        make_groups(&c, 1.0, &mg);
        all_configs("depth-ties", &v, &c, &mg, SPR_KERNEL_CONSTANT);
        free_groups(&mg);
        spr_cloud_free(&c);
    }
    /* 6. denormals: w·c falls below FLT_MIN (both sides flush: PARITY.md rule 6) */
    {
        spr_cloud c;
        ck_assert_int_eq(spr_cloud_alloc(&c, 400), SPR_OK);
        grid(&c, 0, 20, (double[]){0, 0, 0}, (double[]){0.1, 0, 0}, (double[]){0, 0.1, 0}, (double[]){0.1, 0.2, 1}, 0.09f,
             (float[]){3e-38f, 1e-39f, 0.5f});
        spr_camera_defaults(&cam);
        cam.width = cam.height = 96;
        view_for(&c, &cam, &v);
        make_groups(&c, 1.0, &mg);
        all_configs("denormals", &v, &c, &mg, SPR_KERNEL_GAUSS);
        free_groups(&mg);
        spr_cloud_free(&c);
    }
    (void)err;
}
END_TEST

START_TEST(report_shows_a_perturbation)
{
    /* a different ε on the GL side must be reported, with a located first difference */
    spr_cloud c;
    tu_load("meshes/bunny00.off", &c);
    spr_camera_desc cam;
    spr_camera_defaults(&cam);
    cam.width = cam.height = 128;
    spr_view v;
    view_for(&c, &cam, &v);
    spr_render_desc d = {.algo = SPR_ALGO_PBR2P1, .eps = 0.02}, dt = d;
    dt.eps = 0.021;
    spr_parity_report rep;
    spr_error err;
    ck_assert_int_eq(spr_parity_run(cpu, gl, &v, &c, &d, &dt, NULL, "perturbed", &rep, &err), SPR_OK);
    ck_assert(!spr_parity_exact(&rep));
    ck_assert_int_lt(rep.exact_planes, rep.n_planes);
    const spr_plane_diff *first = NULL;
    for (int i = 0; i < rep.n_planes && !first; i++)
        if (rep.planes[i].differing_pixels) first = &rep.planes[i];
    ck_assert_ptr_nonnull(first);
    ck_assert_int_eq(first->pass, 0);              /* the visibility pass is where it starts */
    ck_assert_int_eq(first->plane, SPR_PLANE_TEST); /* in the test depth d_f + ε_t */
    ck_assert_int_ge(first->first_x, 0);
    ck_assert(first->first_ref != first->first_test);
    spr_parity_report_free(&rep);
    spr_cloud_free(&c);
}
END_TEST

/* A draw that reads another target (SPEC §6.2 step 2): fragments with
 * d_f ≤ z_near + ε_t of the mask target are dropped, on both backends alike,
 * and the mask really drops some (the front layer of the sphere). */
START_TEST(depth_mask_and_composites_match)
{
    spr_view v;
    spr_cloud c = sphere_scene(&v);
    size_t np = (size_t)v.width * v.height;
    float *a = malloc(np * 16), *b = malloc(np * 16);
    spr_backend *be[2] = {cpu, gl};
    int m[2], t[2];
    spr_draw_stats st[2];
    for (int k = 0; k < 2; k++) {
        ck_assert_int_eq(spr_backend_set_view(be[k], &v), SPR_OK);
        ck_assert_int_eq(spr_backend_target_create(be[k], SPR_PLANES_ALL, &m[k]), SPR_OK);
        ck_assert_int_eq(spr_backend_target_create(be[k], SPR_PLANES_ALL, &t[k]), SPR_OK);
        spr_draw_desc d = {.cloud = &c};
        spr_pass_state_defaults(&d.state);
        d.state.depth_write = 1;
        ck_assert_int_eq(spr_backend_draw(be[k], m[k], &d, NULL), SPR_OK); /* nearest layer: its d_f */
        d.depth_mask = 1;
        d.mask_target = m[k];
        d.state.eps_t = 0.02f;
        d.state.write_mask |= SPR_WRITE_OPACITY;
        spr_pass_state_blend(&d.state, SPR_BLEND_ADD);
        ck_assert_int_eq(spr_backend_draw(be[k], t[k], &d, &st[k]), SPR_OK);
    }
    ck_assert_msg(st[0].generated == st[1].generated && st[0].passed == st[1].passed, "fragment counts differ");
    ck_assert_msg(st[0].generated > 0 && st[0].generated < st[0].splats * 4, "mask left %llu fragments", (unsigned long long)st[0].generated);
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        ck_assert_int_eq(spr_backend_read_plane(cpu, t[0], (spr_plane)p, a), SPR_OK);
        ck_assert_int_eq(spr_backend_read_plane(gl, t[1], (spr_plane)p, b), SPR_OK);
        ck_assert_msg(memcmp(a, b, np * 4 * (size_t)spr_plane_channels((spr_plane)p)) == 0, "masked draw: plane %s differs",
                      spr_plane_name((spr_plane)p));
    }
    /* every composite op of the table over the two targets (K = 2) */
    for (int op = 0; op < SPR_COMP__COUNT; op++) {
        if (op == SPR_COMP_PREFIX) continue; /* reads fragment lists: test_gl's rectangle tests */
        const int nin = spr_composite_info_of((spr_composite_op)op)->max_inputs < 2 ? 1 : 2;
        int out[2];
        for (int k = 0; k < 2; k++) {
            int in[2] = {m[k], t[k]};
            ck_assert_int_eq(spr_backend_target_create(be[k], SPR_PLANES_ALL, &out[k]), SPR_OK);
            spr_composite_desc cd = {(spr_composite_op)op, in, nin, out[k], 0.01f, {0.1f, 0.2f, 0.3f}, NULL, NULL, NULL};
            ck_assert_int_eq(spr_backend_composite(be[k], &cd), SPR_OK);
        }
        for (int p = 0; p < SPR_PLANE__COUNT; p++) {
            ck_assert_int_eq(spr_backend_read_plane(cpu, out[0], (spr_plane)p, a), SPR_OK);
            ck_assert_int_eq(spr_backend_read_plane(gl, out[1], (spr_plane)p, b), SPR_OK);
            ck_assert_msg(memcmp(a, b, np * 4 * (size_t)spr_plane_channels((spr_plane)p)) == 0, "composite %s: plane %s differs",
                          spr_composite_info_of((spr_composite_op)op)->name, spr_plane_name((spr_plane)p));
        }
        spr_backend_target_destroy(cpu, out[0]);
        spr_backend_target_destroy(gl, out[1]);
        cases++;
    }
    for (int k = 0; k < 2; k++) {
        spr_backend_target_destroy(be[k], m[k]);
        spr_backend_target_destroy(be[k], t[k]);
    }
    free(a);
    free(b);
    spr_cloud_free(&c);
    cases++;
}
END_TEST

/* The fragments each pass generated and passed, algorithm after algorithm in
 * one context as parity runs them (every plane captured after each pass):
 * the GL counts equal the CPU's in every pass.  On Mesa 22.3.6's zink an
 * atomic counter zeroed by glBufferSubData while still in use kept the old
 * storage in the draws' bindings, and blend passes counted 0 from the
 * first pbr2p1 with shading on (gl_buffers.c; CTest gl_zink runs this
 * suite on zink). */
START_TEST(fragment_counts_every_pass)
{
    spr_view v;
    spr_cloud c = sphere_scene(&v);
    static const struct { spr_algo algo; int shade, layers; float alpha; } runs[] = {
        {SPR_ALGO_PBR2P1, 0, 0, 0}, {SPR_ALGO_DEFERRED, 0, 0, 0}, {SPR_ALGO_PBR2P1, 1, 0, 0},
        {SPR_ALGO_DEPTHPEEL, 0, 2, 0.5f}, {SPR_ALGO_TRANSPARENT2, 1, 0, 0.5f}, {SPR_ALGO_PBR2P1, 1, 0, 0}};
    for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
        spr_render_desc d = {.algo = runs[i].algo, .alpha = runs[i].alpha, .layers = runs[i].layers};
        spr_shading_defaults(&d.shade);
        if (runs[i].shade) d.shade.model = SPR_SHADE_PHONG;
        spr_parity_report rep;
        spr_error err = {0};
        ck_assert_msg(spr_parity_run(cpu, gl, &v, &c, &d, &d, NULL, "counts", &rep, &err) == SPR_OK, "%s", err.msg);
        ck_assert_msg(rep.stats_mismatches == 0, "run %zu (%s%s): %d passes count differently, first %s", i, spr_algo_name(d.algo),
                      runs[i].shade ? ", phong" : "", rep.stats_mismatches, rep.first_stats_mismatch);
        spr_parity_report_free(&rep);
    }
    spr_cloud_free(&c);
}
END_TEST

/* EGL runs one driver a display: while the suite's backend is open, a
 * backend asking for another driver by name is refused in one line naming
 * the driver that is open, and one asking for the same driver shares it. */
START_TEST(a_second_driver_while_one_is_open_is_refused)
{
    const char *open = spr_gl_renderer(gl);
    const int on_zink = !strncmp(open, "zink", 4), on_llvmpipe = !strncmp(open, "llvmpipe", 8);
    spr_gl_desc d;
    tu_gl_desc(&d);
    d.driver = on_zink ? SPR_GL_DRIVER_LLVMPIPE : SPR_GL_DRIVER_ZINK;
    spr_error err = {0};
    spr_backend *other = spr_gl_create(&d, &err);
    ck_assert_msg(other == NULL, "a backend on %s opened beside one on %s", spr_gl_driver_name(d.driver), open);
    ck_assert_int_eq(err.code, SPR_E_ARG);
    ck_assert_msg(strstr(err.msg, "this process already has a GL backend open on ") && strstr(err.msg, spr_gl_driver_name(d.driver)), "%s", err.msg);
    d.device = 0; /* a driver by name is the surfaceless platform's: with a device, refused before EGL is asked */
    ck_assert_msg(spr_gl_create(&d, &err) == NULL && err.code == SPR_E_ARG && strstr(err.msg, "not on --gl-device 0"), "%s", err.msg);
    d.device = -1;
    if (on_zink || on_llvmpipe) {
        d.driver = on_zink ? SPR_GL_DRIVER_ZINK : SPR_GL_DRIVER_LLVMPIPE;
        spr_backend *same = spr_gl_create(&d, &err);
        ck_assert_msg(same != NULL, "%s", err.msg);
        ck_assert_msg(!strcmp(spr_gl_renderer(same), open), "%s vs %s", spr_gl_renderer(same), open);
        spr_backend_destroy(same);
    }
}
END_TEST

/* Two GL backends in one process, used in turn: each call makes its own
 * context current, so both draw into their own targets and both equal the
 * CPU reference. */
START_TEST(two_gl_backends_in_one_process)
{
    spr_error err = {0};
    spr_gl_desc gd;
    tu_gl_desc(&gd);
    spr_backend *gl2 = spr_gl_create(&gd, &err);
    ck_assert_msg(gl2 != NULL, "%s", err.msg);
    spr_cloud c = tu_builtin("builtin:torus", 3000);
    spr_view v[2];
    for (int k = 0; k < 2; k++) { /* different sizes, so neither backend's objects fit the other's frame */
        spr_camera_desc cam;
        spr_camera_defaults(&cam);
        cam.width = k ? 40 : 64;
        cam.height = k ? 30 : 48;
        view_for(&c, &cam, &v[k]);
    }
    spr_render_desc d = {.algo = SPR_ALGO_DEFERRED};
    spr_backend *order[3] = {gl2, gl, gl2};
    for (int i = 0; i < 3; i++) {
        int k = order[i] == gl2;
        spr_render_result rc, rg;
        tu_render(&v[k], &c, &d, 2, &rc);
        ck_assert_msg(spr_render(order[i], &v[k], &c, &d, &rg, &err) == SPR_OK, "%s", err.msg);
        ck_assert_msg(memcmp(rc.rgba, rg.rgba, (size_t)v[k].width * v[k].height * 4 * sizeof(float)) == 0,
                      "GL backend %d (render %d) differs from the CPU", k + 1, i);
        spr_render_result_free(&rc);
        spr_render_result_free(&rg);
    }
    /* targets alive on both at once keep their own contents */
    static const float red[4] = {1, 0, 0, 1}, blue[4] = {0, 0, 1, 1};
    int t1, t2;
    ck_assert_int_eq(spr_backend_set_view(gl, &v[0]), SPR_OK);
    ck_assert_int_eq(spr_backend_set_view(gl2, &v[0]), SPR_OK);
    ck_assert_int_eq(spr_backend_target_create(gl, SPR_PLANES_IMAGE, &t1), SPR_OK);
    ck_assert_int_eq(spr_backend_target_create(gl2, SPR_PLANES_IMAGE, &t2), SPR_OK);
    ck_assert_int_eq(spr_backend_clear(gl, t1, red), SPR_OK);
    ck_assert_int_eq(spr_backend_clear(gl2, t2, blue), SPR_OK);
    float px[64 * 48 * 4];
    ck_assert_int_eq(spr_backend_read_plane(gl, t1, SPR_PLANE_COLOR, px), SPR_OK);
    ck_assert_msg(px[0] == 1.0f && px[2] == 0.0f, "the first backend's target holds (%g, %g, %g)", px[0], px[1], px[2]);
    ck_assert_int_eq(spr_backend_read_plane(gl2, t2, SPR_PLANE_COLOR, px), SPR_OK);
    ck_assert_msg(px[0] == 0.0f && px[2] == 1.0f, "the second backend's target holds (%g, %g, %g)", px[0], px[1], px[2]);
    spr_backend_target_destroy(gl, t1);
    spr_backend_target_destroy(gl2, t2);
    spr_backend_destroy(gl2);
    /* and the first one still works once the second (and its context) is gone */
    spr_render_result rc, rg;
    tu_render(&v[0], &c, &d, 2, &rc);
    ck_assert_msg(spr_render(gl, &v[0], &c, &d, &rg, &err) == SPR_OK, "%s", err.msg);
    ck_assert_msg(memcmp(rc.rgba, rg.rgba, (size_t)v[0].width * v[0].height * 4 * sizeof(float)) == 0, "after destroying the second backend");
    spr_render_result_free(&rc);
    spr_render_result_free(&rg);
    spr_cloud_free(&c);
}
END_TEST

/* The program text GL compiled contains every file of the shared arithmetic
 * (core/render/arith/, listed in its ORDER file), byte for byte as it is in
 * the source tree (no copy in a string), one after another in that order. */
START_TEST(programs_embed_the_shared_arithmetic)
{
    char *order = NULL;
    size_t olen = 0;
    spr_error err = {0};
    ck_assert_msg(spr__read_file(SPR_SOURCE_DIR "/core/render/arith/ORDER", &order, &olen, &err) == SPR_OK, "%s", err.msg);
    const char *name[32];
    int parts = 0;
    for (char *line = strtok(order, "\n"); line && parts < 32; line = strtok(NULL, "\n"))
        if (line[0] != '#') name[parts++] = line;
    ck_assert_int_ge(parts, 7);
    static const char *const programs[] = {"splat", "composite", "rect"};
    for (int i = 0; i < 3; i++) {
        char *src = spr_gl_program_source(gl, programs[i]);
        ck_assert_ptr_nonnull(src);
        const char *at = src;
        for (int k = 0; k < parts; k++) {
            char path[512], *part = NULL;
            size_t len = 0;
            snprintf(path, sizeof path, "%s/core/render/arith/%s", SPR_SOURCE_DIR, name[k]);
            ck_assert_msg(spr__read_file(path, &part, &len, &err) == SPR_OK, "%s", err.msg);
            const char *hit = strstr(at, part);
            ck_assert_msg(hit != NULL, "program %s lacks arith/%s, or holds it out of ORDER", programs[i], name[k]);
            uint64_t h = 0xcbf29ce484222325ull;
            for (size_t j = 0; j < len; j++) { h ^= (unsigned char)part[j]; h *= 0x100000001b3ull; }
            if (i == 0) printf("gl: programs hold arith/%s (%zu bytes, FNV-1a %016llx)\n", name[k], len, (unsigned long long)h);
            at = hit + len;
            free(part);
        }
        free(src);
    }
    free(order);
}
END_TEST

/* Every case above ran (a loop that silently ran nothing would pass them):
 * 9 blend pairs × 3 functions × 2 outputs = 54 raw draws, 1 masked draw, one
 * raw composite per op of the table, and the algorithm scenes of
 * expect_exact (bunny views × configurations, built-ins, adversarial
 * scenes: bunny 12 + 5·5, built-ins 5·12, adversarial 6·12 = 169 since the
 * transparency and shading rows). */
/* SPEC 7.7: every domain method, Tier A, on the cube's level-2 primitives
 * (thresholded and strict, nearest and explicit bilinear). */
START_TEST(domain_methods_match)
{
    spr_cloud c = tu_builtin("builtin:cube", 4000);
    spr_decomp_desc dd;
    spr_decomp_defaults(&dd);
    spr_decomp dc = {0};
    spr_error err = {0};
    ck_assert_msg(spr_decompose(&c, &dd, &dc, &err) == SPR_OK, "%s", err.msg);
    spr_camera_desc cam;
    spr_camera_defaults(&cam);
    cam.width = cam.height = 96;
    cam.eye[0] = 3.0; cam.eye[1] = 2.2; cam.eye[2] = 4.5;
    spr_view v;
    view_for(&c, &cam, &v);
    for (int variant = 0; variant < 2; variant++) {
        spr_prims_desc pd;
        spr_prims_defaults(&pd);
        pd.strict = variant;
        pd.tex.extend_color = 1;
        spr_rects r;
        spr_prims_stats st;
        ck_assert_msg(spr_domain_prims(&c, &dc.basis[dc.levels > 2 ? 2 : 0], &pd, &r, &st, &err) == SPR_OK, "%s", err.msg);
        for (int al = SPR_ALGO_DOMAIN_BLENDALL; al <= SPR_ALGO_DOMAIN_PREFIX; al++) {
            spr_render_desc d;
            memset(&d, 0, sizeof d);
            d.algo = (spr_algo)al;
            d.rects = &r;
            d.sampling = variant ? SPR_SAMPLE_NEAREST : SPR_SAMPLE_LINEAR;
            char label[64];
            snprintf(label, sizeof label, "cube %s %s", spr_algo_name((spr_algo)al), variant ? "strict nearest" : "thresholded linear");
            expect_exact(label, &v, &c, &d);
        }
        spr_rects_free(&r);
    }
    spr_decomp_free(&dc);
    spr_cloud_free(&c);
}
END_TEST

START_TEST(summary)
{
    printf("gl: %s — %d parity cases, %d planes compared, all bit-exact\n", spr_gl_renderer(gl), cases, planes_checked);
    ck_assert_int_ge(cases, 55 + 169 + SPR_COMP__COUNT);
    ck_assert_int_gt(planes_checked, 1000);
}
END_TEST

Suite *make_gl_suite(void)
{
    Suite *s = suite_create("gl");
    TCase *tc = tcase_create("gl");
    tcase_set_timeout(tc, 900);
    tcase_add_unchecked_fixture(tc, setup, teardown);
    tcase_add_test(tc, blend_modes_and_depth_funcs_match);
    tcase_add_test(tc, bunny_six_views);
    tcase_add_test(tc, builtin_models);
    tcase_add_test(tc, adversarial_scenes);
    tcase_add_test(tc, report_shows_a_perturbation);
    tcase_add_test(tc, depth_mask_and_composites_match);
    tcase_add_test(tc, programs_embed_the_shared_arithmetic);
    tcase_add_test(tc, two_gl_backends_in_one_process);
    tcase_add_test(tc, fragment_counts_every_pass);
    tcase_add_test(tc, a_second_driver_while_one_is_open_is_refused);
    tcase_add_test(tc, domain_methods_match);
    tcase_add_test(tc, summary);
    suite_add_tcase(s, tc);
    return s;
}
