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
#include <cjson/cJSON.h>
#include "spr_image.h"
#include "test_util.h"

static char dir[64];
static const char *in_dir(const char *name)
{
    static char p[16][256];
    static int k;
    k = (k + 1) % 16;
    snprintf(p[k], sizeof p[k], "%s/%s", dir, name);
    return p[k];
}
static void setup_dir(void)
{
    strcpy(dir, "/tmp/spr_tools_XXXXXX");
    ck_assert_ptr_nonnull(mkdtemp(dir));
}

/* `splatref ARG…` (NULL-terminated); exit status, output (stdout and stderr) in out. */
static char out[1 << 16];
static int cli(const char *first, ...)
{
    char *argv[64] = {"splatref", (char *)first};
    int n = 2;
    va_list ap;
    va_start(ap, first);
    const char *s;
    while ((s = va_arg(ap, const char *)) && n < 63) argv[n++] = (char *)s;
    va_end(ap);
    argv[n] = NULL;
    return tu_run(NULL, NULL, 1, argv, out, sizeof out);
}

static int same_file(const char *a, const char *b)
{
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    ck_assert_msg(fa && fb, "cannot open %s or %s", a, b);
    int same = 1, ca, cb;
    do {
        ca = fgetc(fa), cb = fgetc(fb);
        same &= ca == cb;
    } while (same && ca != EOF);
    fclose(fa);
    fclose(fb);
    return same;
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

START_TEST(scene_round_trip_every_algorithm)
{
    setup_dir();
    for (int al = 0; al < SPR_ALGO__COUNT; al++) {
        const char *name = spr_algo_name((spr_algo)al);
        const char *const *x = algo_args(name);
        const char *a[8] = {0};
        for (int i = 0; x[i]; i++) a[i] = x[i];
        int rc = cli("render", "--algo", name, "--size", "96x80", "--points", "3000", "--save-scene", in_dir("s.json"), "--float",
                     in_dir("a.pfm"), "--out", in_dir("a.png"), "--quiet", a[0], a[1], a[2], a[3], a[4], a[5], NULL);
        ck_assert_msg(rc == 0, "%s: %s", name, out);
        rc = cli("render", "--scene", in_dir("s.json"), "--float", in_dir("b.pfm"), "--out", in_dir("b.png"), "--quiet", NULL);
        ck_assert_msg(rc == 0, "%s: %s", name, out);
        ck_assert_msg(same_file(in_dir("a.pfm"), in_dir("b.pfm")), "%s: --scene renders other bits than the command line", name);
        /* and with the camera saved as raw matrices */
        rc = cli("render", "--scene", in_dir("s.json"), "--scene-camera", "matrices", "--save-scene", in_dir("m.json"), "--out",
                 in_dir("c.png"), "--quiet", NULL);
        ck_assert_msg(rc == 0, "%s: %s", name, out);
        rc = cli("render", "--scene", in_dir("m.json"), "--float", in_dir("c.pfm"), "--out", in_dir("c.png"), "--quiet", NULL);
        ck_assert_msg(rc == 0, "%s: %s", name, out);
        ck_assert_msg(same_file(in_dir("a.pfm"), in_dir("c.pfm")), "%s: the matrix form renders other bits", name);
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
    ck_assert_msg(same_file(in_dir("m.pfm"), in_dir("e.pfm")), "hand matrices and the eye form render other bits");
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
        ck_assert_msg(same_file(a, b), "plane %s differs between the matrix and the eye form", e->d_name);
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
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        write_file(in_dir("bad.json"), cases[i].text);
        int rc = cli("render", "--scene", in_dir("bad.json"), "--out", in_dir("bad.png"), "--quiet", NULL);
        printf("scene: bad file %zu: exit %d: %s", i, rc, out);
        ck_assert_msg(rc == 2 && strstr(out, cases[i].expect), "case %zu: expected '%s', got exit %d: %s", i, cases[i].expect, rc, out);
        ck_assert_msg(strchr(out, '\n') == out + strlen(out) - 1, "case %zu: not one line: %s", i, out);
        ck_assert_int_ne(access(in_dir("bad.png"), F_OK), 0);
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
    suite_add_tcase(s, tc);
    return s;
}
