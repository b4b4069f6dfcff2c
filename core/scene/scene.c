/* scene.c — what render, parity and reference share: the scene's work once
 * its options are read and checked (sceneopts.c): the cube map, loading and
 * framing the model, the BSP tree, grouping, the domain primitives, making a
 * backend. */
#include "spr_util.h"
#include "spr__options.h"
#include "spr__scene_opts.h"
#include "spr_glbackend.h"
#include "spr_swrast.h"
#include "spr_envmap.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void spr_scene_free(spr_scene *s)
{
    spr_cloud_free(&s->cloud);
    if (s->src.read) spr_ply_source_close(&s->src);
    spr_grouping_free(&s->g);
    if (s->bsp.nodes) spr_bsp_free(&s->bsp);
    spr_envmap_free(&s->env);
    spr_rects_free(&s->rects);
}

int spr__make_groups(spr__args *a, spr_scene *s, spr_grouping_desc *gd, const char *hash_near)
{
    spr_error err = {0};
    memcpy(gd->hash.eye, s->cam.eye, sizeof gd->hash.eye);
    if (hash_near && !strcmp(hash_near, "centre")) { /* eye to the model centre */
        spr_bounds b;
        spr_cloud_bounds(&s->cloud, &b);
        double q = 0.0;
        for (int k = 0; k < 3; k++) q += (0.5 * (b.lo[k] + b.hi[k]) - gd->hash.eye[k]) * (0.5 * (b.lo[k] + b.hi[k]) - gd->hash.eye[k]);
        gd->hash.near_dist = sqrt(q);
    }
    gd->threads = s->threads;
    s->group_method = spr_group_method_name(gd->method);
    if (spr_group_run(&s->cloud, gd, &s->g, &err)) { spr__error(a, "%s", err.msg); return -1; }
    return 0;
}

/* --stream: open the model as a chunked source and read it once (bounds,
 * every value checked); with `keep` the centres, normals and radii stay in
 * s->cloud for grouping (spr__stream_drop frees them once grouped). */
static int stream_model(spr__args *a, spr_scene *s, const spr_load_desc *ld, int keep)
{
    spr_error err = {0};
    size_t chunk = s->stream_chunk ? s->stream_chunk : (size_t)1 << 20;
    if (!strncmp(s->model, "builtin:", 8) || ld->balls > 0) {
        spr__error(a, "--stream reads a binary PLY file%s", ld->balls > 0 ? " as it is: --balls adds to the whole cloud" : "");
        return -1;
    }
    double t0 = spr_now_ms();
    if (spr_ply_source_open(s->model, ld, chunk, &s->src, &err) ||
        spr_cloud_source_scan(&s->src, keep ? &s->cloud : NULL, &ld->progress, &err)) {
        spr__error(a, "%s", err.msg);
        return -1;
    }
    s->cloud.n = s->src.n;
    s->cloud.flags = s->src.flags;
    s->load_ms = spr_now_ms() - t0;
    s->cam_given = s->cam;
    s->bounds = s->src.bounds;
    spr_camera_frame(&s->cam, &s->bounds);
    return 0;
}

int spr__load_model(spr__args *a, spr_scene *s, const spr_load_desc *ld)
{
    spr_error err = {0};
    if (a->cloud_in) { /* arrays handed in: already checked as a file's values are */
        if (ld->balls > 0 || spr__get(a, "stream")) { spr__error(a, "--%s: not with a cloud given as arrays", ld->balls > 0 ? "balls" : "stream"); return -1; }
        s->cloud = *a->cloud_in;
        memset(a->cloud_in, 0, sizeof *a->cloud_in);
        if (ld->opacity > 0.0)
            for (size_t i = 0; i < s->cloud.n; i++) s->cloud.alpha[i] = (float)ld->opacity;
    } else {
        if (spr__scene_check_model(a, s->model)) return -1;
        if (spr__get(a, "stream")) return stream_model(a, s, ld, s->stream_keep);
        double t0 = spr_now_ms();
        if (spr_load(s->model, ld, &s->cloud, &err)) {
            spr__error(a, "%s", err.msg);
            if (a->sink) a->sink->code = err.code; /* a library call keeps the reader's code */
            return -1;
        }
        s->load_ms = spr_now_ms() - t0;
    }
    s->cam_given = s->cam;
    spr_cloud_bounds(&s->cloud, &s->bounds);
    spr_camera_frame(&s->cam, &s->bounds);
    return 0;
}

int spr__scene_move_camera(spr__args *a, spr_scene *s, const spr_pinhole *p, int w, int h)
{
    spr_camera_desc c = s->cam_given;
    spr_view v;
    spr_error err = {0};
    spr__camera_pinhole_sized(&c, p, w, h, spr__get(a, "size") != NULL);
    spr_camera_frame(&c, &s->bounds);
    if (spr_view_make(&c, &v, &err)) { spr__error(a, "%s", err.msg); return -1; }
    s->cam = c, s->view = v;
    return 0;
}

int spr__scene_setup(spr__args *a, spr_scene *s, spr_render_desc *rd, int allow_all)
{
    spr__scene_plan p;
    spr_error err = {0};
    if (spr__scene_opts(a, s, rd, &p, allow_all)) return -1;
    const unsigned uses = p.uses;
    spr_grouping_desc *gd = &p.gd;
    if (p.env) { /* a built-in cube map or six PNG faces, before the model (the cheaper failure first) */
        const int builtin = !strcmp(p.env, "sky") || !strcmp(p.env, "checker");
        if ((builtin ? spr_envmap_builtin(p.env, p.env_size, &s->env, &err) : spr_envmap_load(p.env, &s->env, &err))) {
            spr__error(a, "--env: %s", err.msg);
            return -1;
        }
        rd->shade.env = &s->env;
    }
    if (spr__load_model(a, s, &p.ld)) return -1;
    if (spr_view_make(&s->cam, &s->view, &err)) { spr__error(a, "%s", err.msg); return -1; }
    int32_t *axes = NULL;
    if ((uses & SPR_USES_ORDER) && rd->order == SPR_ORDER_BSP && !p.stream) { /* the tree of [ZP] §5.2.1, once for every frame */
        if (spr_bsp_build(&s->cloud, &s->bsp, &err)) { spr__error(a, "%s", err.msg); return -1; }
        rd->bsp = &s->bsp;
        if ((uses & SPR_USES_GROUPS) && gd->method == SPR_GROUP_HASH && gd->hash.axis == SPR_HASH_AXIS_BSP) { /* hash's axes: the same tree */
            if (!(axes = malloc(s->cloud.n * sizeof *axes))) { spr__error(a, "out of memory for %zu hash axes", s->cloud.n); return -1; }
            spr_hash_axes_of_bsp(&s->bsp, axes);
            gd->hash.axes = axes;
        }
    }
    if (uses & SPR_USES_GROUPS) {
        if (a->camera_all && gd->method == SPR_GROUP_HASH && gd->hash.mode == 3) {
            spr__error(a, "--camera all: hash mode 3's groups depend on the eye (--hash-near); check the views one by one with --camera ID");
            return -1;
        }
        gd->progress = spr__progress(p.quiet);
        int rc = spr__make_groups(a, s, gd, p.hash_near);
        free(axes);
        if (rc) return -1;
        rd->groups = &s->g.groups;
    }
    if (p.stream) { /* grouped: only the chunks are held from here on */
        size_t n = s->cloud.n;
        unsigned fl = s->cloud.flags;
        spr_cloud_free(&s->cloud);
        s->cloud.n = n;
        s->cloud.flags = fl;
        rd->source = &s->src;
    }
    if (uses & SPR_USES_RECTS) {
        spr_progress pg = spr__progress(p.quiet);
        if (spr__domain_prims(a, s->model, &s->cloud, &s->dom, s->threads, &pg, &s->rects, &s->prims)) return -1;
        rd->rects = &s->rects;
    }
    if (p.save && spr__scene_save(a, s, rd, p.save, p.save_matrices)) return -1;
    return 0;
}

int spr__gl_opts(spr__args *a, spr_gl_desc *d)
{
    spr_gl_defaults(d);
    if (spr__get_int(a, "gl-device", &d->device, 0, 64) < 0) return -1;
    const char *v = spr__get(a, "gl-driver");
    if (v && spr_gl_driver_parse(v, &d->driver)) {
        spr__error(a, "--gl-driver: '%s' is not a GL driver here (%s)", v, spr_gl_driver_names());
        return -1;
    }
    spr_error err = {0};
    if (spr_gl_desc_check(d, &err)) { /* before any loading: the same rule spr_gl_create applies */
        spr__error(a, "%s", err.msg);
        return -1;
    }
    return 0;
}

spr_backend *spr__backend(spr__args *a, const char *name, int threads, const spr_gl_desc *gl)
{
    spr_error err = {0};
    spr_backend *b;
    if (!strcmp(name, "gl")) {
        b = spr_gl_create(gl, &err);
    } else {
        b = spr_swrast_create(threads, &err);
    }
    if (!b) {
        spr__error(a, "%s", err.msg);
        if (a->sink) a->sink->code = err.code; /* a library call keeps SPR_E_NO_DEVICE */
    }
    return b;
}

spr_result spr_scene_load(const char *path, int threads, spr_scene *s, spr_render_desc *rd, spr_error *err)
{
    static const spr__opt opts[] = {SPR__SCENE_OPTS, {NULL, NULL, NULL}};
    spr__args a;
    char thr[16];
    memset(&a, 0, sizeof a);
    memset(s, 0, sizeof *s);
    memset(err, 0, sizeof *err);
    a.cmd = "scene";
    a.opts = opts;
    a.sink = err; /* messages become the error, nothing is printed */
    snprintf(thr, sizeof thr, "%d", threads < 0 ? 0 : threads);
    for (int k = 0; opts[k].name; k++) {
        if (!strcmp(opts[k].name, "quiet")) a.value[k] = "1";
        if (!strcmp(opts[k].name, "threads")) a.value[k] = thr;
    }
    const int bad = spr__scene_read(&a, path) || spr__scene_setup(&a, s, rd, 0);
    spr__scene_forget(&a); /* s keeps no pointer into the option values */
    if (bad) {
        if (!err->code) err->code = SPR_E_ARG;
        return err->code;
    }
    return SPR_OK;
}
