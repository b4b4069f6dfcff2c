/* cli_render.c — `splatref render`: load, frame, group, render, write. */
#include "spr_util.h"
#include "cli.h"
#include "spr__scene_opts.h"
#include "spr_image.h"
#include "spr_swrast.h"
#include "spr_trace.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

static const spr__opt render_opts[] = {
    SPR__SCENE_OPTS,
    SPR__STREAM_OPTS,
    {"groups-out", "F", "write the groups used, one per line"},
    {"out", "FILE.png", "8-bit image (default splatref.png)"},
    {"float", "FILE.pfm", "final RGB as little-endian PFM"},
    {"dump", "DIR", "every target plane of every pass as PFM, names sorted in pass order"},
    {"stats", "FILE.json", "model size, K, group sizes, fragments and ms per pass"},
    {"backend", "NAME", "cpu (default) | gl"},
    {"gl-device", "N", "GL backend: the N-th EGL device instead of the surfaceless platform"},
    {"trace", "FILE", "every backend call of the frame, one line each (views, targets, clears, draws with their state and fragment counts, composites, reads)"},
    {NULL, NULL, NULL}};

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
        if (!(spr_backend_target_planes(b, info->target) & SPR_PLANE_BIT(p))) continue;
        if (!info->state && p == SPR_PLANE_TEST) continue; /* a composite's test plane repeats its depth */
        if (spr_backend_read_plane_f(b, info->target, (spr_plane)p, buf)) { dc->failed = 1; dc->err = b->err; break; }
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
    const spr_scene *s;
    const spr_render_desc *rd;
    const spr_render_result *res;
    double total_ms, load_ms, group_ms;
    size_t covered;
} stats_ref;

static cJSON *stats_json(const stats_ref *st)
{
    const spr_scene *s = st->s;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "model", s->model);
    cJSON_AddNumberToObject(o, "splats", (double)s->cloud.n);
    cJSON_AddNumberToObject(o, "width", s->view.width);
    cJSON_AddNumberToObject(o, "height", s->view.height);
    cJSON_AddStringToObject(o, "algo", spr_algo_name(st->rd->algo));
    cJSON_AddStringToObject(o, "kernel", spr_kernel_name(st->rd->kernel));
    cJSON_AddBoolToObject(o, "voronoi", st->rd->voronoi);
    cJSON_AddNumberToObject(o, "eps_t", st->res->eps_t);
    cJSON *lr = cJSON_AddObjectToObject(o, "lowres");
    cJSON_AddNumberToObject(lr, "d_min", st->res->lowres.d_min);
    cJSON_AddNumberToObject(lr, "d_max", st->res->lowres.d_max);
    cJSON_AddNumberToObject(lr, "n", st->res->lowres.n);
    cJSON_AddNumberToObject(o, "K", st->res->K);
    cJSON *gr = cJSON_AddObjectToObject(o, "grouping");
    cJSON_AddStringToObject(gr, "method", s->group_method ? s->group_method : "none");
    cJSON_AddNumberToObject(gr, "max_degree", s->g.stats.max_degree);
    cJSON_AddNumberToObject(gr, "avg_degree", s->g.stats.avg_degree);
    cJSON_AddNumberToObject(gr, "ms_graph", s->g.stats.ms_graph);
    cJSON_AddNumberToObject(gr, "ms_color", s->g.stats.ms_color);
    cJSON_AddItemToObject(o, "group_sizes", cli_json_group_sizes(&s->g.groups));
    cJSON *passes = cJSON_AddArrayToObject(o, "passes");
    for (int p = 0; p < st->res->n_passes; p++) {
        const spr_pass_record *pr = &st->res->passes[p];
        cJSON *e = cJSON_CreateObject();
        cJSON_AddStringToObject(e, "name", pr->name);
        cJSON_AddNumberToObject(e, "group", pr->group);
        cJSON_AddNumberToObject(e, "splats", (double)pr->stats.splats);
        cJSON_AddNumberToObject(e, "fragments_generated", (double)pr->stats.generated);
        cJSON_AddNumberToObject(e, "fragments_passed", (double)pr->stats.passed);
        cJSON_AddNumberToObject(e, "ms", pr->ms);
        cJSON_AddItemToArray(passes, e);
    }
    cJSON_AddNumberToObject(o, "covered_pixels", (double)st->covered);
    cJSON_AddNumberToObject(o, "ms_load", st->load_ms);
    cJSON_AddNumberToObject(o, "ms_grouping", st->group_ms);
    cJSON_AddNumberToObject(o, "ms_render", st->total_ms);
    cJSON_AddBoolToObject(o, "streamed", s->src.read != NULL);
    if (s->src.read) {
        cJSON_AddNumberToObject(o, "chunk", (double)s->src.chunk);
    } else { /* the floor of any per-splat phase (`splatref bench`), on the render's threads */
        double sum;
        cJSON_AddNumberToObject(o, "ms_stream_pass", spr_cloud_stream_ms(&s->cloud, s->threads, &sum));
        cJSON_AddNumberToObject(o, "stream_checksum", sum);
    }
    return o;
}

typedef struct text_ref { const char *s; size_t n; } text_ref;
static int write_text(FILE *f, const void *user)
{
    const text_ref *t = user;
    return fwrite(t->s, 1, t->n, f) == t->n ? 0 : -1;
}

int cmd_render(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "render", render_opts, "[options]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    int rc = 2;
    char *trace_buf = NULL;
    size_t trace_len = 0;
    FILE *trace_f = NULL;
    char dump_tmp[1200] = "";
    int dump_open = 0;
    spr_scene s;
    spr_backend *b = NULL;
    spr_render_result res = {0};
    spr_error err = {0};
    spr_render_desc rd;
    const char *out = spr__get(&a, "out") ? spr__get(&a, "out") : "splatref.png";
    const char *bname = spr__get(&a, "backend") ? spr__get(&a, "backend") : "cpu";
    spr_gl_desc gd;
    spr_gl_defaults(&gd);
    if (strcmp(bname, "cpu") && strcmp(bname, "gl")) { spr__error(&a, "--backend: '%s' is not cpu or gl", bname); return 2; }
    if (!strcmp(bname, "gl") && spr__gl_opts(&a, &gd) < 0) return 2;
    const char *trace_out = spr__get(&a, "trace"), *dump_dir = spr__get(&a, "dump"), *groups_out = spr__get(&a, "groups-out"), *float_out = spr__get(&a, "float"), *stats_out = spr__get(&a, "stats");
    if (spr__scene_setup(&a, &s, &rd, 0)) goto done;
    if (groups_out && !rd.groups) { spr__error(&a, "--groups-out: %s uses no groups", spr_algo_name(rd.algo)); goto done; }
    if (!(b = spr__backend(&a, bname, s.threads, &gd))) goto done;
    if (trace_out) { /* the trace backend in front of the real one; written out at the end */
        spr_backend *tb = (trace_f = open_memstream(&trace_buf, &trace_len)) ? spr_trace_create(b, trace_f, &err) : NULL;
        if (!tb) { spr__error(&a, "--trace: %s", trace_f ? err.msg : "out of memory"); goto done; }
        b = tb;
    }
    dump_ctx dc = {dump_tmp, 0, {0}};
    if (dump_dir) {
        if (cli_outdir_begin(&a, "dump", dump_dir, dump_tmp, sizeof dump_tmp)) goto done;
        dump_open = 1;
        rd.hook = dump_hook;
        rd.hook_user = &dc;
    }
    double t0 = spr_now_ms();
    if (spr_render(b, &s.view, &s.cloud, &rd, &res, &err)) { fprintf(stderr, "splatref render: %s\n", err.msg); goto done; }
    double render_ms = spr_now_ms() - t0;
    if (dc.failed) { fprintf(stderr, "splatref render: --dump: %s\n", dc.err.msg); goto done; }

    size_t covered = 0, np = (size_t)res.width * res.height;
    for (size_t i = 0; i < np; i++) covered += res.rgba[4 * i + 3] > 0.0f;
    if (spr_write_png(out, res.rgba, res.width, res.height, 4, &err) ||
        (float_out && spr_write_pfm(float_out, res.rgba, res.width, res.height, 4, &err))) {
        fprintf(stderr, "splatref render: %s\n", err.msg);
        goto done;
    }
    /* one group per splat, or memberships when duplication put splats in several groups */
    if (groups_out &&
        (s.g.groups.start[s.g.groups.K] != s.cloud.n ? spr_groups_write_memberships(groups_out, &s.g.groups, &err)
                                                     : spr_groups_write(groups_out, s.g.labels, s.cloud.n, &err))) {
        fprintf(stderr, "splatref render: %s\n", err.msg);
        goto done;
    }
    if (trace_f) {
        fclose(trace_f);
        trace_f = NULL;
        text_ref tx = {trace_buf, trace_len};
        if (spr__write_atomic(trace_out, write_text, &tx, &err)) { fprintf(stderr, "splatref render: %s\n", err.msg); goto done; }
    }
    if (stats_out) {
        stats_ref st = {&s, &rd, &res, render_ms, s.load_ms, s.g.ms_grouping + s.g.ms_extend, covered};
        if (spr__write_json(&a, stats_out, stats_json(&st))) goto done;
    }
    printf("render: %s, %zu splats, %s%s, K=%d, %dx%d, %s backend, %zu covered pixels, %.1f ms -> %s\n", s.model, s.cloud.n,
           spr_algo_name(rd.algo), rd.voronoi && rd.algo == SPR_ALGO_DEFERRED ? "+voronoi" : "", res.K, res.width, res.height,
           b->name, covered, render_ms, out);
    rc = 0;
done:
    if (dump_open && cli_outdir_end(&a, "dump", dump_tmp, dump_dir, rc == 0)) rc = 2; /* all planes, or none */
    if (trace_f) fclose(trace_f);
    free(trace_buf);
    spr_render_result_free(&res);
    spr_backend_destroy(b);
    spr_scene_free(&s);
    return rc;
}
