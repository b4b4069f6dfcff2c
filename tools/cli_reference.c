/* cli_reference.c — `splatref reference`: the canonical scenes of
 * reference_images/manifest.txt.
 *
 * Manifest lines: NAME HASH OPTIONS...   (HASH = FNV-1a 64 of the final RGBA
 * float image of the CPU reference, OPTIONS = render's scene options).
 * Check (default): the CPU output must hash to HASH and the GL output must
 * equal the CPU output in every plane of every pass; every algorithm of the
 * registry must have at least one scene.  --update: render on
 * the CPU, rewrite the hashes and NAME.png (run deliberately; look at the
 * pictures before committing them).
 */
#include "cli.h"
#include "spr__scene_opts.h"
#include "spr_glbackend.h"
#include "spr_image.h"
#include "spr_parity.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const spr__opt ref_opts[] = {
    {"dir", "DIR", "the reference directory (default reference_images)"},
    {"update", NULL, "re-render on the CPU and rewrite hashes and PNGs"},
    {"only", "NAME", "just this scene"},
    {"gl-device", "N", "GL backend on the N-th EGL device"},
    SPR__BACKEND_OPTS,
    {"threads", "N", "CPU threads (default: all cores)"},
    {"quiet", NULL, "no progress on stderr"},
    {"junit", "F.xml", "also write a JUnit XML report, one test case per scene (checking, not --update)"},
    {NULL, NULL, NULL}};

static const spr__opt scene_opts[] = {SPR__SCENE_OPTS, {NULL, NULL, NULL}};

#define MAX_SCENES 128
typedef struct scene_line {
    char name[64];
    char hash[32];
    char args[1024];
} scene_line;

static int read_manifest(const char *path, scene_line *sl, int *n)
{
    FILE *f = fopen(path, "r");
    if (!f) { fprintf(stderr, "splatref reference: %s: cannot open\n", path); return -1; }
    char line[1200];
    int ln = 0;
    *n = 0;
    while (fgets(line, sizeof line, f)) {
        ln++;
        char *p = line;
        while (*p == ' ') p++;
        if (*p == '#' || *p == '\n' || !*p) continue;
        line[strcspn(line, "\n")] = 0;
        scene_line *s = &sl[*n];
        int used = 0;
        if (*n >= MAX_SCENES || sscanf(p, "%63s %31s %n", s->name, s->hash, &used) != 2) {
            fprintf(stderr, "splatref reference: %s:%d: expected NAME HASH OPTIONS...\n", path, ln);
            fclose(f);
            return -1;
        }
        snprintf(s->args, sizeof s->args, "%s", p + used);
        (*n)++;
    }
    fclose(f);
    return 0;
}

typedef struct manifest_ref { const scene_line *sl; int n; } manifest_ref;

static int write_manifest_body(FILE *f, const void *user)
{
    const manifest_ref *m = user;
    fprintf(f, "# splatref reference scenes: NAME HASH OPTIONS...\n"
               "# HASH = FNV-1a 64 of the CPU reference's final RGBA float image (splatref reference --update)\n");
    for (int i = 0; i < m->n; i++) fprintf(f, "%s %s %s\n", m->sl[i].name, m->sl[i].hash, m->sl[i].args);
    return ferror(f) ? -1 : 0;
}

/* Split OPTIONS into argv (no quoting needed: options never contain spaces). */
static int split(char *args, char **argv, int cap)
{
    int n = 0;
    for (char *t = strtok(args, " \t"); t && n < cap; t = strtok(NULL, " \t")) argv[n++] = t;
    return n;
}

int cmd_reference(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "reference", ref_opts, "[--dir DIR] [--update] [--only NAME]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    const char *dir = spr__get(&a, "dir") ? spr__get(&a, "dir") : "reference_images";
    const char *only = spr__get(&a, "only"), *junit = spr__get(&a, "junit");
    int update = spr__flag(&a, "update"), threads = 0;
    spr_gl_desc gd;
    spr_gl_defaults(&gd);
    if ((!update && spr__gl_opts(&a, &gd) < 0) || spr__get_int(&a, "threads", &threads, 0, 1024) < 0 ||
        (spr__flag(&a, "quiet"), spr__reject_unused(&a)))
        return 2;
    char mpath[1200];
    snprintf(mpath, sizeof mpath, "%s/manifest.txt", dir);
    static scene_line sl[MAX_SCENES];
    int n;
    if (read_manifest(mpath, sl, &n)) return 2;
    spr_backend *cpu = spr__backend(&a, "cpu", threads, NULL), *gl = NULL;
    if (!cpu) return 2;
    const char *gl_reason = NULL;
    spr_error gerr = {0};
    if (!update) {
        gl = spr_gl_create(&gd, &gerr);
        if (!gl) gl_reason = gerr.msg;
        if (!gl && gerr.code != SPR_E_NO_DEVICE) { /* a context exists but the backend does not build: a failure */
            fprintf(stderr, "splatref reference: %s\n", gerr.msg);
            spr_backend_destroy(cpu);
            return 1;
        }
        else printf("reference: GL renderer %s\n", spr_gl_renderer(gl));
    }
    int bad = 0, checked = 0, skipped = 0, per_algo[SPR_ALGO__COUNT] = {0};
    cli_junit *ju = junit && !update ? cli_junit_new("splatref reference") : NULL;
    /* SPLATREF_TEST_SIZE=small (the sanitizer build of .ci/run): the scenes of
     * built-in models only; the data-file scenes are the full-size run's */
    const char *size = getenv("SPLATREF_TEST_SIZE");
    int small = size && !strcmp(size, "small");
    for (int i = 0; i < n && bad < 1000; i++) {
        if (only && strcmp(only, sl[i].name)) continue;
        if (small && strstr(sl[i].args, "--model ") && !strstr(sl[i].args, "--model builtin:")) {
            skipped++;
            cli_junit_add(ju, "splatref.reference", sl[i].name, 0.0, CLI_JUNIT_SKIPPED, "a data file's scene: left to the full-size run", "");
            continue;
        }
        const double t0 = spr_now_ms();
        char args[1024], *sargv[64];
        snprintf(args, sizeof args, "%s", sl[i].args);
        int sargc = split(args, sargv, 62);
        if (spr__flag(&a, "quiet")) sargv[sargc++] = "--quiet";
        spr__args sa;
        spr_scene s;
        spr_render_desc rd;
        char cmd[80];
        snprintf(cmd, sizeof cmd, "reference %.63s", sl[i].name);
        spr_error serr = {0};
        sa.sink = NULL;
        if (spr__parse(&sa, cmd, scene_opts, "", 0, sargc, sargv)) {
            bad++;
            cli_junit_add(ju, "splatref.reference", sl[i].name, 0.0, CLI_JUNIT_ERROR, "the manifest's options do not parse", sl[i].args);
            continue;
        }
        sa.sink = &serr; /* the message goes to the terminal and to the report */
        if (spr__scene_setup(&sa, &s, &rd, 0)) {
            fprintf(stderr, "splatref %s: %s\n", cmd, serr.msg);
            bad++;
            cli_junit_add(ju, "splatref.reference", sl[i].name, (spr_now_ms() - t0) / 1000.0, CLI_JUNIT_ERROR, serr.msg, serr.msg);
            continue;
        }
        spr_error err = {0};
        spr_render_result res;
        if (spr_render(cpu, &s.view, &s.cloud, &rd, &res, &err)) {
            fprintf(stderr, "splatref reference: %s: %s\n", sl[i].name, err.msg);
            cli_junit_add(ju, "splatref.reference", sl[i].name, (spr_now_ms() - t0) / 1000.0, CLI_JUNIT_ERROR, err.msg, err.msg);
            spr_scene_free(&s);
            bad++;
            continue;
        }
        char hash[32], png[1200];
        snprintf(hash, sizeof hash, "%016llx",
                 (unsigned long long)spr_hash64(res.rgba, (size_t)res.width * res.height * 4 * sizeof(float)));
        if (update) {
            snprintf(sl[i].hash, sizeof sl[i].hash, "%s", hash);
            snprintf(png, sizeof png, "%.1000s/%.63s.png", dir, sl[i].name);
            if (spr_write_png(png, res.rgba, res.width, res.height, 4, &err)) { fprintf(stderr, "splatref reference: %s\n", err.msg); bad++; }
            printf("reference %-28s %s  updated %s\n", sl[i].name, hash, png);
        } else {
            int cpu_ok = !strcmp(hash, sl[i].hash), gl_ok = 1, gl_err = 0;
            char gl_verdict[200] = "gl skipped";
            cli_text tx;
            FILE *out = cli_text_begin(&tx);
            if (gl) {
                spr_parity_report rep;
                if (spr_parity_run(cpu, gl, &s.view, &s.cloud, &rd, &rd, NULL, sl[i].name, &rep, &err)) {
                    snprintf(gl_verdict, sizeof gl_verdict, "gl failed: %.150s", err.msg);
                    bad++;
                    gl_err = 1;
                } else {
                    gl_ok = spr_parity_exact(&rep);
                    snprintf(gl_verdict, sizeof gl_verdict, "gl %d/%d planes bit-exact, max ulp %llu", rep.exact_planes, rep.n_planes,
                             (unsigned long long)rep.max_ulp);
                    if (!gl_ok) { bad++; cli_parity_summary(out, spr_algo_name(rd.algo), &rep); }
                    spr_parity_report_free(&rep);
                }
            }
            fprintf(out, "reference %-28s cpu %s (%s)  %s\n", sl[i].name, cpu_ok ? "matches" : "DIFFERS", hash, gl_verdict);
            const char *text = cli_text_end(&tx);
            char msg[320];
            snprintf(msg, sizeof msg, "%s%s%s", cpu_ok ? "" : "the CPU image's hash differs from the manifest's",
                     !cpu_ok && (!gl_ok || gl_err) ? "; " : "", gl_err || !gl_ok ? gl_verdict : "");
            cli_junit_add(ju, "splatref.reference", sl[i].name, (spr_now_ms() - t0) / 1000.0,
                          gl_err ? CLI_JUNIT_ERROR : cpu_ok && gl_ok ? CLI_JUNIT_PASS : CLI_JUNIT_FAILURE, msg, text);
            cli_text_free(&tx);
            bad += !cpu_ok;
        }
        checked++;
        per_algo[rd.algo]++;
        spr_render_result_free(&res);
        spr_scene_free(&s);
    }
    if (update && !bad) {
        spr_error err = {0};
        manifest_ref m = {sl, n};
        if (spr__write_atomic(mpath, write_manifest_body, &m, &err)) { fprintf(stderr, "splatref reference: %s\n", err.msg); bad++; }
    }
    spr_backend_destroy(cpu);
    spr_backend_destroy(gl);
    /* every algorithm of the registry has a canonical scene: a new row needs a reference image */
    printf("reference: scenes per algorithm:");
    for (int al = 0; al < SPR_ALGO__COUNT; al++) printf(" %s %d", spr_algo_name((spr_algo)al), per_algo[al]);
    printf("\n");
    for (int al = 0; al < SPR_ALGO__COUNT && !only && !small; al++)
        if (!per_algo[al]) {
            char line[1400];
            snprintf(line, sizeof line, "reference: algorithm %s has no scene in %s\n", spr_algo_name((spr_algo)al), mpath);
            fputs(line, stdout);
            cli_junit_add(ju, "splatref.reference", spr_algo_name((spr_algo)al), 0.0, CLI_JUNIT_FAILURE, "no canonical scene", line);
            bad++;
        }
    if (skipped) printf("reference: %d scenes of data files left to the full-size run (SPLATREF_TEST_SIZE=small)\n", skipped);
    printf("reference: %d scenes, %d failed%s%s\n", checked, bad, gl_reason ? "; GL skipped: " : "", gl_reason ? gl_reason : "");
    const int jrc = cli_junit_write(&a, ju, junit);
    cli_junit_free(ju);
    if (jrc) return 2;
    if (bad) return 1;
    const char *req = getenv("SPLATREF_REQUIRE_GL");
    if (gl_reason && !update && req && *req && strcmp(req, "0")) return 1; /* CI: GL must run */
    return gl_reason && !update ? 77 : 0;
}
