/* cli_scene.c — what render, parity and reference share: reading the scene
 * options, loading and framing the model, grouping, making a backend. */
#include "cli.h"
#include "spr_glbackend.h"
#include "spr_swrast.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

void cli_scene_free(cli_scene *s)
{
    spr_cloud_free(&s->cloud);
    spr_groups_free(&s->groups);
    free(s->labels);
    s->labels = NULL;
}

int cli_make_groups(const cli_args *a, cli_scene *s, const char *method, double c, const char *relax, int K, int threads,
                    spr_progress prog)
{
    spr_error err = {0};
    size_t n = s->cloud.n;
    s->labels = malloc((n ? n : 1) * sizeof(int32_t));
    if (!s->labels) { cli_error(a, "out of memory"); return -1; }
    memset(&s->gstats, 0, sizeof s->gstats);
    spr_result r = SPR_OK;
    s->group_method = method;
    if (!strcmp(method, "none")) {
        memset(s->labels, 0, n * sizeof(int32_t));
        s->gstats.K = 1;
    } else if (!strcmp(method, "mgc")) {
        spr_mgc_desc d;
        spr_mgc_defaults(&d);
        d.c = c;
        d.threads = threads;
        d.progress = prog;
        if (relax) {
            if (!strcmp(relax, "none")) d.relax_coplanar = d.relax_opposite = 0;
            else if (!strcmp(relax, "coplanar")) d.relax_opposite = 0;
            else if (!strcmp(relax, "opposite")) d.relax_coplanar = 0;
            else if (strcmp(relax, "coplanar,opposite") && strcmp(relax, "opposite,coplanar")) {
                cli_error(a, "--relax: '%s' is not coplanar,opposite | coplanar | opposite | none", relax);
                return -1;
            }
        }
        r = spr_group_mgc(&s->cloud, &d, s->labels, &s->gstats, &err);
    } else if (!strcmp(method, "hash")) {
        r = spr_group_hash(&s->cloud, K, s->labels, &s->gstats, &err);
    } else {
        cli_error(a, "--groups: '%s' is not none, mgc or hash", method);
        return -1;
    }
    if (!r) r = spr_groups_from_labels(s->labels, n, s->gstats.K, &s->groups, &err);
    if (r) { cli_error(a, "%s", err.msg); return -1; }
    return 0;
}

int cli_scene_setup(const cli_args *a, cli_scene *s, spr_render_desc *rd, int allow_all)
{
    memset(s, 0, sizeof *s);
    memset(rd, 0, sizeof *rd);
    spr_error err = {0};
    spr_load_desc ld;
    spr_load_defaults(&ld);
    spr_camera_defaults(&s->cam);
    double c = 1.0, bg[3] = {0, 0, 0};
    int K = 8, quiet = cli_flag(a, "quiet");
    const char *model = cli_get(a, "model") ? cli_get(a, "model") : "builtin:torus";
    const char *method = cli_get(a, "groups") ? cli_get(a, "groups") : "mgc";
    const char *kname = cli_get(a, "kernel"), *aname = cli_get(a, "algo");
    /* Parse and check every option before any work. */
    if (cli_get_size(a, "points", &ld.points, 16, SPR_MAX_SPLATS) < 0 || cli_get_int(a, "radius-k", &ld.radius_k, 1, 256) < 0 ||
        cli_get_double(a, "radius-scale", &ld.radius_rho, 1e-6, 1e6) < 0 || cli_get_vec3(a, "eye", s->cam.eye) < 0 ||
        cli_get_vec3(a, "target", s->cam.target) < 0 || cli_get_vec3(a, "up", s->cam.up) < 0 ||
        cli_get_double(a, "fov", &s->cam.fov_deg, 1e-3, 179.0) < 0 || cli_get_double(a, "ortho", &s->cam.ortho_height, 1e-12, 1e30) < 0 ||
        cli_get_double(a, "near", &s->cam.near_plane, 0.0, 1e30) < 0 || cli_get_double(a, "far", &s->cam.far_plane, 0.0, 1e30) < 0 ||
        cli_get_wh(a, "size", &s->cam.width, &s->cam.height) < 0 || cli_get_vec3(a, "background", bg) < 0 ||
        cli_get_double(a, "c", &c, 1e-6, 1.0) < 0 || cli_get_int(a, "k", &K, 1, SPR_MAX_GROUPS) < 0 ||
        cli_get_double(a, "eps", &rd->eps, 1e-30, 1e30) < 0 || cli_get_double(a, "lowres-n", &rd->lowres_n, 1.0, 16777216.0) < 0 ||
        cli_get_int(a, "threads", &s->threads, 0, 1024) < 0)
        return -1;
    for (int k = 0; k < 3; k++) {
        if (bg[k] < 0.0 || bg[k] > 1.0) { cli_error(a, "--background: components must lie in [0,1]"); return -1; }
        rd->background[k] = (float)bg[k];
    }
    if (cli_get(a, "ortho")) s->cam.fov_deg = 0.0;
    s->all_algos = allow_all && (!aname || !strcmp(aname, "all"));
    if (aname && !s->all_algos && (int)(rd->algo = (spr_algo)spr_algo_from_name(aname)) < 0) {
        cli_error(a, "--algo: '%s' is not pbr2p1%s or deferred", aname, allow_all ? ", all" : "");
        return -1;
    }
    if (kname && (int)(rd->kernel = (spr_kernel)spr_kernel_from_name(kname)) < 0) {
        cli_error(a, "--kernel: '%s' is not gauss, constant, linear or epanechnikov", kname);
        return -1;
    }
    if (strcmp(method, "none") && strcmp(method, "mgc") && strcmp(method, "hash")) {
        cli_error(a, "--groups: '%s' is not none, mgc or hash", method);
        return -1;
    }
    rd->voronoi = cli_flag(a, "voronoi");
    ld.threads = s->threads;
    ld.progress = cli_progress(quiet);

    double t0 = now_ms();
    snprintf(s->model, sizeof s->model, "%s", model);
    if (spr_load(model, &ld, &s->cloud, &err)) { fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg); return -1; }
    s->load_ms = now_ms() - t0;
    spr_bounds bd;
    spr_cloud_bounds(&s->cloud, &bd);
    spr_camera_frame(&s->cam, &bd);
    if (spr_view_make(&s->cam, &s->view, &err)) { fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg); return -1; }

    t0 = now_ms();
    if (rd->algo == SPR_ALGO_DEFERRED || s->all_algos) {
        const char *gf = cli_get(a, "groups-file");
        if (gf) {
            s->labels = malloc(s->cloud.n * sizeof(int32_t));
            if (!s->labels) { cli_error(a, "out of memory"); return -1; }
            s->group_method = "file";
            if (spr_groups_read(gf, s->cloud.n, s->labels, &err) || spr_groups_from_labels(s->labels, s->cloud.n, 0, &s->groups, &err)) {
                fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg);
                return -1;
            }
        } else if (cli_make_groups(a, s, method, c, cli_get(a, "relax"), K, s->threads, cli_progress(quiet))) {
            return -1;
        }
        rd->groups = &s->groups;
    }
    s->group_ms = now_ms() - t0;
    return 0;
}

spr_backend *cli_backend(const cli_args *a, const char *name, int threads, int gl_device)
{
    spr_error err = {0};
    spr_backend *b;
    if (!strcmp(name, "gl")) {
        spr_gl_desc d;
        spr_gl_defaults(&d);
        d.device = gl_device;
        b = spr_gl_create(&d, &err);
    } else {
        b = spr_swrast_create(threads, &err);
    }
    if (!b) fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg);
    return b;
}
