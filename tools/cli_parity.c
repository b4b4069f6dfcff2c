/* cli_parity.c — `splatref parity`: the same scene on the CPU reference and
 * the GL backend, every plane of every pass compared (PARITY.md). */
#include "cli.h"
#include "spr__scene_opts.h"
#include "spr_glbackend.h"
#include "spr_image.h"
#include "spr_parity.h"
#include "cli_grad.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const spr__opt parity_opts[] = {
    SPR__SCENE_OPTS,
    SPR__STREAM_OPTS,
    {"gl-device", "N", "GL backend on the N-th EGL device instead of the surfaceless platform"},
    {"report", "DIR", "write report.json and a diff heatmap PNG per differing plane"},
    {"gl-eps", "E", "use this eps for the GL side only (a deliberate perturbation, to see a report)"},
    {"random", "N", "instead of one scene: N generated adversarial scenes, every algorithm; mismatches saved (and minimised) in --report DIR (default parity-random)"},
    {"seed", "S", "--random: the seed of the scene generator (default 1)"},
    {"first", "I", "--random: start at scene I of the seed (scene i of a seed is always the same scene; default 0)"},
    {"junit", "F.xml", "also write a JUnit XML report (one test case per plane; --random: per scene and algorithm) for CI servers"},
    CLI_GRAD_OPTS,
    {NULL, NULL, NULL}};

void cli_parity_plane_line(FILE *f, const spr_plane_diff *d)
{
    char where[64] = "";
    if (d->group >= 0) snprintf(where, sizeof where, " k=%d", d->group);
    fprintf(f, "pass %d %s%s plane %s: %zu pixels differ, max %llu ulp (%.3g), first at (%d,%d) ch %d: cpu %.9g gl %.9g", d->pass, d->pass_name,
            where, spr_parity_plane_name(d->plane), d->differing_pixels, (unsigned long long)d->max_ulp, d->max_abs, d->first_x, d->first_y,
            d->first_channel, d->first_ref, d->first_test);
}

/* The summary line of one algorithm, then where it first departs. */
void cli_parity_summary(FILE *f, const char *algo, const spr_parity_report *p)
{
    fprintf(f, "parity %s: %d/%d planes bit-exact, max ulp %llu%s\n", algo, p->exact_planes, p->n_planes,
            (unsigned long long)p->max_ulp, p->stats_mismatches ? ", fragment counts differ" : "");
    int shown = 0;
    for (int i = 0; i < p->n_planes && shown < 3; i++) {
        const spr_plane_diff *d = &p->planes[i];
        if (!d->differing_pixels) continue;
        fprintf(f, "  first differences: ");
        cli_parity_plane_line(f, d);
        fprintf(f, "\n");
        shown++;
    }
    if (p->stats_mismatches) fprintf(f, "  %s\n", p->first_stats_mismatch);
}

/* parity's JUnit cases: one per plane of every pass and the final image,
 * one for the passes' fragment counts. */
static void junit_planes(cli_junit *j, const char *algo, const spr_parity_report *p, double seconds)
{
    char cls[96];
    snprintf(cls, sizeof cls, "splatref.parity.%s", algo);
    for (int i = 0; i < p->n_planes; i++) {
        const spr_plane_diff *d = &p->planes[i];
        char name[160], where[32] = "";
        if (d->group >= 0) snprintf(where, sizeof where, " k=%d", d->group);
        if (d->pass < 0) snprintf(name, sizeof name, "final image");
        else snprintf(name, sizeof name, "pass %d %s%s plane %s", d->pass, d->pass_name, where, spr_parity_plane_name(d->plane));
        if (!d->differing_pixels) { cli_junit_add(j, cls, name, seconds / p->n_planes, CLI_JUNIT_PASS, NULL, NULL); continue; }
        char *text = NULL;
        size_t len = 0;
        FILE *f = open_memstream(&text, &len);
        if (f) cli_parity_plane_line(f, d), fclose(f);
        char msg[96];
        snprintf(msg, sizeof msg, "%zu pixels differ, max %llu ulp", d->differing_pixels, (unsigned long long)d->max_ulp);
        cli_junit_add(j, cls, name, seconds / p->n_planes, CLI_JUNIT_FAILURE, msg, text ? text : "");
        free(text);
    }
    cli_junit_add(j, cls, "fragment counts of every pass", 0.0, p->stats_mismatches ? CLI_JUNIT_FAILURE : CLI_JUNIT_PASS,
                  p->stats_mismatches ? "generated or passed fragments differ" : NULL, p->first_stats_mismatch);
}

int cmd_parity(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "parity", parity_opts, "[scene and algorithm options as for render] [--report DIR]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    int rc = 2, report_open = 0;
    char report_tmp[1200] = "";
    double gl_eps = 0.0;
    spr_gl_desc gd;
    if (spr__gl_opts(&a, &gd) < 0 || spr__get_double(&a, "gl-eps", &gl_eps, 1e-30, 1e30) < 0) return 2;
    const char *dir = spr__get(&a, "report"), *junit = spr__get(&a, "junit");
    if (spr__get(&a, "random")) { /* differential fuzzing: no scene options apply */
        int count = 0, first = 0;
        size_t seed = 1;
        if (spr__get_int(&a, "random", &count, 1, 100000000) < 0 || spr__get_size(&a, "seed", &seed, 0, (size_t)-1) < 0 ||
            spr__get_int(&a, "first", &first, 0, 2000000000) < 0 ||
            (spr__flag(&a, "quiet"), spr__reject_unused(&a)))
            return 2;
        return cli_parity_random(&a, first, count, (uint64_t)seed, dir, &gd, junit);
    }
    spr_scene s;
    spr_render_desc rd;
    spr_backend *cpu = NULL, *gl = NULL;
    spr_parity_report reps[SPR_ALGO__COUNT];
    int nrep = 0;
    cli_junit *ju = junit ? cli_junit_new("splatref parity") : NULL;
    memset(reps, 0, sizeof reps);
    cli_grad_claim(&a);
    cli_grad_inputs gin = {0};
    spr_grad_desc ggd;
    const int grad_given = spr__get(&a, "loss") || spr__get(&a, "dl-dimage");
    if (spr__scene_setup(&a, &s, &rd, 1)) goto done;
    if (dir && cli_outdir_begin(&a, "report", dir, report_tmp, sizeof report_tmp)) goto done;
    report_open = dir != NULL;
    if (!(gl = spr__backend(&a, "gl", s.threads, &gd)) || !(cpu = spr__backend(&a, "cpu", s.threads, NULL))) goto done;
    printf("parity: cpu reference vs gl [%s], %s, %zu splats, %dx%d\n", spr_gl_renderer(gl), s.model, s.cloud.n, s.view.width,
           s.view.height);
    spr__parity_set rr = {dir, &s, spr_gl_renderer(gl), 0, {0}, {0}};
    int all_exact = 1;
    const int tier_b = rd.sampling == SPR_SAMPLE_HARDWARE;
    for (int algo = 0; algo < SPR_ALGO__COUNT; algo++) { /* the registry, in its order */
        if (!s.all_algos && (spr_algo)algo != rd.algo) continue;
        spr_render_desc d = rd, dt;
        d.algo = (spr_algo)algo;
        if (!(spr_algo_info_of(d.algo)->uses & SPR_USES_GROUPS)) d.groups = NULL;
        dt = d;
        if (gl_eps > 0.0) dt.eps = gl_eps;
        spr_error err = {0};
        const double t0 = spr_now_ms();
        if (spr_parity_run(cpu, gl, &s.view, &s.cloud, &d, &dt, dir ? report_tmp : NULL, spr_algo_name(d.algo), &reps[nrep], &err)) {
            fprintf(stderr, "splatref parity: %s\n", err.msg);
            goto done;
        }
        cli_parity_summary(stdout, spr_algo_name(d.algo), &reps[nrep]);
        junit_planes(ju, spr_algo_name(d.algo), &reps[nrep], (spr_now_ms() - t0) / 1000.0);
        if (tier_b && (spr_algo_info_of(d.algo)->uses & SPR_USES_RECTS)) { /* PARITY.md Tier B: GL's texture() filter */
            const spr_parity_report *p = &reps[nrep];
            for (int i = 0; i < p->n_planes; i++)
                if (p->planes[i].plane == SPR_PLANE_FINAL)
                    printf("  tier B (GL texture() bilinear vs explicit bilinear): final image %zu pixels differ, max %llu ulp, "
                           "max abs %.3g, max 8-bit %d LSB\n",
                           p->planes[i].differing_pixels, (unsigned long long)p->planes[i].max_ulp, p->planes[i].max_abs, p->planes[i].max_lsb);
        }
        all_exact &= spr_parity_exact(&reps[nrep]);
        const spr_gauss_profile *gpf = spr_gauss_profile_of(d.algo, d.gauss_profile);
        if (d.algo == SPR_ALGO_GAUSS3D && gpf->grad.trains && !d.gauss_aa && !d.source) { /* SPEC 10.10: the backward pass too */
            if (grad_given ? cli_grad_upstream(&a, s.view.width, s.view.height, &ggd, &gin) : (memset(&ggd, 0, sizeof ggd), ggd.loss = SPR_LOSS_L2, 0)) goto done;
            printf("gauss3d gradients under %s (%s):\n", gpf->name, grad_given ? "the upstream gradient given" : "loss l2 against a black image");
            const int ge = cli_grad_parity(stdout, cpu, gl, &s.view, &s.cloud, &d, &ggd, &err);
            cli_grad_inputs_free(&gin);
            if (ge < 0) {
                fprintf(stderr, "splatref parity: %s\n", err.msg);
                goto done;
            }
            all_exact &= ge;
        }
        rr.algo[nrep] = spr_algo_name(d.algo);
        rr.rep[nrep] = &reps[nrep];
        rr.n = ++nrep;
    }
    if (dir) {
        char path[1200];
        snprintf(path, sizeof path, "%s/report.json", report_tmp);
        if (spr__write_json(&a, path, spr__parity_json(&rr))) goto done;
        printf("report: %s/report.json\n", dir);
    }
    if (ju && cli_junit_write(&a, ju, junit)) goto done;
    printf("verdict: %s\n", all_exact ? "BIT-EXACT (Tier A)" : tier_b ? "DIFFERENT (Tier B mode: bounded error expected, see above)" : "DIFFERENT");
    rc = all_exact ? 0 : 1;
done:
    /* the report of a finished comparison (equal or not) appears whole; a failed run leaves none */
    if (report_open && cli_outdir_end(&a, "report", report_tmp, dir, rc != 2)) rc = 2;
    for (int i = 0; i < nrep; i++) spr_parity_report_free(&reps[i]);
    cli_junit_free(ju);
    spr_backend_destroy(cpu);
    spr_backend_destroy(gl);
    spr_scene_free(&s);
    return rc;
}
