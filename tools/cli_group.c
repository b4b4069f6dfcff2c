/* cli_group.c — `splatref group`: grouping alone, with the statistics of
 * [ZP] Tables 1–3 (K, degrees, overlap factor, cost L, duplication, time). */
#include "spr_util.h"
#include "cli.h"
#include "spr__scene_opts.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const spr__opt group_opts[] = {
    SPR__MODEL_OPTS,
    {"method", "M", "mgc | wgc | hash | none (as render's --groups; default mgc)"},
    SPR__GROUP_OPTS,
    {"eye", "X,Y,Z", "hash mode 3: the eye collisions are measured from (default: render's framing)"},
    {"out", "FILE", "memberships, one line each: splat_index group"},
    {"stats", "FILE.json", "K, group sizes, degrees, overlap factor, cost L, duplication ratio, ms per phase"},
    {NULL, NULL, NULL}};

typedef struct group_report {
    const spr_scene *s;
    double overlap_factor, cost, ms_metrics;
    int max_degree;
    double avg_degree;
} group_report;

static cJSON *stats_json(const group_report *r)
{
    const spr_scene *s = r->s;
    const spr_group_stats *st = &s->g.stats;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "model", s->model);
    cJSON_AddNumberToObject(o, "splats", (double)s->cloud.n);
    cJSON_AddStringToObject(o, "method", s->group_method);
    cJSON_AddNumberToObject(o, "K", s->g.groups.K);
    cJSON_AddItemToObject(o, "group_sizes", cli_json_group_sizes(&s->g.groups));
    cJSON_AddNumberToObject(o, "memberships", s->g.groups.start[s->g.groups.K]);
    cJSON_AddNumberToObject(o, "duplication_ratio", s->g.dup_ratio);
    cJSON_AddNumberToObject(o, "max_degree", r->max_degree);
    cJSON_AddNumberToObject(o, "avg_degree", r->avg_degree);
    cJSON_AddNumberToObject(o, "average_overlap_factor", r->overlap_factor);
    cJSON_AddNumberToObject(o, "cost_L", r->cost);
    cJSON_AddNumberToObject(o, "cost_L_before_optimisation", st->cost_before);
    cJSON_AddNumberToObject(o, "cost_L_after_optimisation", st->cost_after);
    cJSON_AddNumberToObject(o, "optimisation_pops", (double)st->pops);
    cJSON_AddNumberToObject(o, "hash_displaced", (double)st->displaced);
    cJSON_AddNumberToObject(o, "radius_scale_capped_groups", s->g.capped_groups);
    cJSON *rs = cJSON_AddArrayToObject(o, "radius_scale");
    for (int k = 0; s->g.groups.radius_scale && k < s->g.groups.K; k++) cJSON_AddItemToArray(rs, cJSON_CreateNumber(s->g.groups.radius_scale[k]));
    cJSON *ms = cJSON_AddObjectToObject(o, "ms");
    cJSON_AddNumberToObject(ms, "neighbour_graph", st->ms_graph);
    cJSON_AddNumberToObject(ms, "colouring", st->ms_color);
    cJSON_AddNumberToObject(ms, "optimisation", st->ms_optimise);
    cJSON_AddNumberToObject(ms, "extension", s->g.ms_extend);
    cJSON_AddNumberToObject(ms, "total_grouping", s->g.ms_grouping);
    cJSON_AddNumberToObject(ms, "metrics", r->ms_metrics);
    return o;
}

int cmd_group(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "group", group_opts, "--model M --method mgc|wgc|hash [options] --out groups.txt --stats F.json", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    spr_scene s;
    memset(&s, 0, sizeof s);
    int rc = 2;
    spr_grouping_desc gd;
    const char *hash_near = NULL;
    spr_load_desc ld;
    spr_camera_defaults(&s.cam);
    if (spr__model_opts(&a, &s, &ld) || spr__parse_group_opts(&a, "method", &gd, &hash_near) ||
        (hash_near && spr__get_vec3(&a, "eye", s.cam.eye) < 0) ||
        (spr__get(&a, "out"), spr__get(&a, "stats"), spr__get(&a, "quiet"), spr__reject_unused(&a)))
        goto done;
    if (gd.method == SPR_GROUP_FILE) { spr__error(&a, "--groups-file: nothing to group"); goto done; }
    s.cam.have_eye = hash_near && spr__get(&a, "eye");
    gd.keep_graph = 1; /* WGC's overlap graph serves the metrics below */
    gd.progress = ld.progress;
    if (spr__load_model(&a, &s, &ld)) goto done; /* framing gives hash mode 3 its eye when none is given */
    if (spr__make_groups(&a, &s, &gd, hash_near)) goto done;
    /* metrics on the overlap graph (|p_i − p_j| < r_i + r_j, areas A_ij) */
    group_report rep = {&s, 0, 0, 0, 0, 0};
    double t0 = spr_now_ms();
    spr_overlap_graph og = s.g.graph; /* WGC's own graph when it built one (same ε) */
    memset(&s.g.graph, 0, sizeof s.g.graph);
    spr_error err = {0};
    spr_progress prog = spr__progress(spr__flag(&a, "quiet"));
    if (!og.g.start && spr_overlap_graph_build(&s.cloud, spr_cloud_default_eps(&s.cloud), s.threads, &prog, &og, &err)) {
        fprintf(stderr, "splatref group: %s\n", err.msg);
        goto done;
    }
    float *w = spr_wgc_weights(&s.cloud, &og);
    if (!w) { spr_overlap_graph_free(&og); spr__error(&a, "out of memory"); goto done; }
    rep.overlap_factor = spr_overlap_factor(&s.cloud, &og.g, s.g.labels);
    rep.cost = spr_wgc_cost(&og, w, s.g.labels);
    if (!strcmp(s.group_method, "mgc")) {
        rep.max_degree = s.g.stats.max_degree; /* of the conflict graph (Eq. 5 with relaxations) */
        rep.avg_degree = s.g.stats.avg_degree;
    } else {
        for (size_t i = 0; i < s.cloud.n; i++) {
            int deg = (int)(og.g.start[i + 1] - og.g.start[i]);
            if (deg > rep.max_degree) rep.max_degree = deg;
        }
        rep.avg_degree = s.cloud.n ? (double)og.g.start[s.cloud.n] / (double)s.cloud.n : 0.0;
    }
    free(w);
    spr_overlap_graph_free(&og);
    rep.ms_metrics = spr_now_ms() - t0;
    if (spr__get(&a, "out") && spr_groups_write_memberships(spr__get(&a, "out"), &s.g.groups, &err)) {
        fprintf(stderr, "splatref group: %s\n", err.msg);
        goto done;
    }
    if (spr__get(&a, "stats") && spr__write_json(&a, spr__get(&a, "stats"), stats_json(&rep))) goto done;
    printf("group: %s, %zu splats, %s: K=%d, max degree %d, avg degree %.2f, overlap factor %.4f, cost L %.6g",
           s.model, s.cloud.n, s.group_method, s.g.groups.K, rep.max_degree, rep.avg_degree, rep.overlap_factor, rep.cost);
    if (!strcmp(s.group_method, "wgc")) printf(" (before optimisation %.6g)", s.g.stats.cost_before);
    if (s.g.dup_ratio > 0.0) printf(", duplication +%.1f%%", 100.0 * s.g.dup_ratio);
    if (s.g.groups.radius_scale) printf(", radius scale k0 %.4f", s.g.groups.radius_scale[0]);
    if (s.g.capped_groups) printf(" (%d group(s) stopped at the Eq. 13 cap)", s.g.capped_groups);
    printf(", %.0f ms\n", s.g.ms_grouping + s.g.ms_extend);
    rc = 0;
done:
    spr_scene_free(&s);
    return rc;
}
