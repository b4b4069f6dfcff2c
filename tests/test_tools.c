/* test_tools.c — the users' tools: scene files, `check` and `compare`,
 * `explain` (pixel history), `step` (the walk-through page).  Every case
 * runs the real `splatref` command. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <dirent.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <cjson/cJSON.h>
#include "spr_image.h"
#include "spr_io.h"
#include "test_util.h"

static char dir[64];
#define in_dir(name) tu_in(dir, (name))
static void setup_dir(void) { tu_tmpdir(dir, "tools"); }

/* `splatref ARG…` (NULL-terminated); exit status, output (stdout and stderr) in out. */
static char out[1 << 16];
/* argv[0 … n−1], then the NULL-terminated ap, then tail (NULL-terminated, or NULL). */
static int run_va(char **argv, int n, va_list ap, const char *const *tail)
{
    const char *s;
    while ((s = va_arg(ap, const char *)) && n < 50) argv[n++] = (char *)s;
    for (; tail && *tail && n < 62; tail++) argv[n++] = (char *)*tail;
    argv[n] = NULL;
    return tu_run(NULL, NULL, 1, argv, out, sizeof out);
}
static int cli(const char *first, ...)
{
    char *argv[64] = {"splatref", (char *)first};
    va_list ap;
    va_start(ap, first);
    int rc = run_va(argv, 2, ap, NULL);
    va_end(ap);
    return rc;
}


static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    ck_assert_ptr_nonnull(f);
    fputs(text, f);
    fclose(f);
}

/* Options that give each algorithm a small scene with what it needs. */
static const char *const *algo_args(const char *algo)
{
    static const char *dom[] = {"--model", "builtin:cube", "--points", "1500", "--level", "1", NULL};
    static const char *grp[] = {"--groups", "wgc", "--k", "3", NULL};
    static const char *none[] = {NULL};
    if (!strncmp(algo, "domain", 6)) return dom;
    if (!strcmp(algo, "deferred") || !strncmp(algo, "transparent", 11)) return grp;
    return none;
}

/* `splatref CMD --algo ALGO --size SIZE --points 3000 EXTRA… --quiet` with
 * the algorithm's scene options (algo_args; they come last, so the domain
 * scenes' --points wins). */
static int algo_run(const char *cmd, const char *algo, const char *size, ...)
{
    char *argv[64] = {"splatref", (char *)cmd, "--algo", (char *)algo, "--size", (char *)size, "--points", "3000", "--quiet"};
    va_list ap;
    va_start(ap, size);
    int rc = run_va(argv, 9, ap, algo_args(algo));
    va_end(ap);
    return rc;
}

START_TEST(scene_round_trip_every_algorithm)
{
    setup_dir();
    for (int al = 0; al < SPR_ALGO__COUNT; al++) {
        const char *name = spr_algo_name((spr_algo)al);
        int rc = algo_run("render", name, "96x80", "--save-scene", in_dir("s.json"), "--float", in_dir("a.pfm"), "--out", in_dir("a.png"), NULL);
        ck_assert_msg(rc == 0, "%s: %s", name, out);
        rc = cli("render", "--scene", in_dir("s.json"), "--float", in_dir("b.pfm"), "--out", in_dir("b.png"), "--quiet", NULL);
        ck_assert_msg(rc == 0, "%s: %s", name, out);
        ck_assert_msg(tu_same_file(in_dir("a.pfm"), in_dir("b.pfm")), "%s: --scene renders other bits than the command line", name);
        /* and with the camera saved as raw matrices */
        rc = cli("render", "--scene", in_dir("s.json"), "--scene-camera", "matrices", "--save-scene", in_dir("m.json"), "--out",
                 in_dir("c.png"), "--quiet", NULL);
        ck_assert_msg(rc == 0, "%s: %s", name, out);
        rc = cli("render", "--scene", in_dir("m.json"), "--float", in_dir("c.pfm"), "--out", in_dir("c.png"), "--quiet", NULL);
        ck_assert_msg(rc == 0, "%s: %s", name, out);
        ck_assert_msg(tu_same_file(in_dir("a.pfm"), in_dir("c.pfm")), "%s: the matrix form renders other bits", name);
        printf("scene round trip: %-20s --save-scene/--scene and the matrix form: identical bits\n", name);
    }
}
END_TEST

/* Matrices written by hand for eye (0,0,6) looking at the origin, up +y,
 * fov 40°, 120×90, near 4, far 8: V translates by −6 along z; P is
 * gluPerspective's. */
START_TEST(scene_hand_matrices_equal_lookat)
{
    setup_dir();
    const double ft = 1.0 / tan(0.5 * 40.0 * M_PI / 180.0), aspect = 120.0 / 90.0, n = 4.0, f = 8.0;
    char json[2048];
    snprintf(json, sizeof json,
             "{\"splatref_scene\": 1,\n \"model\": {\"path\": \"builtin:sphere\", \"points\": 4000},\n"
             " \"camera\": {\"view-matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,-6],[0,0,0,1]],\n"
             "   \"projection-matrix\": [[%.17g,0,0,0],[0,%.17g,0,0],[0,0,%.17g,%.17g],[0,0,-1,0]],\n"
             "   \"size\": [120, 90]},\n \"render\": {\"algo\": \"deferred\", \"voronoi\": true},\n \"grouping\": {\"groups\": \"mgc\"}}\n",
             ft / aspect, ft, (f + n) / (n - f), 2.0 * f * n / (n - f));
    write_file(in_dir("hand.json"), json);
    int rc = cli("render", "--scene", in_dir("hand.json"), "--float", in_dir("m.pfm"), "--out", in_dir("m.png"), "--dump", in_dir("dm"),
                 "--quiet", NULL);
    ck_assert_msg(rc == 0, "%s", out);
    /* near/far were derived from P: the eye form with the same planes */
    rc = cli("render", "--model", "builtin:sphere", "--points", "4000", "--eye", "0,0,6", "--target", "0,0,0", "--fov", "40", "--near", "4",
             "--far", "8", "--size", "120x90", "--algo", "deferred", "--voronoi", "--float", in_dir("e.pfm"), "--out", in_dir("e.png"),
             "--dump", in_dir("de"), "--quiet", NULL);
    ck_assert_msg(rc == 0, "%s", out);
    ck_assert_msg(tu_same_file(in_dir("m.pfm"), in_dir("e.pfm")), "hand matrices and the eye form render other bits");
    /* every plane of every pass too: the test depth (z̃ + ρ/n) depends on near and far */
    DIR *d = opendir(in_dir("de"));
    ck_assert_ptr_nonnull(d);
    struct dirent *e;
    int files = 0;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        char a[400], b[400];
        snprintf(a, sizeof a, "%s/dm/%s", dir, e->d_name);
        snprintf(b, sizeof b, "%s/de/%s", dir, e->d_name);
        ck_assert_msg(tu_same_file(a, b), "plane %s differs between the matrix and the eye form", e->d_name);
        files++;
    }
    closedir(d);
    ck_assert_int_gt(files, 10);
    printf("scene: hand-written matrices (near/far from P) and --eye/--target/--fov: identical bits\n");
}
END_TEST

START_TEST(scene_bad_files)
{
    setup_dir();
    static const struct { const char *text, *expect; } cases[] = {
        {"{\"splatref_scene\": 1, \"render\": {\"algo\": \"deferred\", \"bogus\": 3}}", "unknown key 'render.bogus'"},
        {"{\"splatref_scene\": 1, \"lights\": {}}", "unknown key 'lights'"},
        {"{\"splatref_scene\": 1, \"camera\": {\"eps\": 3}}", "unknown key 'camera.eps'"},
        {"{\"splatref_scene\": 2}", "version 2"},
        {"{\"render\": {}}", "not a splatref scene"},
        {"{\"splatref_scene\": 1,\n \"camera\": {\"size\": [10,}}", ":2:"},
        {"{\"splatref_scene\": 1, \"camera\": {\"size\": \"big\"}}", "bad.json)"},
        {"{\"splatref_scene\": 1, \"camera\": {\"view-matrix\": [[1,0,0,0]]}}", "camera.view-matrix: expected 4 rows"},
        {"{\"splatref_scene\": 1, \"model\": {\"path\": \"" SPR_DATA_DIR "/meshes/bunny00.off\", \"fnv1a64\": \"0123456789abcdef\"}}",
         "changed since the scene was saved"},
        /* issue 25's fuzz_scene: a key or a value holding a newline is shown escaped, the message one line */
        {"{\"splatref_scene\": 1, \"cam\\nera\": {}}", "unknown key 'cam\\nera'"},
        {"{\"splatref_scene\": 1, \"render\": {\"algo\": \"deferred\", \"shade\": \"ph\\nong\"}}", "--shade: 'ph\\nong' is not none"},
        /* an error about options the file gave names the file, whatever follows the option's name */
        {"{\"splatref_scene\": 1, \"render\": {\"algo\": \"gauss3d\"}, \"camera\": {\"intrinsics\": [30, 30, 16, 12], "
         "\"world-to-camera\": [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4]]}}",
         "--intrinsics/--world-to-camera: the rotation is not rigid (|RᵀR − I| reaches 3, det 2; a rotation has 0 and +1) (from "},
        {"{\"splatref_scene\": 1, \"camera\": {\"cameras\": \"none.json\", \"camera\": 1}}", "none.json: cannot open: No such file or directory (from "},
        {"{\"splatref_scene\": 1, \"camera\": {\"camera\": 1}}", "--cameras and --camera go together (from "},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        write_file(in_dir("bad.json"), cases[i].text);
        int rc = cli("render", "--scene", in_dir("bad.json"), "--out", in_dir("bad.png"), "--quiet", NULL);
        printf("scene: bad file %zu: exit %d: %s", i, rc, out);
        ck_assert_msg(rc == 2 && strstr(out, cases[i].expect), "case %zu: expected '%s', got exit %d: %s", i, cases[i].expect, rc, out);
        ck_assert_msg(strchr(out, '\n') == out + strlen(out) - 1, "case %zu: not one line: %s", i, out);
        ck_assert_int_ne(access(in_dir("bad.png"), F_OK), 0);
    }
    /* the backend section: a GL driver that is not one is refused by a command that makes a GL backend, naming the file */
    write_file(in_dir("bad.json"), "{\"splatref_scene\": 1, \"backend\": {\"gl-driver\": \"swiftshader\"}}");
    int rc = cli("parity", "--scene", in_dir("bad.json"), "--report", in_dir("rep"), "--quiet", NULL);
    ck_assert_msg(rc == 2 && strstr(out, "--gl-driver: 'swiftshader' is not a GL driver here (default | llvmpipe | zink) (from ") &&
                      strchr(out, '\n') == out + strlen(out) - 1,
                  "backend.gl-driver: exit %d: %s", rc, out);
    ck_assert_int_ne(access(in_dir("rep"), F_OK), 0);
}
END_TEST

/* ---- check and compare on images made from our own GL output ---- */
static float *read_img(const char *path, int *w, int *h, int *ch)
{
    float *im;
    spr_error err = {0};
    ck_assert_msg(spr_read_image(path, &im, w, h, ch, &err) == SPR_OK, "%s", err.msg);
    return im;
}

START_TEST(check_gl_image_tiers)
{
    setup_dir();
    /* the GL backend's image of a scene with overlapping groups */
    int rc = cli("render", "--model", "builtin:torus", "--points", "6000", "--size", "120x100", "--algo", "deferred", "--voronoi", "--groups",
                 "mgc", "--save-scene", in_dir("s.json"), "--backend", "gl", "--out", in_dir("gl.png"), "--float", in_dir("gl.pfm"), "--quiet",
                 NULL);
    ck_assert_msg(rc == 0, "%s", out);
    for (int f = 0; f < 2; f++) {
        rc = cli("check", "--scene", in_dir("s.json"), "--image", in_dir(f ? "gl.pfm" : "gl.png"), "--out", in_dir("rep"), "--quiet", NULL);
        printf("check: our GL %s: exit %d\n%s", f ? "float image" : "8-bit PNG", rc, out);
        ck_assert_msg(rc == 0 && strstr(out, "verdict: PASS (Tier A)") && strstr(out, " 0 of 12000 pixels differ"), "%s", out);
    }
    /* report files */
    int w, h, ch;
    float *heat = read_img(in_dir("rep/heatmap.png"), &w, &h, &ch);
    ck_assert_int_eq(w, 120);
    free(heat);
    float *sbs = read_img(in_dir("rep/side-by-side.png"), &w, &h, &ch);
    ck_assert_int_eq(w, 3 * 120 + 8);
    free(sbs);
    /* one covered pixel one LSB brighter: the first with a mid-range red */
    float *im = read_img(in_dir("gl.png"), &w, &h, &ch);
    size_t p = 0;
    while (p < (size_t)w * h && !(im[p * ch] > 0.2f && im[p * ch] < 0.8f)) p++;
    ck_assert_uint_lt(p, (size_t)w * h);
    const int px = (int)(p % (size_t)w), py = (int)(p / (size_t)w);
    char at[64], pix[64];
    snprintf(at, sizeof at, "x %d, y %d", px, py);
    snprintf(pix, sizeof pix, "--pixel %d,%d", px, py);
    int v = (int)lrintf(im[p * ch] * 255.0f);
    im[p * ch] = (float)(v + 1) / 255.0f;
    spr_error err = {0};
    ck_assert(spr_write_png(in_dir("lsb.png"), im, w, h, ch, &err) == SPR_OK);
    rc = cli("check", "--scene", in_dir("s.json"), "--image", in_dir("lsb.png"), "--out", in_dir("rep"), "--quiet", NULL);
    printf("check: one pixel +1 LSB, Tier A: exit %d\n%s", rc, out);
    ck_assert_msg(rc == 1 && strstr(out, "1 of 12000 pixels differ, 1 fails") && strstr(out, at) &&
                      strstr(out, "splatref explain --scene") && strstr(out, pix),
                  "%s", out);
    rc = cli("check", "--scene", in_dir("s.json"), "--image", in_dir("lsb.png"), "--lsb", "1", "--out", in_dir("rep"), "--quiet", NULL);
    printf("check: one pixel +1 LSB, --lsb 1: exit %d\n%s", rc, out);
    ck_assert_msg(rc == 0 && strstr(out, "verdict: PASS (Tier B)") && strstr(out, "max 1 LSB"), "%s", out);
    /* the report names it */
    cJSON *rep = tu_read_json(in_dir("rep/report.json"));
    cJSON *first = cJSON_GetObjectItem(rep, "first_differing");
    ck_assert_ptr_nonnull(first);
    ck_assert_int_eq(cJSON_GetObjectItem(first, "x")->valueint, px);
    ck_assert_int_eq(cJSON_GetObjectItem(first, "y")->valueint, py);
    ck_assert_str_eq(cJSON_GetObjectItem(rep, "verdict")->valuestring, "pass");
    cJSON_Delete(rep);
    /* the whole image one pixel to the right */
    free(im);
    im = read_img(in_dir("gl.png"), &w, &h, &ch);
    float *sh = calloc((size_t)w * h * ch, sizeof *sh);
    for (int y = 0; y < h; y++)
        for (int x = 1; x < w; x++)
            for (int c = 0; c < ch; c++) sh[((size_t)y * w + x) * ch + c] = im[((size_t)y * w + x - 1) * ch + c];
    ck_assert(spr_write_png(in_dir("shift.png"), sh, w, h, ch, &err) == SPR_OK);
    rc = cli("check", "--scene", in_dir("s.json"), "--image", in_dir("shift.png"), "--tier", "B", "--out", in_dir("rep"), "--quiet", NULL);
    printf("check: shifted one pixel, Tier B without position tolerance: exit %d\n%s", rc, out);
    ck_assert_msg(rc == 1 && strstr(out, "verdict: FAIL (Tier B)"), "%s", out);
    rc = cli("check", "--scene", in_dir("s.json"), "--image", in_dir("shift.png"), "--position-tolerance", "1", "--out", in_dir("rep"),
             "--quiet", NULL);
    printf("check: shifted one pixel, --position-tolerance 1: exit %d\n%s", rc, out);
    ck_assert_msg(rc == 0 && strstr(out, "verdict: PASS (Tier B)") && !strstr(out, ", 0 pass only within one pixel"), "%s", out);
    /* compare does the same for two images */
    rc = cli("compare", in_dir("gl.png"), in_dir("lsb.png"), NULL);
    ck_assert_msg(rc == 1 && strstr(out, "FAIL (Tier A)"), "%s", out);
    rc = cli("compare", in_dir("gl.png"), in_dir("lsb.png"), "--lsb", "1", NULL);
    ck_assert_msg(rc == 0 && strstr(out, "PASS (Tier B)"), "%s", out);
    rc = cli("compare", in_dir("gl.png"), in_dir("shift.png"), "--position-tolerance", "1", NULL);
    ck_assert_msg(rc == 0 && strstr(out, "PASS (Tier B)"), "%s", out);
    /* sizes and channels that do not match: one line, exit 2 */
    float small[4 * 4 * 3] = {0};
    ck_assert(spr_write_pfm(in_dir("small.pfm"), small, 4, 4, 3, &err) == SPR_OK);
    rc = cli("check", "--scene", in_dir("s.json"), "--image", in_dir("small.pfm"), "--out", in_dir("rep2"), "--quiet", NULL);
    ck_assert_msg(rc == 2 && strstr(out, "is 4x4, the scene renders 120x100") && access(in_dir("rep2"), F_OK) != 0, "%s", out);
    ck_assert(spr_write_pfm(in_dir("grey.pfm"), sh, w, h, 1, &err) == SPR_OK);
    rc = cli("check", "--scene", in_dir("s.json"), "--image", in_dir("grey.pfm"), "--quiet", NULL);
    ck_assert_msg(rc == 2 && strstr(out, "has 1 channel, the reference has 3"), "%s", out);
    free(im);
    free(sh);
}
END_TEST

/* ---- explain: pixel history ---- */
static cJSON *explain_json(const char *scene, int x, int y, const char *backend)
{
    char pix[32];
    snprintf(pix, sizeof pix, "%d,%d", x, y);
    char *argv[] = {"splatref", "explain", "--scene", (char *)scene, "--pixel", pix, "--backend", (char *)backend, "--json", "--quiet", NULL};
    static char big[1 << 22];
    int rc = tu_run(NULL, NULL, 1, argv, big, sizeof big);
    size_t len = strlen(big);
    ck_assert_msg(rc == 0, "explain %s exit %d: %.400s ... %s", pix, rc, big, len > 1500 ? big + len - 1500 : "");
    cJSON *o = cJSON_Parse(big);
    ck_assert_msg(o != NULL, "explain --json is not JSON: %.400s", big);
    return o;
}

static float pfm_at(const char *path, int x, int y, int c)
{
    float *im;
    int w, h, ch;
    spr_error err = {0};
    ck_assert_msg(spr_read_pfm(path, &im, &w, &h, &ch, &err) == SPR_OK, "%s", err.msg);
    float v = im[((size_t)y * w + x) * ch + c];
    free(im);
    return v;
}

/* A pixel where the composite blends two groups: candidates from the dumps
 * (two group targets covered), confirmed by the history. */
START_TEST(explain_two_groups_within_eps)
{
    setup_dir();
    int rc = cli("render", "--model", "builtin:torus", "--points", "6000", "--size", "80x64", "--algo", "deferred", "--voronoi", "--groups", "wgc",
                 "--k", "3", "--save-scene", in_dir("s.json"), "--dump", in_dir("dump"), "--out", in_dir("a.png"), "--quiet", NULL);
    ck_assert_msg(rc == 0, "%s", out);
    char d0[300], d1[300];
    int found = 0, tried = 0;
    for (int y = 8; y < 56 && !found; y += 3)
        for (int x = 8; x < 72 && !found; x += 3) {
            snprintf(d0, sizeof d0, "%s/000_geometry_k000_depth.pfm", in_dir("dump"));
            snprintf(d1, sizeof d1, "%s/001_geometry_k001_depth.pfm", in_dir("dump"));
            if (!(pfm_at(d0, x, y, 0) < 1.0f && pfm_at(d1, x, y, 0) < 1.0f)) continue;
            tried++;
            cJSON *o = explain_json(in_dir("s.json"), x, y, "cpu");
            cJSON *passes = cJSON_GetObjectItem(cJSON_GetObjectItem(o, "cpu"), "passes"), *p;
            int blended = 0, groups_with_fragments = 0;
            cJSON_ArrayForEach(p, passes)
            {
                const char *kind = cJSON_GetObjectItem(p, "kind")->valuestring;
                if (!strcmp(kind, "draw_splats")) {
                    /* the last fragment that passed leaves the dumped planes of its pass */
                    cJSON *fr = cJSON_GetObjectItem(p, "fragments"), *f, *last = NULL;
                    cJSON_ArrayForEach(f, fr) if (!strcmp(cJSON_GetObjectItem(f, "outcome")->valuestring, "pass")) last = f;
                    groups_with_fragments += last != NULL;
                    if (!last) continue;
                    cJSON *after = cJSON_GetObjectItem(last, "after");
                    const int pass = cJSON_GetObjectItem(p, "pass")->valueint, k = cJSON_GetObjectItem(p, "group")->valueint;
                    static const char *const planes[] = {"depth", "test", "id", "count"};
                    for (int q = 0; q < 4; q++) {
                        char f2[400];
                        snprintf(f2, sizeof f2, "%s/%03d_geometry_k%03d_%s.pfm", in_dir("dump"), pass, k, planes[q]);
                        const float dumped = pfm_at(f2, x, y, 0);
                        const double mine = cJSON_GetObjectItem(after, planes[q])->valuedouble;
                        ck_assert_msg((float)mine == dumped, "pixel %d,%d pass %d %s: history %.9g, dump %.9g", x, y, pass, planes[q], mine, dumped);
                    }
                    char fc[400], fw[400];
                    snprintf(fc, sizeof fc, "%s/%03d_geometry_k%03d_color.pfm", in_dir("dump"), pass, k);
                    snprintf(fw, sizeof fw, "%s/%03d_geometry_k%03d_weight.pfm", in_dir("dump"), pass, k);
                    cJSON *col = cJSON_GetObjectItem(after, "color");
                    for (int c = 0; c < 4; c++) {
                        const float dumped = c < 3 ? pfm_at(fc, x, y, c) : pfm_at(fw, x, y, 0);
                        ck_assert_msg((float)cJSON_GetArrayItem(col, c)->valuedouble == dumped, "pixel %d,%d pass %d colour %d", x, y, pass, c);
                    }
                    ck_assert(cJSON_IsTrue(cJSON_GetObjectItem(p, "replay_matches")));
                } else if (!strcmp(kind, "composite")) {
                    cJSON *st = cJSON_GetObjectItem(p, "steps"), *s;
                    cJSON_ArrayForEach(s, st)
                    {
                        if (strcmp(cJSON_GetObjectItem(s, "step")->valuestring, "eps_input")) continue;
                        cJSON *v = cJSON_GetObjectItem(s, "v");
                        /* included: d_f(k) <= limit, by hand from the step's own numbers */
                        const float dk = (float)cJSON_GetArrayItem(v, 0)->valuedouble, lim = (float)cJSON_GetArrayItem(v, 1)->valuedouble;
                        const int inc = cJSON_GetArrayItem(v, 2)->valuedouble != 0.0;
                        ck_assert_int_eq(inc, dk <= lim);
                        blended += inc && dk < 1.0f;
                    }
                }
            }
            if (blended >= 2 && groups_with_fragments >= 2) {
                found = 1;
                printf("explain: pixel %d,%d: %d groups' fragments listed, the composite blends %d inputs within eps; "
                       "the last passing fragment of every pass equals the dumped planes\n", x, y, groups_with_fragments, blended);
                /* the text form lists the decision */
                char pix[32];
                snprintf(pix, sizeof pix, "%d,%d", x, y);
                rc = cli("explain", "--scene", in_dir("s.json"), "--pixel", pix, "--backend", "cpu", "--quiet", NULL);
                ck_assert_msg(rc == 0 && strstr(out, "-> blended") && strstr(out, "SPEC 4.2: d = min_k d_f(k)"), "%s", out);
            }
            cJSON_Delete(o);
        }
    ck_assert_msg(found, "no pixel where two groups blend within eps among %d candidates", tried);
}
END_TEST

/* The new commands on bad input: one line naming the problem, exit 2, no output. */
START_TEST(tools_bad_inputs)
{
    setup_dir();
    int rc = cli("render", "--size", "40x30", "--save-scene", in_dir("s.json"), "--out", in_dir("a.png"), "--quiet", NULL);
    ck_assert_msg(rc == 0, "%s", out);
    static const struct { const char *argv[8]; const char *expect; } cases[] = {
        {{"explain", "--pixel", "40,3"}, "outside the 40x30 image"},
        {{"explain", "--pixel", "4"}, "--pixel X,Y is required"},
        {{"explain", "--pixel", "4,4", "--backend", "vulkan"}, "is not both, cpu or gl"},
        {{"check"}, "--image is required"},
        {{"check", "--image", "/nonexistent.png"}, "/nonexistent.png"},
        {{"check", "--image", "x.tif"}, "unknown image type"},
        {{"check", "--image", "a.png", "--tier", "D"}, "is not A, B or C"},
        {{"check", "--image", "a.png", "--tier", "A", "--lsb", "1"}, "Tier A is bit-exact"},
        {{"check", "--image", "a.png", "--ulp", "3"}, "--ulp applies to float"},
        {{"check", "--image", "a.png", "--plane", "sparkle"}, "--plane: 'sparkle'"},
        {{"step"}, "--out DIR is required"},
        {{"render", "--view-matrix", "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1"}, "go together"},
        {{"render", "--eye", "0,0,5", "--view-matrix", "1,0,0,0,0,1,0,0,0,0,1,-5,0,0,0,1", "--projection-matrix", "1,0,0,0,0,1,0,0,0,0,-1,-1,0,0,-1,0"},
         "both place the camera"},
        {{"render", "--view-matrix", "1,0,0,0,0,1,0,0,0,0,1,-5,0,0,0,1", "--projection-matrix", "1,0,0,0,0,1,0,0,0,0,-1,-1,0,0,1,1"}, "row 4 must be"},
        {{"render", "--view-matrix", "1,0,0", "--projection-matrix", "1,0,0,0,0,1,0,0,0,0,-1,-1,0,0,-1,0"}, "has 3 numbers"},
        {{"render", "--view-matrix", "1,0,x,0,0,1,0,0,0,0,1,-5,0,0,0,1", "--projection-matrix", "1,0,0,0,0,1,0,0,0,0,-1,-1,0,0,-1,0"}, "element 3"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *argv[20] = {"splatref"};
        int n = 1;
        for (int k = 0; k < 8 && cases[i].argv[k]; k++) argv[n++] = (char *)cases[i].argv[k];
        if (strcmp(cases[i].argv[0], "render")) argv[n++] = "--scene", argv[n++] = (char *)in_dir("s.json");
        if (strcmp(cases[i].argv[0], "explain") && strcmp(cases[i].argv[0], "step")) /* explain has no --out; step's is the error */
            argv[n++] = "--out", argv[n++] = (char *)in_dir("bad-out");
        argv[n++] = "--quiet";
        argv[n] = NULL;
        for (int k = 0; argv[k]; k++)
            if (!strcmp(argv[k], "a.png")) argv[k] = (char *)in_dir("a.png");
        rc = tu_run(NULL, NULL, 1, argv, out, sizeof out);
        printf("bad input %zu (%s): exit %d: %s", i, cases[i].argv[0], rc, out);
        ck_assert_msg(rc == 2 && strstr(out, cases[i].expect), "case %zu: expected '%s', exit %d: %s", i, cases[i].expect, rc, out);
        ck_assert_msg(strchr(out, '\n') == out + strlen(out) - 1, "case %zu: not one line: %s", i, out);
        ck_assert_msg(access(in_dir("bad-out"), F_OK) != 0, "case %zu: output written", i);
    }
}
END_TEST

/* A fuzzer input without its first byte (the harness's format selector) written to path. */
static void corpus_file(const char *name, const char *path)
{
    char src[600];
    snprintf(src, sizeof src, "%s/tests/fuzz/corpus/image/%s", SPR_SOURCE_DIR, name);
    FILE *f = fopen(src, "rb"), *g = fopen(path, "wb");
    ck_assert_msg(f && g, "%s", src);
    unsigned char b[4096];
    size_t n = fread(b, 1, sizeof b, f);
    ck_assert(n > 1 && fwrite(b + 1, 1, n - 1, g) == n - 1);
    fclose(f), fclose(g);
}

/* What an image handed to check may cost (issue 36): the fuzzer's 95-byte PNG whose last chunk header claims 2 GB
 * and a 65536x65536 IHDR with 14 bytes of image data are one line each, and a header of another size than the scene's
 * is refused before anything is decoded; the children's peak memory stays far below 200 MB (it was 2.1 GB). */
START_TEST(check_bounds_what_an_image_costs)
{
    setup_dir();
    ck_assert_int_eq(cli("render", "--model", "builtin:torus", "--points", "500", "--size", "5x5", "--out", in_dir("t.png"), "--save-scene",
                         in_dir("s5.json"), "--quiet", NULL), 0);
    corpus_file("finding_short_tail_2gb", in_dir("tail.png"));
    int rc = cli("check", "--scene", in_dir("s5.json"), "--image", in_dir("tail.png"), "--out", in_dir("r1"), "--quiet", NULL);
    ck_assert_msg(rc == 2 && strstr(out, "tail.png: byte 83: 11 bytes that are not a chunk") && strchr(out, '\n') == out + strlen(out) - 1, "%s", out);
    corpus_file("finding_huge_ihdr_tiny_idat", in_dir("huge.png"));
    float *im = NULL;
    int w, h, ch;
    spr_error err = {0};
    ck_assert_int_ne(spr_read_image(in_dir("huge.png"), &im, &w, &h, &ch, &err), SPR_OK);
    ck_assert_msg(strstr(err.msg, "65536x65536 pixels need") && strstr(err.msg, "more than its"), "%s", err.msg);
    ck_assert_ptr_null(im);
    /* check: its header's size against the scene's, before the image data is read */
    rc = cli("check", "--scene", in_dir("s5.json"), "--image", in_dir("huge.png"), "--out", in_dir("r2"), "--quiet", NULL);
    ck_assert_msg(rc == 2 && strstr(out, "huge.png is 65536x65536, the scene renders 5x5"), "%s", out);
    ck_assert_int_ne(access(in_dir("r1"), F_OK), 0);
    ck_assert_int_ne(access(in_dir("r2"), F_OK), 0);
    struct rusage ru;
    ck_assert_int_eq(getrusage(RUSAGE_CHILDREN, &ru), 0);
    printf("tools: check of the fuzzer's PNG inputs: children's peak memory %ld KB\n", ru.ru_maxrss);
    ck_assert_msg(ru.ru_maxrss < 200 * 1024, "peak %ld KB", ru.ru_maxrss);
}
END_TEST

/* Views 0 … n − 1 of the cameras file rendered with gauss3d into dir, named as render.py names them (00000.png, …). */
static void render_views(const char *model, const char *cams, const char *dir, int n)
{
    char id[16], path[300];
    for (int k = 0; k < n; k++) {
        snprintf(id, sizeof id, "%d", k);
        snprintf(path, sizeof path, "%s/%05d.png", dir, k);
        ck_assert_msg(cli("render", "--model", model, "--algo", "gauss3d", "--cameras", cams, "--camera", id, "--out", path, "--quiet", NULL) == 0,
                      "%s", out);
    }
}

/* check --cameras F.json --camera all --images DIR (issue 36): twelve views of the real donut, each image rendered by
 * `render --camera K` into the name the training code's render.py gives it (00000.png, …).  Then, by construction:
 * view 4's image gets one white pixel (it fails with exactly that pixel, alone), view 7's image is removed (its
 * view fails, the run goes on), view 9's file holds view 10's picture (fails: each view is checked with its own
 * camera).  One JUnit testcase a view; the other nine pass.  By img_name: a folder named ring00.png, … */
START_TEST(check_every_view_of_a_cameras_json)
{
    setup_dir();
    char model[512], cams[512], renders[128], named[128], path[256];
    snprintf(model, sizeof model, "%s/tests/data/captures/real/donut-mipsplat.ply", SPR_SOURCE_DIR);
    snprintf(cams, sizeof cams, "%s/tests/data/cameras/donut-ring12.json", SPR_SOURCE_DIR);
    snprintf(renders, sizeof renders, "%s", in_dir("renders"));
    snprintf(named, sizeof named, "%s", in_dir("named"));
    ck_assert_int_eq(mkdir(renders, 0777), 0);
    ck_assert_int_eq(mkdir(named, 0777), 0);
    render_views(model, cams, renders, 12);
    for (int k = 0; k < 12; k += 3) { /* by img_name: views 0, 3, 6, 9 */
        char to[256];
        snprintf(path, sizeof path, "%s/%05d.png", renders, k);
        snprintf(to, sizeof to, "%s/ring%02d.png", named, k);
        ck_assert_int_eq(link(path, to), 0);
    }
    /* a model trained with --eval (3DGS's scene/__init__.py writes its test cameras first, then the training ones;
     * render.py numbers test/ and train/ from 00000 each): entries 0..2 as its test views, 3..11 as its training views */
    char train[128], test[128];
    snprintf(train, sizeof train, "%s", in_dir("train"));
    snprintf(test, sizeof test, "%s", in_dir("test"));
    ck_assert_int_eq(mkdir(train, 0777), 0);
    ck_assert_int_eq(mkdir(test, 0777), 0);
    for (int k = 0; k < 12; k++) {
        char to[256];
        snprintf(path, sizeof path, "%s/%05d.png", renders, k);
        snprintf(to, sizeof to, "%s/%05d.png", k < 3 ? test : train, k < 3 ? k : k - 3);
        ck_assert_int_eq(link(path, to), 0);
    }
    int rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", cams, "--camera", "all", "--images", train, "--views", "3..", "--out",
                 in_dir("report-train"), "--quiet", NULL);
    ck_assert_msg(rc == 0 && strstr(out, "check: view 1 of 9 (camera 3, ring03): ") && strstr(out, "train/00000.png: PASS") &&
                      strstr(out, "check: 9 views (entries 3..11) of ") && strstr(out, ": 9 pass, 0 fail, 0 without") &&
                      strstr(out, "verdict: PASS (all 9 views)") && !strstr(out, "hint"),
                  "rc %d: %s", rc, out);
    {
        cJSON *rj = tu_read_json(in_dir("report-train/report.json"));
        const cJSON *verdict = cJSON_GetObjectItem(rj, "verdict"), *views = cJSON_GetObjectItem(rj, "views");
        ck_assert_msg(cJSON_IsString(verdict) && !strcmp(verdict->valuestring, "pass") && cJSON_GetArraySize(views) == 9,
                      "report.json of --views 3..: verdict %s, %d views", cJSON_IsString(verdict) ? verdict->valuestring : "?", cJSON_GetArraySize(views));
        cJSON_Delete(rj);
    }
    rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", cams, "--camera", "all", "--images", test, "--views", "0..2", "--out",
             in_dir("report-test"), "--quiet", NULL);
    ck_assert_msg(rc == 0 && strstr(out, "check: 3 views (entries 0..2) of ") && strstr(out, "verdict: PASS (all 3 views)"), "rc %d: %s", rc, out);
    /* a trainer's 8-bit renders checked at Tier B (issue 44): every option check reads for one image works for every
     * view.  A copy of the test views, view 1's image with one channel of one pixel 1 LSB up, view 2's 2 LSB up:
     * Tier A fails both, --tier B --lsb 1 passes view 1 alone, --lsb 2 passes all three */
    {
        char lsb[128];
        snprintf(lsb, sizeof lsb, "%s", in_dir("lsb"));
        ck_assert_int_eq(mkdir(lsb, 0777), 0);
        for (int k = 0; k < 3; k++) {
            float *im = NULL;
            int w, h, ch;
            spr_error err = {0};
            char from[256], to[256];
            snprintf(from, sizeof from, "%s/%05d.png", test, k);
            snprintf(to, sizeof to, "%s/%05d.png", lsb, k);
            ck_assert_int_eq(spr_read_image(from, &im, &w, &h, &ch, &err), SPR_OK);
            size_t at = 0; /* the first pixel whose red lies in [10, 250] of 255: room to go up */
            while (at < (size_t)w * h && !(im[at * ch] >= 10.0f / 255.0f && im[at * ch] <= 250.0f / 255.0f)) at++;
            ck_assert_uint_lt(at, (size_t)w * h);
            const long r8 = lrintf(im[at * ch] * 255.0f);
            im[at * ch] = (float)(r8 + k) / 255.0f;
            ck_assert_int_eq(spr_write_png(to, im, w, h, ch, &err), SPR_OK);
            free(im);
        }
        static const struct { const char *tier, *lsb, *want; int rc; } tiers[] = {
            {"A", NULL, ": 1 pass, 2 fail, 0 without", 1}, {"B", "1", ": 2 pass, 1 fail, 0 without", 1}, {"B", "2", ": 3 pass, 0 fail, 0 without", 0}};
        for (int t = 0; t < 3; t++) {
            rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", cams, "--camera", "all", "--images", lsb, "--views", "0..2", "--tier",
                     tiers[t].tier, tiers[t].lsb ? "--lsb" : "--out", tiers[t].lsb ? tiers[t].lsb : in_dir("report-lsb"), "--out", in_dir("report-lsb"),
                     "--quiet", NULL);
            ck_assert_msg(rc == tiers[t].rc && strstr(out, tiers[t].want) && !strstr(out, "is not used here"), "--tier %s --lsb %s: rc %d: %s",
                          tiers[t].tier, tiers[t].lsb ? tiers[t].lsb : "-", rc, out);
        }
        ck_assert_msg(strstr(out, "00002.png: PASS, 0 of 3072 pixels fail, max 2 LSB"), "%s", out);
    }
    /* the training folder checked against every entry: every view fails, and the hint names both selections */
    rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", cams, "--camera", "all", "--images", train, "--out", in_dir("report-all"),
             "--quiet", NULL);
    ck_assert_msg(rc == 1 && strstr(out, ": 0 pass, ") && strstr(out, "holds 9 images 00000.png, … for 12 views") &&
                      strstr(out, "for its training views give --views 3.., for its test views --views 0..8"),
                  "rc %d: %s", rc, out);
    /* a range beyond the file, or not a range: one line naming the file; --views without --camera all */
    static const char *const bad_views[][2] = {{"3..12", "has 12 entries (0..11)"}, {"3", "give FIRST..LAST or FIRST.."}, {"5..2", "give FIRST..LAST"}};
    for (int b = 0; b < 3; b++) {
        rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", cams, "--camera", "all", "--images", train, "--views", bad_views[b][0],
                 "--out", in_dir("report-bad"), NULL);
        ck_assert_msg(rc == 2 && strstr(out, bad_views[b][1]) && (b || strstr(out, "donut-ring12.json")) && strchr(out, '\n') == out + strlen(out) - 1,
                      "%s: rc %d: %s", bad_views[b][0], rc, out);
        ck_assert_int_ne(access(in_dir("report-bad"), F_OK), 0);
    }
    /* views of different sizes (training sets resized per image): the first three entries, the second at 80 × 60;
     * each view is rendered and checked at its own size, and an image of another view's size fails that view alone */
    {
        cJSON *all = tu_read_json(cams), *three = cJSON_CreateArray();
        for (int k = 0; k < 3; k++) cJSON_AddItemToArray(three, cJSON_Duplicate(cJSON_GetArrayItem(all, k), 1));
        cJSON_Delete(all);
        cJSON *e1 = cJSON_GetArrayItem(three, 1);
        cJSON_ReplaceItemInObject(e1, "width", cJSON_CreateNumber(80));
        cJSON_ReplaceItemInObject(e1, "height", cJSON_CreateNumber(60));
        cJSON_ReplaceItemInObject(e1, "fx", cJSON_CreateNumber(70));
        cJSON_ReplaceItemInObject(e1, "fy", cJSON_CreateNumber(70));
        char *js = cJSON_Print(three);
        cJSON_Delete(three);
        char mixed[128], mcams[128];
        snprintf(mixed, sizeof mixed, "%s", in_dir("mixed"));
        snprintf(mcams, sizeof mcams, "%s", in_dir("mixed.json"));
        FILE *mf = fopen(mcams, "w");
        ck_assert(mf && fputs(js, mf) >= 0);
        fclose(mf);
        free(js);
        ck_assert_int_eq(mkdir(mixed, 0777), 0);
        render_views(model, mcams, mixed, 3);
        rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", mcams, "--camera", "all", "--images", mixed, "--out", in_dir("report-mixed"),
                 "--quiet", NULL);
        ck_assert_msg(rc == 0 && strstr(out, "00001.png: PASS, 0 of 4800 pixels fail") && strstr(out, "00002.png: PASS, 0 of 3072 pixels fail"),
                      "rc %d: %s", rc, out);
        char from0[256], to1[256];
        snprintf(from0, sizeof from0, "%s/00000.png", mixed);
        snprintf(to1, sizeof to1, "%s/00001.png", mixed);
        ck_assert_int_eq(unlink(to1), 0);
        ck_assert_int_eq(link(from0, to1), 0);
        rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", mcams, "--camera", "all", "--images", mixed, "--out", in_dir("report-mixed"),
                 "--quiet", NULL);
        ck_assert_msg(rc == 1 && strstr(out, "00001.png is 64x48, the view renders 80x60") && strstr(out, ": 2 pass, 0 fail, 1 without a usable image"),
                      "rc %d: %s", rc, out);
    }
    /* an img_name with a control character (JSON allows \n): refused as the file is read, one line */
    FILE *cf = fopen(in_dir("ctl.json"), "w");
    ck_assert_ptr_nonnull(cf);
    fputs("[{\"id\": 0, \"img_name\": \"ring\\n00\", \"width\": 8, \"height\": 8, \"position\": [0,0,0], "
          "\"rotation\": [[1,0,0],[0,1,0],[0,0,1]], \"fx\": 5, \"fy\": 5}]", cf);
    fclose(cf);
    rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", in_dir("ctl.json"), "--camera", "all", "--images", train, "--out",
             in_dir("report-bad"), NULL);
    ck_assert_msg(rc == 2 && strstr(out, "ctl.json: camera 0: \"img_name\" holds the control character 0x0a at byte 4") &&
                      strchr(out, '\n') == out + strlen(out) - 1,
                  "rc %d: %s", rc, out);
    rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", cams, "--camera", "3", "--image", path, "--views", "0..2", NULL);
    ck_assert_msg(rc == 2 && strstr(out, "--views goes with --cameras F.json --camera all"), "rc %d: %s", rc, out);

    /* the three changes */
    float *im = NULL;
    int w, h, ch;
    spr_error err = {0};
    snprintf(path, sizeof path, "%s/00004.png", renders);
    ck_assert_int_eq(spr_read_image(path, &im, &w, &h, &ch, &err), SPR_OK);
    ck_assert_int_eq(w, 64);
    const int px = 17, py = 30; /* row 30 of spr_read_image's rows (row 0 the bottom) */
    for (int c = 0; c < 3; c++) im[((size_t)py * w + px) * ch + c] = 1.0f;
    ck_assert_int_eq(spr_write_png(path, im, w, h, ch, &err), SPR_OK);
    free(im);
    snprintf(path, sizeof path, "%s/00007.png", renders);
    ck_assert_int_eq(unlink(path), 0);
    char from[256];
    snprintf(from, sizeof from, "%s/00010.png", renders);
    snprintf(path, sizeof path, "%s/00009.png", renders);
    ck_assert_int_eq(rename(path, in_dir("view9.png")), 0);
    ck_assert_int_eq(link(from, path), 0);

    const char *junit = in_dir("views.xml"), *rep = in_dir("report");
    rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", cams, "--camera", "all", "--images", renders, "--junit", junit,
                 "--out", rep, "--quiet", NULL);
    ck_assert_msg(rc == 1, "rc %d: %s", rc, out);
    for (int k = 0; k < 12; k++) {
        char head[64];
        snprintf(head, sizeof head, "check: view %d of 12 (camera %d, ring%02d): ", k + 1, k, k);
        const char *l = strstr(out, head);
        ck_assert_msg(l, "no line for view %d: %s", k, out);
        l += strlen(head);
        if (k == 4) ck_assert_msg(!strncmp(strstr(l, ": ") + 2, "FAIL, 1 of 3072 pixels fail", 27) && strstr(l, "first x 17, y 30"), "%.200s", l);
        else if (k == 7) ck_assert_msg(!strncmp(l, "FAIL: no image ", 15) && strstr(l, "00007.png (nor .pfm)"), "%.200s", l);
        else if (k == 9) ck_assert_msg(!strncmp(strstr(l, ": ") + 2, "FAIL, ", 6), "%.200s", l);
        else ck_assert_msg(!strncmp(strstr(l, ": ") + 2, "PASS, 0 of 3072 pixels fail", 27), "view %d: %.200s", k, l);
    }
    ck_assert_msg(strstr(out, "check: 12 views of ") && strstr(out, ": 9 pass, 2 fail, 1 without a usable image") &&
                  strstr(out, "verdict: FAIL (cameras 4, 7, 9)"), "%s", out);
    /* JUnit: one testcase a view, failures exactly at 4, 7 and 9 */
    char *x = NULL;
    size_t xl = 0;
    ck_assert_int_eq(spr__read_file(junit, &x, &xl, &err), SPR_OK);
    int cases = 0, fails = 0;
    for (const char *q = x; (q = strstr(q, "<testcase ")); q++) {
        const char *end = strstr(q, "</testcase>"), *f = strstr(q, "<failure");
        char name[64];
        snprintf(name, sizeof name, " name=\"view %d of 12 (camera %d,", cases + 1, cases);
        ck_assert_msg(!strncmp(strstr(q, " name="), name, strlen(name)), "testcase %d: %.120s", cases, q);
        const int failed = f && end && f < end;
        ck_assert_msg(failed == (cases == 4 || cases == 7 || cases == 9), "testcase %d failed %d", cases, failed);
        fails += failed, cases++;
    }
    ck_assert_int_eq(cases, 12);
    ck_assert_int_eq(fails, 3);
    ck_assert_msg(strstr(x, "tests=\"12\" failures=\"3\""), "%.300s", x);
    free(x);
    /* the report folder: a summary, one folder a view, pictures where a view fails */
    snprintf(path, sizeof path, "%s/report.json", rep);
    ck_assert_int_eq(access(path, F_OK), 0);
    snprintf(path, sizeof path, "%s/00004/heatmap.png", rep);
    ck_assert_int_eq(access(path, F_OK), 0);
    snprintf(path, sizeof path, "%s/00003/report.json", rep);
    ck_assert_int_eq(access(path, F_OK), 0);
    snprintf(path, sizeof path, "%s/00003/heatmap.png", rep);
    ck_assert_int_ne(access(path, F_OK), 0);
    /* undone, every view passes (exit 0) */
    ck_assert_int_eq(unlink(in_dir("renders/00009.png")), 0);
    ck_assert_int_eq(rename(in_dir("view9.png"), in_dir("renders/00009.png")), 0);
    ck_assert_int_eq(link(in_dir("renders/00008.png"), in_dir("renders/00007.png")), 0); /* view 8's picture as view 7's: fails */
    rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", cams, "--camera", "all", "--images", renders, "--out", rep, "--quiet", NULL);
    ck_assert_msg(rc == 1 && strstr(out, ": 10 pass, 2 fail, 0 without") && strstr(out, "(cameras 4, 7)"), "%s", out);
    /* by img_name: views 0, 3, 6, 9 pass, the others have no image */
    rc = cli("check", "--model", model, "--algo", "gauss3d", "--cameras", cams, "--camera", "all", "--images", named, "--image-names", "name", "--out",
             rep, "--quiet", NULL);
    ck_assert_msg(rc == 1 && strstr(out, ": 4 pass, 0 fail, 8 without a usable image") && strstr(out, "ring03.png: PASS") &&
                  strstr(out, "no image ") && strstr(out, "ring01.png (nor .pfm)"), "%s", out);
    /* one line each: --camera all without --images, --images without --camera all, all elsewhere, a bad flag */
    static const char *const bad[][2] = {{"check", "--camera all checks every view: give --images DIR"},
                                         {"check-images", "--images DIR goes with --cameras F.json --camera all"},
                                         {"render", "--camera all: only check takes every view"},
                                         {"check-names", "--image-names: 'stem' is not position or name"}};
    for (int b = 0; b < 4; b++) {
        const int ck = strncmp(bad[b][0], "check", 5) == 0;
        if (!strcmp(bad[b][0], "check")) rc = cli("check", "--model", model, "--cameras", cams, "--camera", "all", "--image", in_dir("t.png"), NULL);
        else if (!strcmp(bad[b][0], "check-images")) rc = cli("check", "--model", model, "--cameras", cams, "--camera", "3", "--images", renders, NULL);
        else if (!strcmp(bad[b][0], "render")) rc = cli("render", "--model", model, "--cameras", cams, "--camera", "all", "--out", in_dir("x.png"), NULL);
        else rc = cli("check", "--model", model, "--cameras", cams, "--camera", "all", "--images", renders, "--image-names", "stem", NULL);
        ck_assert_msg(rc == 2 && strstr(out, bad[b][1]) && strchr(out, '\n') == out + strlen(out) - 1, "%s (%d): %s", bad[b][0], ck, out);
    }
}
END_TEST

Suite *make_tools_suite(void)
{
    Suite *s = suite_create("tools");
    TCase *tc = tcase_create("tools");
    tcase_set_timeout(tc, 900);
    tcase_add_test(tc, scene_round_trip_every_algorithm);
    tcase_add_test(tc, scene_hand_matrices_equal_lookat);
    tcase_add_test(tc, scene_bad_files);
    tcase_add_test(tc, explain_two_groups_within_eps);
    tcase_add_test(tc, tools_bad_inputs);
    tcase_add_test(tc, check_bounds_what_an_image_costs);
    tcase_add_test(tc, check_every_view_of_a_cameras_json);
    suite_add_tcase(s, tc);
    return s;
}


/* CPU and GL histories of every algorithm: identical, every fragment, step and plane. */
START_TEST(explain_cpu_gl_identical_every_algorithm)
{
    setup_dir();
    for (int al = 0; al < SPR_ALGO__COUNT; al++) {
        const char *name = spr_algo_name((spr_algo)al);
        int rc = algo_run("render", name, "72x60", "--save-scene", in_dir("s.json"), "--out", in_dir("a.png"), NULL);
        ck_assert_msg(rc == 0, "%s: %s", name, out);
        int frags = 0, steps = 0, calls = 0;
        static const int px[][2] = {{18, 30}, {24, 30}, {36, 40}, {30, 22}, {50, 30}};
        for (size_t i = 0; i < sizeof px / sizeof px[0]; i++) {
            cJSON *o = explain_json(in_dir("s.json"), px[i][0], px[i][1], "both");
            cJSON *id = cJSON_GetObjectItem(o, "identical");
            ck_assert_msg(cJSON_IsTrue(id), "%s pixel %d,%d: cpu and gl histories differ: %s", name, px[i][0], px[i][1],
                          cJSON_GetObjectItem(cJSON_GetObjectItem(o, "first_difference"), "what")->valuestring);
            cJSON *p;
            cJSON_ArrayForEach(p, cJSON_GetObjectItem(cJSON_GetObjectItem(o, "gl"), "passes"))
            {
                calls++;
                frags += cJSON_GetArraySize(cJSON_GetObjectItem(p, "fragments"));
                steps += cJSON_GetArraySize(cJSON_GetObjectItem(p, "steps"));
                cJSON *rm = cJSON_GetObjectItem(p, "replay_matches");
                ck_assert_msg(!rm || cJSON_IsTrue(rm), "%s: gl replay does not match its planes", name);
            }
            cJSON_Delete(o);
        }
        printf("explain: %-20s cpu and gl identical at 5 pixels: %d calls, %d fragments, %d composite steps\n", name, calls, frags, steps);
        /* gauss3d and gauss2d have no fragments: their pixels' histories are the loop's notes (SPEC 10.8) */
        const int loop = al == SPR_ALGO_GAUSS3D || al == SPR_ALGO_GAUSS2D;
        ck_assert_msg(loop ? steps > 0 : frags > 0, "%s: no %s reached the pixels tried", name, loop ? "loop step" : "fragment");
    }
}
END_TEST

/* --stream on the GL backend: parity bit-exact for every algorithm that can
 * stream (chunks of 97 splats), and the GL backend's streamed image equal
 * to the CPU's whole-cloud image. */
START_TEST(parity_stream_bit_exact)
{
    setup_dir();
    spr_cloud c = tu_builtin("builtin:torus", 3000);
    spr_error e = {0};
    ck_assert_int_eq(spr_write_ply(in_dir("t.ply"), &c, &e), SPR_OK);
    spr_cloud_free(&c);
    static const char *const variants[][6] = {
        {"pbr2p1", NULL}, {"deferred", "--groups", "hash", NULL}, {"deferred", "--groups", "hash", "--voronoi", NULL},
        {"zbuffer", NULL}, {"depthpeel", "--layers", "3", NULL}};
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        const char *a[6] = {NULL, NULL, NULL, NULL, NULL, NULL};
        for (int k = 0; k < 5 && variants[v][k]; k++) a[k] = variants[v][k];
        int rc = cli("parity", "--model", in_dir("t.ply"), "--size", "64x48", "--stream", "--chunk", "97", "--quiet", "--algo", a[0], a[1], a[2], a[3], a[4], NULL);
        printf("parity --stream %s%s: exit %d, %s", a[0], a[3] ? " --voronoi" : "", rc, strstr(out, "verdict") ? strstr(out, "verdict") : out);
        ck_assert_msg(rc == 0 && strstr(out, "verdict: BIT-EXACT (Tier A)"), "%s", out);
    }
    int rc = cli("render", "--model", in_dir("t.ply"), "--size", "64x48", "--algo", "deferred", "--groups", "hash", "--float", in_dir("cpu.pfm"),
                 "--out", in_dir("cpu.png"), "--quiet", NULL);
    ck_assert_msg(rc == 0, "%s", out);
    rc = cli("render", "--model", in_dir("t.ply"), "--size", "64x48", "--algo", "deferred", "--groups", "hash", "--float", in_dir("gl.pfm"),
             "--out", in_dir("gl.png"), "--backend", "gl", "--stream", "--chunk", "97", "--quiet", NULL);
    ck_assert_msg(rc == 0, "%s", out);
    ck_assert_msg(tu_same_file(in_dir("cpu.pfm"), in_dir("gl.pfm")), "the GL backend's streamed image differs from the CPU's whole-cloud image");
    printf("render --stream --backend gl: the same bits as the CPU reference on the whole cloud\n");
}
END_TEST

Suite *make_tools_gl_suite(void)
{
    Suite *s = suite_create("tools_gl");
    TCase *tc = tcase_create("tools_gl");
    tcase_set_timeout(tc, 900);
    tcase_add_test(tc, check_gl_image_tiers);
    tcase_add_test(tc, explain_cpu_gl_identical_every_algorithm);
    tcase_add_test(tc, parity_stream_bit_exact);
    suite_add_tcase(s, tc);
    return s;
}


/* ---- the walk-through page in a real browser ---- */
static const char *chromium_path(void)
{
    static const char *const c[] = {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome", NULL};
    const char *env = getenv("SPLATREF_CHROMIUM");
    if (env && access(env, X_OK) == 0) return env;
    for (int i = 0; c[i]; i++)
        if (access(c[i], X_OK) == 0) return c[i];
    return NULL;
}

/* Dump the page's DOM after load with #test=X,Y (and a screenshot). */
static char *browse(const char *page_dir, int x, int y, const char *shot)
{
    const char *chrome = chromium_path();
    ck_assert_msg(chrome != NULL, "Chromium is not installed (tools/install-deps.sh installs Debian's chromium): the browser test cannot run");
    char url[512], prof[300], shot_arg[600];
    snprintf(url, sizeof url, "file://%s/index.html#test=%d,%d", page_dir, x, y);
    snprintf(prof, sizeof prof, "--user-data-dir=%s", in_dir("chrome-profile"));
    static char dom[1 << 24];
    char *dargv[] = {(char *)chrome, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", prof, "--virtual-time-budget=10000",
                     "--dump-dom", url, NULL};
    /* stdout is the DOM; stderr (Chromium's own logging) goes with it, so read the DOM from its markers */
    int rc = tu_run(chrome, NULL, 1, dargv, dom, sizeof dom);
    ck_assert_msg(rc == 0, "chromium exit %d: %.2000s", rc, dom);
    if (shot) {
        static char log[1 << 16];
        snprintf(shot_arg, sizeof shot_arg, "--screenshot=%s", shot);
        char *sargv[] = {(char *)chrome, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", prof, "--virtual-time-budget=10000",
                         "--window-size=1280,2400", shot_arg, url, NULL};
        rc = tu_run(chrome, NULL, 1, sargv, log, sizeof log);
        ck_assert_msg(rc == 0 && access(shot, F_OK) == 0, "chromium screenshot exit %d: %.2000s", rc, log);
    }
    return dom;
}

/* The value the page shows for (pass, plane) after the click, or NULL. */
static const char *shown(const char *dom, int pass, const char *plane, char *buf, size_t cap)
{
    char key[96];
    snprintf(key, sizeof key, "data-pass=\"%d\" data-plane=\"%s\" data-value=\"", pass, plane);
    const char *p = strstr(dom, key);
    if (!p) return NULL;
    p += strlen(key);
    size_t n = strcspn(p, "\"");
    if (n >= cap) n = cap - 1;
    memcpy(buf, p, n);
    buf[n] = 0;
    return buf;
}

static void browser_check(const char *algo, const char *const *extra, const char *shot)
{
    const char *a[8] = {0};
    for (int i = 0; extra[i]; i++) a[i] = extra[i];
    char dname[64], pname[64];
    snprintf(dname, sizeof dname, "dump-%s", algo);
    snprintf(pname, sizeof pname, "page-%s", algo);
    int rc = cli("render", "--algo", algo, "--size", "64x56", "--save-scene", in_dir("s.json"), "--dump", in_dir(dname), "--float", in_dir("f.pfm"),
                 "--out", in_dir("f.png"), "--quiet", a[0], a[1], a[2], a[3], a[4], a[5], NULL);
    ck_assert_msg(rc == 0, "%s", out);
    rc = cli("step", "--scene", in_dir("s.json"), "--out", in_dir(pname), "--quiet", NULL);
    ck_assert_msg(rc == 0 && strstr(out, "index.html"), "%s", out);
    /* a covered pixel: the first with colour in the final image, scanning from the middle row */
    int w, h, ch;
    float *im = read_img(in_dir("f.pfm"), &w, &h, &ch);
    int x = -1, y = h / 2;
    for (int yy = h / 2; yy < h && x < 0; yy++)
        for (int xx = 0; xx < w && x < 0; xx++)
            if (im[((size_t)yy * w + xx) * ch] > 0.0f) x = xx, y = yy;
    free(im);
    ck_assert_int_ge(x, 0);
    char dpath[300];
    snprintf(dpath, sizeof dpath, "%s", in_dir(pname));
    const char *dom = browse(dpath, x, y, shot);
    /* every picture decoded, no script error */
    const char *st = strstr(dom, "id=\"selftest\"");
    ck_assert_msg(st != NULL, "the page did not run its self-test: %.2000s", dom);
    int images = -1, decoded = -2, errors = -1;
    const char *q;
    if ((q = strstr(st, "data-images=\""))) images = atoi(q + 13);
    if ((q = strstr(st, "data-decoded=\""))) decoded = atoi(q + 14);
    if ((q = strstr(st, "data-errors=\""))) errors = atoi(q + 13);
    printf("browser: %s: %d of %d images decoded, %d script errors\n", algo, decoded, images, errors);
    ck_assert_msg(images >= 4 && decoded == images && errors == 0, "%s: images %d decoded %d errors %d: %.300s", algo, images, decoded, errors, st);
    /* the click shows that pixel's values: each equals the dumped plane */
    DIR *d = opendir(in_dir(dname));
    ck_assert_ptr_nonnull(d);
    struct dirent *e;
    int checked = 0;
    while ((e = readdir(d))) {
        int pass, k = -1, n = 0;
        char name[64], plane[32];
        if (sscanf(e->d_name, "%d_%63[a-z ]_k%d_%31[a-z].pfm%n", &pass, name, &k, plane, &n) != 4)
            if (sscanf(e->d_name, "%d_%63[a-z ]_%31[a-z].pfm", &pass, name, plane) != 3) continue;
        if (!strcmp(plane, "weight")) continue; /* shown inside colour */
        char f2[400], buf[256];
        snprintf(f2, sizeof f2, "%s/%s", in_dir(dname), e->d_name);
        const char *v = shown(dom, pass, plane, buf, sizeof buf);
        ck_assert_msg(v != NULL, "%s: the page shows no %s of pass %d at %d,%d", algo, plane, pass, x, y);
        float *pl;
        int pw, ph, pc;
        spr_error err = {0};
        ck_assert(spr_read_pfm(f2, &pl, &pw, &ph, &pc, &err) == SPR_OK);
        char *end = (char *)v;
        for (int c = 0; c < pc; c++) {
            float got = strtof(end, &end);
            if (*end == ',') end++;
            ck_assert_msg(got == pl[((size_t)y * pw + x) * pc + c], "%s: pass %d %s channel %d at %d,%d: page %s, dump %.9g", algo, pass, plane, c,
                          x, y, v, pl[((size_t)y * pw + x) * pc + c]);
        }
        free(pl);
        checked++;
    }
    closedir(d);
    printf("browser: %s: clicking pixel %d,%d shows %d plane values, each equal to the dumped plane\n", algo, x, y, checked);
    ck_assert_int_gt(checked, 3);
}

START_TEST(step_page_in_chromium)
{
    setup_dir();
    static const char *const def[] = {"--groups", "wgc", "--k", "3", "--points", "2500", NULL};
    browser_check("deferred", def, SPR_BUILD_DIR "/step-deferred-screenshot.png");
    static const char *const dom[] = {"--model", "builtin:cube", "--points", "1500", "--level", "1", NULL};
    browser_check("domain-prefix", dom, SPR_BUILD_DIR "/step-domain-prefix-screenshot.png");
}
END_TEST

/* step writes a page for every algorithm of the registry */
START_TEST(step_every_algorithm)
{
    setup_dir();
    for (int al = 0; al < SPR_ALGO__COUNT; al++) {
        const char *name = spr_algo_name((spr_algo)al);
        int rc = algo_run("step", name, "48x40", "--pixels", "2", "--out", in_dir(name), NULL);
        ck_assert_msg(rc == 0, "%s: %s", name, out);
        char p[400];
        snprintf(p, sizeof p, "%s/index.html", in_dir(name));
        ck_assert_msg(access(p, F_OK) == 0, "%s: no index.html", name);
        printf("step: %-20s %s", name, out);
    }
}
END_TEST

Suite *make_browser_suite(void)
{
    Suite *s = suite_create("browser");
    TCase *tc = tcase_create("browser");
    tcase_set_timeout(tc, 900);
    tcase_add_test(tc, step_every_algorithm);
    tcase_add_test(tc, step_page_in_chromium);
    suite_add_tcase(s, tc);
    return s;
}
