/* cli_scene.c — what render, parity and reference share: reading the scene
 * options, loading and framing the model, grouping, making a backend. */
#include "spr_util.h"
#include "cli.h"
#include "spr_glbackend.h"
#include "spr_swrast.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void cli_scene_free(cli_scene *s)
{
    spr_cloud_free(&s->cloud);
    spr_groups_free(&s->groups);
    spr_overlap_graph_free(&s->og);
    free(s->labels);
    s->labels = NULL;
}

int cli_parse_group_opts(const cli_args *a, cli_group_opts *o)
{
    memset(o, 0, sizeof *o);
    o->method = cli_get(a, "method") ? cli_get(a, "method") : cli_get(a, "groups") ? cli_get(a, "groups") : "mgc";
    o->c = 1.0;
    o->K = 8;
    o->mode = 1;
    o->relax = cli_get(a, "relax");
    o->extend = cli_get(a, "extend");
    const char *axis = cli_get(a, "hash-axis");
    if (cli_get_double(a, "c", &o->c, 1e-6, 1.0) < 0 || cli_get_int(a, "k", &o->K, 1, SPR_MAX_GROUPS) < 0 ||
        cli_get_int(a, "mode", &o->mode, 1, 3) < 0)
        return -1;
    if (cli_get(a, "hash-near") && !strcmp(cli_get(a, "hash-near"), "centre")) o->hash_near = -1.0; /* eye to model centre */
    else if (cli_get_double(a, "hash-near", &o->hash_near, 0.0, 1e30) < 0) return -1;
    if (strcmp(o->method, "none") && strcmp(o->method, "mgc") && strcmp(o->method, "wgc") && strcmp(o->method, "hash")) {
        cli_error(a, "--groups: '%s' is not none, mgc, wgc or hash", o->method);
        return -1;
    }
    if (axis && strcmp(axis, "bsp") && strcmp(axis, "normal")) { cli_error(a, "--hash-axis: '%s' is not bsp or normal", axis); return -1; }
    o->axis = axis && !strcmp(axis, "normal") ? SPR_HASH_AXIS_NORMAL : SPR_HASH_AXIS_BSP;
    if (o->mode == 3 && !cli_get(a, "hash-near")) { cli_error(a, "--mode 3 needs --hash-near DIST (eye distance below which collisions are handled)"); return -1; }
    if (o->extend && strcmp(o->extend, "dup") && strcmp(o->extend, "radius") && strcmp(o->extend, "hash-radius")) {
        cli_error(a, "--extend: '%s' is not dup, radius or hash-radius", o->extend);
        return -1;
    }
    if (o->relax && strcmp(o->relax, "none") && strcmp(o->relax, "coplanar") && strcmp(o->relax, "opposite") &&
        strcmp(o->relax, "coplanar,opposite") && strcmp(o->relax, "opposite,coplanar")) {
        cli_error(a, "--relax: '%s' is not coplanar,opposite | coplanar | opposite | none", o->relax);
        return -1;
    }
    return 0;
}

int cli_make_groups(const cli_args *a, cli_scene *s, const cli_group_opts *o, spr_progress prog)
{
    spr_error err = {0};
    size_t n = s->cloud.n;
    s->labels = malloc((n ? n : 1) * sizeof(int32_t));
    if (!s->labels) { cli_error(a, "out of memory"); return -1; }
    memset(&s->gstats, 0, sizeof s->gstats);
    spr_result r = SPR_OK;
    s->group_method = o->method;
    double t0 = spr_now_ms();
    if (!strcmp(o->method, "none")) {
        memset(s->labels, 0, n * sizeof(int32_t));
        s->gstats.K = 1;
    } else if (!strcmp(o->method, "mgc")) {
        spr_mgc_desc d;
        spr_mgc_defaults(&d);
        d.c = o->c;
        d.threads = s->threads;
        d.progress = prog;
        if (o->relax) {
            d.relax_coplanar = strstr(o->relax, "coplanar") != NULL;
            d.relax_opposite = strstr(o->relax, "opposite") != NULL;
        }
        r = spr_group_mgc(&s->cloud, &d, s->labels, &s->gstats, &err);
    } else if (!strcmp(o->method, "wgc")) {
        spr_wgc_desc d;
        spr_wgc_defaults(&d);
        d.K = o->K;
        d.threads = s->threads;
        d.progress = prog;
        d.graph_out = &s->og;
        r = spr_group_wgc(&s->cloud, &d, s->labels, &s->gstats, &err);
    } else {
        spr_hash_desc d;
        spr_hash_defaults(&d);
        d.K = o->K;
        d.mode = o->mode;
        d.axis = o->axis;
        d.near_dist = o->hash_near;
        memcpy(d.eye, s->cam.eye, sizeof d.eye);
        if (d.near_dist < 0.0) {
            spr_bounds b;
            spr_cloud_bounds(&s->cloud, &b);
            d.near_dist = 0.0;
            for (int k = 0; k < 3; k++) d.near_dist += (0.5 * (b.lo[k] + b.hi[k]) - d.eye[k]) * (0.5 * (b.lo[k] + b.hi[k]) - d.eye[k]);
            d.near_dist = sqrt(d.near_dist);
        }
        d.threads = s->threads;
        d.progress = prog;
        r = spr_group_hash(&s->cloud, &d, s->labels, &s->gstats, &err);
    }
    s->ms_grouping = spr_now_ms() - t0;
    if (r) { fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg); return -1; }
    t0 = spr_now_ms();
    spr_extend_desc ed;
    spr_extend_defaults(&ed);
    ed.threads = s->threads;
    ed.progress = prog;
    if (o->extend && !strcmp(o->extend, "dup")) {
        r = spr_group_duplicate(&s->cloud, s->labels, s->gstats.K, &ed, &s->groups, &s->dup_ratio, &err);
    } else {
        r = spr_groups_from_labels(s->labels, n, s->gstats.K, &s->groups, &err);
        if (!r && o->extend && !strcmp(o->extend, "radius")) r = spr_group_enlarge(&s->cloud, &s->groups, &ed, &err);
        if (!r && o->extend && !strcmp(o->extend, "hash-radius")) {
            /* [ZP] §4.4.2's fast approximation: the lattice circumradius, √50/4 for K = 8 */
            s->groups.radius_scale = malloc((size_t)s->groups.K * sizeof(float));
            if (!s->groups.radius_scale) r = spr__fail(&err, SPR_E_NOMEM, "out of memory");
            for (int k = 0; !r && k < s->groups.K; k++) s->groups.radius_scale[k] = (float)spr_hash_enlarge_factor(s->groups.K);
        }
    }
    s->ms_extend = o->extend ? spr_now_ms() - t0 : 0.0;
    if (r) { fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg); return -1; }
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
    double bg[3] = {0, 0, 0};
    int quiet = cli_flag(a, "quiet");
    cli_group_opts go;
    const char *model = cli_get(a, "model") ? cli_get(a, "model") : "builtin:torus";
    const char *kname = cli_get(a, "kernel"), *aname = cli_get(a, "algo");
    /* Parse and check every option before any work. */
    if (cli_get_size(a, "points", &ld.points, 16, SPR_MAX_SPLATS) < 0 || cli_get_int(a, "radius-k", &ld.radius_k, 1, 256) < 0 ||
        cli_get_double(a, "radius-scale", &ld.radius_rho, 1e-6, 1e6) < 0 || cli_get_vec3(a, "eye", s->cam.eye) < 0 ||
        cli_get_vec3(a, "target", s->cam.target) < 0 || cli_get_vec3(a, "up", s->cam.up) < 0 ||
        cli_get_double(a, "fov", &s->cam.fov_deg, 1e-3, 179.0) < 0 || cli_get_double(a, "ortho", &s->cam.ortho_height, 1e-12, 1e30) < 0 ||
        cli_get_double(a, "near", &s->cam.near_plane, 0.0, 1e30) < 0 || cli_get_double(a, "far", &s->cam.far_plane, 0.0, 1e30) < 0 ||
        cli_get_wh(a, "size", &s->cam.width, &s->cam.height) < 0 || cli_get_vec3(a, "background", bg) < 0 ||
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
    if (cli_parse_group_opts(a, &go)) return -1;
    rd->voronoi = cli_flag(a, "voronoi");
    ld.threads = s->threads;
    ld.progress = cli_progress(quiet);

    double t0 = spr_now_ms();
    snprintf(s->model, sizeof s->model, "%s", model);
    if (spr_load(model, &ld, &s->cloud, &err)) { fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg); return -1; }
    s->load_ms = spr_now_ms() - t0;
    spr_bounds bd;
    spr_cloud_bounds(&s->cloud, &bd);
    spr_camera_frame(&s->cam, &bd);
    if (spr_view_make(&s->cam, &s->view, &err)) { fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg); return -1; }

    if (rd->algo == SPR_ALGO_DEFERRED || s->all_algos) {
        const char *gf = cli_get(a, "groups-file");
        if (gf) {
            t0 = spr_now_ms();
            s->labels = malloc(s->cloud.n * sizeof(int32_t));
            if (!s->labels) { cli_error(a, "out of memory"); return -1; }
            s->group_method = "file";
            if (spr_groups_read_any(gf, s->cloud.n, &s->groups, s->labels, &err)) {
                fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg);
                return -1;
            }
            s->ms_grouping = spr_now_ms() - t0;
        } else if (cli_make_groups(a, s, &go, cli_progress(quiet))) {
            return -1;
        }
        rd->groups = &s->groups;
    }
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
