/* cli_render.c — `splatref render`: load, frame, group, render, write. */
#include "cli.h"
#include "spr_image.h"
#include "spr_swrast.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

static const cli_opt render_opts[] = {
    {"model", "PATH|builtin:NAME", "model file (.ply .off .xyz .pwn) or builtin:sphere|torus|octahedron|planes|cube (default builtin:torus)"},
    {"points", "N", "size of a built-in model (default 20000)"},
    {"radius-k", "K", "k of the radius rule r = rho*d_k when the file has no radii (default 8)"},
    {"radius-scale", "RHO", "rho of the radius rule (default 1.0)"},
    {"eye", "X,Y,Z", "camera position (default: frame the model from +z)"},
    {"target", "X,Y,Z", "point looked at (default: model centre)"},
    {"up", "X,Y,Z", "up vector (default 0,1,0)"},
    {"fov", "DEG", "vertical field of view, perspective (default 30)"},
    {"ortho", "HEIGHT", "orthographic camera with this view height"},
    {"near", "N", "near plane (default: tight around the model)"},
    {"far", "F", "far plane (default: tight around the model)"},
    {"size", "WxH", "image size (default 512x512)"},
    {"background", "R,G,B", "background colour in [0,1] (default 0,0,0)"},
    {"algo", "NAME", "pbr2p1 | deferred (default deferred)"},
    {"groups", "METHOD", "deferred grouping: none | mgc | hash (default mgc)"},
    {"groups-file", "F", "read one group per splat (input order) from F"},
    {"groups-out", "F", "write the groups used, one per line"},
    {"c", "C", "MGC overlap relaxation factor in (0,1] (default 1.0)"},
    {"relax", "LIST", "MGC relaxations: coplanar,opposite | coplanar | opposite | none (default both)"},
    {"k", "K", "hash grouping: number of groups (default 8)"},
    {"kernel", "NAME", "gauss | constant | linear | epanechnikov (default gauss)"},
    {"eps", "E", "depth tolerance in world units (default 2 x mean radius)"},
    {"voronoi", NULL, "deferred: Voronoi depth [ZP] Eq. 14"},
    {"lowres-n", "N", "quantisation steps n of the low-precision depth (default from eps)"},
    {"backend", "NAME", "cpu (default)"},
    {"threads", "N", "CPU threads (default: all cores)"},
    {"out", "FILE.png", "8-bit image (default splatref.png)"},
    {"float", "FILE.pfm", "final RGB as little-endian PFM"},
    {"dump", "DIR", "every target plane of every pass as PFM, names sorted in pass order"},
    {"stats", "FILE.json", "model size, K, group sizes, fragments and ms per pass"},
    {"quiet", NULL, "no progress on stderr"},
    {NULL, NULL, NULL}};

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

/* ---- --dump: every plane of every pass ---- */
typedef struct dump_ctx {
    const char *dir;
    int failed;
    spr_error err;
} dump_ctx;

static void dump_hook(void *user, spr_backend *b, const spr_pass_info *info)
{
    dump_ctx *dc = user;
    if (dc->failed) return;
    int W = b->view.width, H = b->view.height;
    float *buf = malloc((size_t)W * H * 4 * sizeof(float));
    if (!buf) { dc->failed = 1; snprintf(dc->err.msg, sizeof dc->err.msg, "out of memory"); return; }
    for (int p = 0; p < SPR_PLANE__COUNT && !dc->failed; p++) {
        if (!info->state && (p == SPR_PLANE_ID || p == SPR_PLANE_COUNT || p == SPR_PLANE_TEST)) continue;
        if (spr_backend_read_plane(b, info->target, (spr_plane)p, buf)) { dc->failed = 1; dc->err = b->err; break; }
        if (p == SPR_PLANE_ID || p == SPR_PLANE_COUNT) {
            uint32_t *u = (uint32_t *)buf;
            for (size_t i = 0; i < (size_t)W * H; i++) buf[i] = u[i] == UINT32_MAX ? -1.0f : (float)u[i];
        }
        /* PFM holds 1 or 3 channels: the colour plane's 4th channel (the
         * weight sum, or coverage after compositing) goes to its own file. */
        for (int part = 0; part < (p == SPR_PLANE_COLOR ? 2 : 1) && !dc->failed; part++) {
            const char *pname = part ? "weight" : spr_plane_name((spr_plane)p);
            char name[1200];
            if (info->group >= 0)
                snprintf(name, sizeof name, "%s/%03d_%s_k%03d_%s.pfm", dc->dir, info->index, info->name, info->group, pname);
            else
                snprintf(name, sizeof name, "%s/%03d_%s_%s.pfm", dc->dir, info->index, info->name, pname);
            if (part) /* move the 4th channel to the front, one value per pixel */
                for (size_t i = 0; i < (size_t)W * H; i++) buf[i] = buf[4 * i + 3];
            if (spr_write_pfm(name, buf, W, H, part ? 1 : spr_plane_channels((spr_plane)p), &dc->err)) dc->failed = 1;
        }
    }
    free(buf);
}

/* ---- --stats JSON ---- */
typedef struct stats_ref {
    const cli_scene *s;
    const spr_render_desc *rd;
    const spr_render_result *res;
    double total_ms, load_ms, group_ms;
    size_t covered;
} stats_ref;

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"' || *s == '\\') fputc('\\', f);
        if ((unsigned char)*s < 0x20) { fprintf(f, "\\u%04x", *s); continue; }
        fputc(*s, f);
    }
    fputc('"', f);
}

static int stats_body(FILE *f, const void *user)
{
    const stats_ref *st = user;
    const cli_scene *s = st->s;
    fprintf(f, "{\n  \"model\": ");
    json_str(f, s->model);
    fprintf(f, ",\n  \"splats\": %zu,\n  \"width\": %d,\n  \"height\": %d,\n", s->cloud.n, s->view.width, s->view.height);
    fprintf(f, "  \"algo\": \"%s\",\n  \"kernel\": \"%s\",\n  \"voronoi\": %s,\n", spr_algo_name(st->rd->algo),
            spr_kernel_name(st->rd->kernel), st->rd->voronoi ? "true" : "false");
    fprintf(f, "  \"eps_t\": %.9g,\n  \"lowres\": {\"d_min\": %.9g, \"d_max\": %.9g, \"n\": %.9g},\n", st->res->eps_t,
            st->res->lowres.d_min, st->res->lowres.d_max, st->res->lowres.n);
    fprintf(f, "  \"K\": %d,\n  \"grouping\": {\"method\": \"%s\", \"max_degree\": %d, \"avg_degree\": %.4f, \"ms_graph\": %.3f, \"ms_color\": %.3f},\n",
            st->res->K, s->group_method ? s->group_method : "none", s->gstats.max_degree, s->gstats.avg_degree,
            s->gstats.ms_graph, s->gstats.ms_color);
    fprintf(f, "  \"group_sizes\": [");
    for (int k = 0; k < s->groups.K; k++) fprintf(f, "%s%u", k ? ", " : "", s->groups.start[k + 1] - s->groups.start[k]);
    fprintf(f, "],\n  \"passes\": [\n");
    for (int p = 0; p < st->res->n_passes; p++) {
        const spr_pass_record *pr = &st->res->passes[p];
        fprintf(f, "    {\"name\": \"%s\", \"group\": %d, \"splats\": %llu, \"fragments_generated\": %llu, \"fragments_passed\": %llu, \"ms\": %.3f}%s\n",
                pr->name, pr->group, (unsigned long long)pr->stats.splats, (unsigned long long)pr->stats.generated,
                (unsigned long long)pr->stats.passed, pr->ms, p + 1 < st->res->n_passes ? "," : "");
    }
    fprintf(f, "  ],\n  \"covered_pixels\": %zu,\n  \"ms_load\": %.3f,\n  \"ms_grouping\": %.3f,\n  \"ms_render\": %.3f\n}\n",
            st->covered, st->load_ms, st->group_ms, st->total_ms);
    return ferror(f) ? -1 : 0;
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

int cmd_render(int argc, char **argv)
{
    cli_args a;
    int pr = cli_parse(&a, "render", render_opts, "[options]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    int rc = 2;
    cli_scene s;
    memset(&s, 0, sizeof s);
    spr_backend *b = NULL;
    spr_render_result res = {0};
    spr_error err = {0};

    /* Parse and check every option before any work. */
    spr_load_desc ld;
    spr_load_defaults(&ld);
    spr_camera_defaults(&s.cam);
    spr_render_desc rd = {0};
    double c = 1.0, bg[3] = {0, 0, 0};
    int K = 8, threads = 0, quiet = cli_flag(&a, "quiet");
    const char *model = cli_get(&a, "model") ? cli_get(&a, "model") : "builtin:torus";
    const char *method = cli_get(&a, "groups") ? cli_get(&a, "groups") : "mgc";
    const char *kname = cli_get(&a, "kernel"), *aname = cli_get(&a, "algo"), *bname = cli_get(&a, "backend");
    const char *out = cli_get(&a, "out") ? cli_get(&a, "out") : "splatref.png";
    if (cli_get_size(&a, "points", &ld.points, 16, SPR_MAX_SPLATS) < 0 || cli_get_int(&a, "radius-k", &ld.radius_k, 1, 256) < 0 ||
        cli_get_double(&a, "radius-scale", &ld.radius_rho, 1e-6, 1e6) < 0 || cli_get_vec3(&a, "eye", s.cam.eye) < 0 ||
        cli_get_vec3(&a, "target", s.cam.target) < 0 || cli_get_vec3(&a, "up", s.cam.up) < 0 ||
        cli_get_double(&a, "fov", &s.cam.fov_deg, 1e-3, 179.0) < 0 || cli_get_double(&a, "ortho", &s.cam.ortho_height, 1e-12, 1e30) < 0 ||
        cli_get_double(&a, "near", &s.cam.near_plane, 0.0, 1e30) < 0 || cli_get_double(&a, "far", &s.cam.far_plane, 0.0, 1e30) < 0 ||
        cli_get_wh(&a, "size", &s.cam.width, &s.cam.height) < 0 || cli_get_vec3(&a, "background", bg) < 0 ||
        cli_get_double(&a, "c", &c, 1e-6, 1.0) < 0 || cli_get_int(&a, "k", &K, 1, SPR_MAX_GROUPS) < 0 ||
        cli_get_double(&a, "eps", &rd.eps, 1e-30, 1e30) < 0 || cli_get_double(&a, "lowres-n", &rd.lowres_n, 1.0, 16777216.0) < 0 ||
        cli_get_int(&a, "threads", &threads, 0, 1024) < 0)
        goto done;
    for (int k = 0; k < 3; k++) {
        if (bg[k] < 0.0 || bg[k] > 1.0) { cli_error(&a, "--background: components must lie in [0,1]"); goto done; }
        rd.background[k] = (float)bg[k];
    }
    if (cli_get(&a, "ortho")) s.cam.fov_deg = 0.0;
    if (aname && (int)(rd.algo = (spr_algo)spr_algo_from_name(aname)) < 0) { cli_error(&a, "--algo: '%s' is not pbr2p1 or deferred", aname); goto done; }
    if (kname && (int)(rd.kernel = (spr_kernel)spr_kernel_from_name(kname)) < 0) {
        cli_error(&a, "--kernel: '%s' is not gauss, constant, linear or epanechnikov", kname);
        goto done;
    }
    if (bname && strcmp(bname, "cpu")) {
        cli_error(&a, "--backend: '%s' is not available (this build has: cpu)", bname);
        goto done;
    }
    if (strcmp(method, "none") && strcmp(method, "mgc") && strcmp(method, "hash")) {
        cli_error(&a, "--groups: '%s' is not none, mgc or hash", method);
        goto done;
    }
    rd.voronoi = cli_flag(&a, "voronoi");
    ld.threads = threads;
    ld.progress = cli_progress(quiet);

    double t0 = now_ms();
    snprintf(s.model, sizeof s.model, "%s", model);
    if (spr_load(model, &ld, &s.cloud, &err)) { fprintf(stderr, "splatref render: %s\n", err.msg); goto done; }
    double load_ms = now_ms() - t0;
    spr_bounds bd;
    spr_cloud_bounds(&s.cloud, &bd);
    spr_camera_frame(&s.cam, &bd);
    if (spr_view_make(&s.cam, &s.view, &err)) { fprintf(stderr, "splatref render: %s\n", err.msg); goto done; }

    t0 = now_ms();
    if (rd.algo == SPR_ALGO_DEFERRED) {
        const char *gf = cli_get(&a, "groups-file");
        if (gf) {
            s.labels = malloc(s.cloud.n * sizeof(int32_t));
            if (!s.labels) { cli_error(&a, "out of memory"); goto done; }
            s.group_method = "file";
            if (spr_groups_read(gf, s.cloud.n, s.labels, &err) || spr_groups_from_labels(s.labels, s.cloud.n, 0, &s.groups, &err)) {
                fprintf(stderr, "splatref render: %s\n", err.msg);
                goto done;
            }
        } else if (cli_make_groups(&a, &s, method, c, cli_get(&a, "relax"), K, threads, cli_progress(quiet))) {
            goto done;
        }
        rd.groups = &s.groups;
    }
    double group_ms = now_ms() - t0;

    b = spr_swrast_create(threads, &err);
    if (!b) { fprintf(stderr, "splatref render: %s\n", err.msg); goto done; }
    dump_ctx dc = {cli_get(&a, "dump"), 0, {0}};
    if (dc.dir) {
        if (mkdir(dc.dir, 0777) != 0 && errno != EEXIST) { cli_error(&a, "--dump: cannot create %s: %s", dc.dir, strerror(errno)); goto done; }
        rd.hook = dump_hook;
        rd.hook_user = &dc;
    }
    t0 = now_ms();
    if (spr_render(b, &s.view, &s.cloud, &rd, &res, &err)) { fprintf(stderr, "splatref render: %s\n", err.msg); goto done; }
    double render_ms = now_ms() - t0;
    if (dc.failed) { fprintf(stderr, "splatref render: --dump: %s\n", dc.err.msg); goto done; }

    size_t covered = 0, np = (size_t)res.width * res.height;
    for (size_t i = 0; i < np; i++) covered += res.rgba[4 * i + 3] > 0.0f;
    if (spr_write_png(out, res.rgba, res.width, res.height, 4, &err) ||
        (cli_get(&a, "float") && spr_write_pfm(cli_get(&a, "float"), res.rgba, res.width, res.height, 4, &err))) {
        fprintf(stderr, "splatref render: %s\n", err.msg);
        goto done;
    }
    if (cli_get(&a, "groups-out") && s.labels && spr_groups_write(cli_get(&a, "groups-out"), s.labels, s.cloud.n, &err)) {
        fprintf(stderr, "splatref render: %s\n", err.msg);
        goto done;
    }
    if (cli_get(&a, "stats")) {
        stats_ref st = {&s, &rd, &res, render_ms, load_ms, group_ms, covered};
        if (spr__write_atomic(cli_get(&a, "stats"), stats_body, &st, &err)) { fprintf(stderr, "splatref render: %s\n", err.msg); goto done; }
    }
    printf("render: %s, %zu splats, %s%s, K=%d, %dx%d, %zu covered pixels, %.1f ms -> %s\n", model, s.cloud.n,
           spr_algo_name(rd.algo), rd.voronoi && rd.algo == SPR_ALGO_DEFERRED ? "+voronoi" : "", res.K, res.width, res.height,
           covered, render_ms, out);
    rc = 0;
done:
    spr_render_result_free(&res);
    spr_backend_destroy(b);
    cli_scene_free(&s);
    return rc;
}
