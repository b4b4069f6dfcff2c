/* cli_group.c — `splatref group`: grouping alone, with the statistics of
 * [ZP] Tables 1–3 (K, degrees, overlap factor, cost L, duplication, time). */
#include "spr_util.h"
#include "cli.h"
#include "cli_scene_opts.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const cli_opt group_opts[] = {
    CLI_SCENE_OPTS,
    {"method", "M", "mgc | wgc | hash | none (as render's --groups)"},
    {"out", "FILE", "memberships, one line each: splat_index group"},
    {"stats", "FILE.json", "K, group sizes, degrees, overlap factor, cost L, duplication ratio, ms per phase"},
    {NULL, NULL, NULL}};

typedef struct group_report {
    const cli_scene *s;
    double overlap_factor, cost, ms_metrics;
    int max_degree;
    double avg_degree;
} group_report;

static int stats_body(FILE *f, const void *user)
{
    const group_report *r = user;
    const cli_scene *s = r->s;
    const spr_group_stats *st = &s->gstats;
    fprintf(f, "{\n  \"model\": \"%s\",\n  \"splats\": %zu,\n  \"method\": \"%s\",\n  \"K\": %d,\n  \"group_sizes\": [", s->model,
            s->cloud.n, s->group_method, s->groups.K);
    for (int k = 0; k < s->groups.K; k++) fprintf(f, "%s%u", k ? ", " : "", s->groups.start[k + 1] - s->groups.start[k]);
    fprintf(f, "],\n  \"memberships\": %u,\n  \"duplication_ratio\": %.6f,\n", s->groups.start[s->groups.K], s->dup_ratio);
    fprintf(f, "  \"max_degree\": %d,\n  \"avg_degree\": %.4f,\n  \"average_overlap_factor\": %.6f,\n  \"cost_L\": %.9g,\n",
            r->max_degree, r->avg_degree, r->overlap_factor, r->cost);
    fprintf(f, "  \"cost_L_before_optimisation\": %.9g,\n  \"cost_L_after_optimisation\": %.9g,\n  \"optimisation_pops\": %zu,\n",
            st->cost_before, st->cost_after, st->pops);
    fprintf(f, "  \"hash_displaced\": %zu,\n  \"radius_scale\": [", st->displaced);
    for (int k = 0; s->groups.radius_scale && k < s->groups.K; k++) fprintf(f, "%s%.6f", k ? ", " : "", s->groups.radius_scale[k]);
    fprintf(f, "],\n  \"ms\": {\"neighbour_graph\": %.3f, \"colouring\": %.3f, \"optimisation\": %.3f, \"extension\": %.3f, "
               "\"total_grouping\": %.3f, \"metrics\": %.3f}\n}\n",
            st->ms_graph, st->ms_color, st->ms_optimise, s->ms_extend, s->ms_grouping, r->ms_metrics);
    return ferror(f) ? -1 : 0;
}

int cmd_group(int argc, char **argv)
{
    cli_args a;
    int pr = cli_parse(&a, "group", group_opts, "--model M --method mgc|wgc|hash [options] --out groups.txt --stats F.json", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    cli_scene s;
    spr_render_desc rd;
    int rc = 2;
    if (cli_scene_setup(&a, &s, &rd, 0)) goto done;
    if (rd.algo != SPR_ALGO_DEFERRED) { cli_error(&a, "--algo has no meaning here"); goto done; }
    /* metrics on the overlap graph (|p_i − p_j| < r_i + r_j, areas A_ij) */
    group_report rep = {&s, 0, 0, 0, 0, 0};
    double t0 = spr_now_ms();
    spr_overlap_graph og = s.og; /* WGC's own graph when it built one (same ε) */
    memset(&s.og, 0, sizeof s.og);
    spr_error err = {0};
    spr_progress prog = cli_progress(cli_flag(&a, "quiet"));
    if (!og.g.start && spr_overlap_graph_build(&s.cloud, spr_cloud_default_eps(&s.cloud), s.threads, &prog, &og, &err)) {
        fprintf(stderr, "splatref group: %s\n", err.msg);
        goto done;
    }
    float *w = spr_wgc_weights(&s.cloud, &og);
    if (!w) { spr_overlap_graph_free(&og); cli_error(&a, "out of memory"); goto done; }
    rep.overlap_factor = spr_overlap_factor(&s.cloud, &og.g, s.labels);
    rep.cost = spr_wgc_cost(&og, w, s.labels);
    if (!strcmp(s.group_method, "mgc")) {
        rep.max_degree = s.gstats.max_degree; /* of the conflict graph (Eq. 5 with relaxations) */
        rep.avg_degree = s.gstats.avg_degree;
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
    if ((cli_get(&a, "out") && spr_groups_write_memberships(cli_get(&a, "out"), &s.groups, &err)) ||
        (cli_get(&a, "stats") && spr__write_atomic(cli_get(&a, "stats"), stats_body, &rep, &err))) {
        fprintf(stderr, "splatref group: %s\n", err.msg);
        goto done;
    }
    printf("group: %s, %zu splats, %s: K=%d, max degree %d, avg degree %.2f, overlap factor %.4f, cost L %.6g",
           s.model, s.cloud.n, s.group_method, s.groups.K, rep.max_degree, rep.avg_degree, rep.overlap_factor, rep.cost);
    if (!strcmp(s.group_method, "wgc")) printf(" (before optimisation %.6g)", s.gstats.cost_before);
    if (s.dup_ratio > 0.0) printf(", duplication +%.1f%%", 100.0 * s.dup_ratio);
    if (s.groups.radius_scale) printf(", radius scale k0 %.4f", s.groups.radius_scale[0]);
    printf(", %.0f ms\n", s.ms_grouping + s.ms_extend);
    rc = 0;
done:
    cli_scene_free(&s);
    return rc;
}
