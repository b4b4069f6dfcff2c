/* test_cli.c — the `splatref` command on bad input: one clear line on
 * stderr naming the file or option, exit status ≠ 0, no output file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <dirent.h>
#include <unistd.h>
#include "spr_image.h"
#include "spr_io.h"
#include "spr_npy.h"
#include <cjson/cJSON.h>
#include "test_util.h"

static char dir[64];

#define path_in(name) tu_in(dir, (name))
static void setup_dir(void) { tu_tmpdir(dir, "cli"); }

static void write_text(const char *name, const char *s, size_t n)
{
    FILE *f = fopen(path_in(name), "wb");
    ck_assert_ptr_nonnull(f);
    fwrite(s, 1, n, f);
    fclose(f);
}

static int run(char *const argv[], char *err, size_t cap) { return tu_run(NULL, NULL, 0, argv, err, cap); }

/* `splatref ARGS… [--out OUT] --quiet` (args NULL-terminated, at most 12). */
static int run_args(const char *const *args, const char *out, char *err, size_t cap)
{
    char *argv[20] = {"splatref"};
    int n = 1;
    for (int k = 0; args[k] && k < 12; k++) argv[n++] = (char *)args[k];
    if (out) argv[n++] = "--out", argv[n++] = (char *)out;
    argv[n++] = "--quiet";
    argv[n] = NULL;
    return run(argv, err, cap);
}

static int count_files(void)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (e->d_name[0] != '.') n++;
    closedir(d);
    return n;
}

/* s is exactly one line: text ending in its only newline (what every failure of the command prints). */
static int one_line(const char *s)
{
    const char *nl = strchr(s, '\n');
    return nl && !nl[1];
}

static void expect_failure(const char *what, const char *model, const char *extra, const char *must_contain)
{
    char err[4096];
    const char *out = path_in("out.png");
    int before = count_files();
    char *argv[] = {"splatref", "render", "--model", (char *)model, "--out", (char *)out, "--quiet", (char *)extra, NULL};
    if (!extra) argv[7] = NULL;
    int rc = run(argv, err, sizeof err);
    printf("cli: %-22s exit %d: %s", what, rc, err);
    ck_assert_msg(rc != 0 && rc < 128, "%s: exit status %d", what, rc);
    ck_assert_msg(one_line(err), "%s: not exactly one line: [%s]", what, err);
    ck_assert_msg(strstr(err, must_contain) != NULL, "%s: message lacks \"%s\": %s", what, must_contain, err);
    ck_assert_msg(access(out, F_OK) != 0, "%s: output file was written", what);
    ck_assert_int_eq(count_files(), before); /* no temporary left behind either */
}

START_TEST(bad_inputs)
{
    setup_dir();
    char buf[1024];
    /* a valid 6-vertex binary PLY, then cut */
    int o = sprintf(buf, "ply\nformat binary_little_endian 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
                         "property float z\nend_header\n");
    for (int i = 0; i < 18; i++) { float f = (float)i; memcpy(buf + o, &f, 4); o += 4; }
    write_text("trunc.ply", buf, (size_t)o - 5);
    const char *huge = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n"
                       "property float y\nproperty float z\nend_header\n";
    write_text("huge.ply", huge, strlen(huge));
    const char *nan = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "end_header\n0 0 0\n1 0 0\n0 NaN 1\n";
    write_text("nan.ply", nan, strlen(nan));
    const char *neg = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "property float radius\nend_header\n0 0 0 1\n1 0 0 -2\n0 1 0 1\n";
    write_text("neg.ply", neg, strlen(neg));

    expect_failure("truncated binary PLY", path_in("trunc.ply"), NULL, "trunc.ply: byte");
    expect_failure("10^12 vertices", path_in("huge.ply"), NULL, "huge.ply");
    expect_failure("NaN coordinate", path_in("nan.ply"), NULL, "nan.ply:10:");
    expect_failure("negative radius", path_in("neg.ply"), NULL, "neg.ply:10:");
    expect_failure("missing file", path_in("missing.ply"), NULL, "missing.ply");
    expect_failure("unknown option", "builtin:sphere", "--frobnicate", "--frobnicate");
    expect_failure("bad option value", "builtin:sphere", "--size=12x", "--size");
    expect_failure("unknown model", "builtin:teapot", NULL, "teapot");
}
END_TEST

START_TEST(render_writes_outputs)
{
    setup_dir();
    char err[4096];
    const char *png = path_in("s.png"), *pfm = path_in("s.pfm"), *js = path_in("s.json"), *dump = path_in("dump"), *gout = path_in("g.txt");
    char *argv[] = {"splatref", "render", "--model", "builtin:sphere", "--points", "3000", "--size", "64x48", "--voronoi",
                    "--out", (char *)png, "--float", (char *)pfm, "--stats", (char *)js, "--dump", (char *)dump,
                    "--groups-out", (char *)gout, "--quiet", NULL};
    ck_assert_int_eq(run(argv, err, sizeof err), 0);
    ck_assert_int_eq(access(png, F_OK), 0);
    ck_assert_int_eq(access(pfm, F_OK), 0);
    ck_assert_int_eq(access(js, F_OK), 0);
    ck_assert_int_eq(access(gout, F_OK), 0);
    ck_assert_int_eq(access(path_in("dump/000_geometry_k000_color.pfm"), F_OK), 0);
    ck_assert_int_eq(access(path_in("dump/000_geometry_k000_weight.pfm"), F_OK), 0);
    /* a dumped plane as a picture */
    const char *shown = path_in("w.png");
    char *sargv[] = {"splatref", "show", (char *)path_in("dump/000_geometry_k000_weight.pfm"), "--out", (char *)shown, NULL};
    ck_assert_int_eq(run(sargv, err, sizeof err), 0);
    ck_assert_int_eq(access(shown, F_OK), 0);
    /* the float image is RGB, little-endian, 64×48 */
    float *im;
    int w, h, ch;
    spr_error e;
    ck_assert_int_eq(spr_read_pfm(pfm, &im, &w, &h, &ch, &e), SPR_OK);
    ck_assert_int_eq(w, 64);
    ck_assert_int_eq(h, 48);
    ck_assert_int_eq(ch, 3);
    free(im);
    /* the groups written are read back by --groups-file and give the same image */
    const char *png2 = path_in("s2.png");
    char *argv2[] = {"splatref", "render", "--model", "builtin:sphere", "--points", "3000", "--size", "64x48", "--voronoi",
                     "--out", (char *)png2, "--groups-file", (char *)gout, "--quiet", NULL};
    ck_assert_int_eq(run(argv2, err, sizeof err), 0);
    FILE *a = fopen(png, "rb"), *b = fopen(png2, "rb");
    char ba[65536], bb[65536];
    size_t na = fread(ba, 1, sizeof ba, a), nb = fread(bb, 1, sizeof bb, b);
    fclose(a);
    fclose(b);
    ck_assert_uint_eq(na, nb);
    ck_assert_mem_eq(ba, bb, na);
}
END_TEST

START_TEST(sample_then_info)
{
    setup_dir();
    char err[4096];
    const char *ply = path_in("bunny5k.ply");
    char *argv[] = {"splatref", "sample", "--model", (char *)tu_data("meshes/bunny00.off"), "--points", "5000", "--out", (char *)ply, "--quiet", NULL};
    ck_assert_int_eq(run(argv, err, sizeof err), 0);
    spr_cloud c;
    spr_error e;
    ck_assert_int_eq(spr_load(ply, NULL, &c, &e), SPR_OK);
    ck_assert_uint_eq(c.n, 5000);
    ck_assert_uint_eq(c.flags & (SPR_SRC_NORMALS | SPR_SRC_RADII | SPR_SRC_COLORS), SPR_SRC_NORMALS | SPR_SRC_RADII | SPR_SRC_COLORS);
    spr_cloud_free(&c);
    /* info describes the file it was given: the count and where each attribute came from */
    char *info[] = {"splatref", "info", "--model", (char *)ply, NULL};
    ck_assert_int_eq(tu_run(NULL, NULL, 1, info, err, sizeof err), 0);
    static const char *const lines[] = {"splats:   5000\n", "normals:  from the file\n", "colours:  from the file\n",
                                        "radii:    from the file\n", "opacity:  from the file\n"};
    for (size_t i = 0; i < sizeof lines / sizeof lines[0]; i++)
        ck_assert_msg(strstr(err, lines[i]) != NULL, "info lacks \"%s\":\n%s", lines[i], err);
    /* without a model it lists the registries */
    char *reg[] = {"splatref", "info", NULL};
    ck_assert_int_eq(tu_run(NULL, NULL, 1, reg, err, sizeof err), 0);
    for (int al = 0; al < SPR_ALGO__COUNT; al++) ck_assert_ptr_nonnull(strstr(err, spr_algo_name((spr_algo)al)));
    for (int op = 0; op < SPR_COMP__COUNT; op++) ck_assert_ptr_nonnull(strstr(err, spr_composite_info_of((spr_composite_op)op)->name));
    char *bad[] = {"splatref", "sample", "--model", (char *)tu_data("points_3/kitten.xyz"), "--points", "10", "--out", (char *)path_in("x.ply"), NULL};
    ck_assert_int_eq(run(bad, err, sizeof err), 2); /* a point file has no faces to sample */
    ck_assert_ptr_nonnull(strstr(err, "kitten.xyz"));
    ck_assert_int_ne(access(path_in("x.ply"), F_OK), 0);
}
END_TEST

START_TEST(group_command)
{
    setup_dir();
    char err[4096];
    const char *out = path_in("g.txt"), *js = path_in("g.json");
    char *argv[] = {"splatref", "group", "--model", "builtin:torus", "--points", "3000", "--method", "hash", "--mode", "2",
                    "--extend", "dup", "--out", (char *)out, "--stats", (char *)js, "--quiet", NULL};
    ck_assert_int_eq(run(argv, err, sizeof err), 0);
    FILE *f = fopen(out, "r");
    ck_assert_ptr_nonnull(f);
    unsigned idx, prev_k = 0;
    int k, lines = 0;
    while (fscanf(f, "%u %d", &idx, &k) == 2) {
        ck_assert_int_ge(k, (int)prev_k); /* memberships ordered by group */
        prev_k = (unsigned)k;
        lines++;
    }
    fclose(f);
    ck_assert_int_ge(lines, 2976); /* every splat, plus duplicates */
    /* the statistics agree with the memberships file: K, group sizes, the
     * membership count, and every one of the 2976 splats present */
    cJSON *root = tu_read_json(js);
    ck_assert_int_eq(cJSON_GetObjectItem(root, "K")->valueint, 8);
    ck_assert_int_eq(cJSON_GetObjectItem(root, "memberships")->valueint, lines);
    ck_assert_int_eq(cJSON_GetObjectItem(root, "splats")->valueint, 2976);
    int per_group[8] = {0};
    unsigned char *seen = calloc(2976, 1);
    f = fopen(out, "r");
    while (fscanf(f, "%u %d", &idx, &k) == 2) {
        ck_assert(idx < 2976 && k >= 0 && k < 8);
        seen[idx] = 1;
        per_group[k]++;
    }
    fclose(f);
    for (int i = 0; i < 2976; i++) ck_assert_msg(seen[i], "splat %d in no group", i);
    cJSON *sizes = cJSON_GetObjectItem(root, "group_sizes");
    ck_assert_int_eq(cJSON_GetArraySize(sizes), 8);
    for (int g = 0; g < 8; g++) ck_assert_int_eq(cJSON_GetArrayItem(sizes, g)->valueint, per_group[g]);
    ck_assert_double_gt(cJSON_GetObjectItem(root, "duplication_ratio")->valuedouble, 0.0);
    free(seen);
    cJSON_Delete(root);
    /* render reads the memberships back, duplicates included */
    char *rargv[] = {"splatref", "render", "--model", "builtin:torus", "--points", "3000", "--groups-file", (char *)out,
                     "--size", "64x64", "--out", (char *)path_in("gr.png"), "--quiet", NULL};
    ck_assert_int_eq(run(rargv, err, sizeof err), 0);
    char *bad[] = {"splatref", "group", "--model", "builtin:torus", "--method", "hash", "--mode", "3", "--out", (char *)path_in("x.txt"), NULL};
    ck_assert_int_eq(run(bad, err, sizeof err), 2); /* mode 3 without --hash-near */
    ck_assert_ptr_nonnull(strstr(err, "--hash-near"));
    ck_assert_int_ne(access(path_in("x.txt"), F_OK), 0);
}
END_TEST

/* --target 0,0,0 is used even though the model's centre is elsewhere.  Two
 * splats (radius 0.3, normals +z): red at the origin, green at (4,0,0), so
 * the model centre is (2,0,0).  Eye (0,0,10) looking at the origin with a
 * 60° field of view on 64×64: the image centre (pixels 31..32) sees the
 * origin, and the red splat covers ±0.3/(10·tan 30°)·32 ≈ ±1.7 px around
 * it; looking at (2,0,0) instead, the centre would see empty space 2 units
 * from either splat (background). */
START_TEST(explicit_origin_target_is_used)
{
    setup_dir();
    const char *ply = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                      "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\n"
                      "property uchar blue\nproperty float radius\nend_header\n0 0 0 0 0 1 255 0 0 0.3\n4 0 0 0 0 1 0 255 0 0.3\n";
    write_text("two.ply", ply, strlen(ply));
    char err[4096];
    char *argv[] = {"splatref", "render", "--model", (char *)path_in("two.ply"), "--algo", "pbr2p1", "--eye", "0,0,10",
                    "--target", "0,0,0", "--fov", "60", "--size", "64x64", "--out", (char *)path_in("o.png"), "--float",
                    (char *)path_in("o.pfm"), "--quiet", NULL};
    ck_assert_int_eq(run(argv, err, sizeof err), 0);
    float *im;
    int w, h, ch;
    spr_error e = {0};
    ck_assert_int_eq(spr_read_pfm(path_in("o.pfm"), &im, &w, &h, &ch, &e), SPR_OK);
    for (int y = 31; y <= 32; y++)
        for (int x = 31; x <= 32; x++) {
            const float *px = im + ((size_t)y * w + x) * ch;
            ck_assert_msg(px[0] == 1.0f && px[1] == 0.0f && px[2] == 0.0f, "pixel (%d,%d) = %g %g %g, expected red", x, y, px[0],
                          px[1], px[2]);
        }
    free(im);
}
END_TEST

/* An option the command, algorithm or grouping does not read is refused
 * with one line naming it, for every subcommand. */
/* The transparency and shading options say what is wrong in one line and
 * write nothing: a missing cube-map face (named), values out of range,
 * images of different sizes for compare. */
START_TEST(transparency_options)
{
    setup_dir();
    const char *out = path_in("t.png");
    static const struct { const char *argv[10]; const char *says; } cases[] = {
        {{"render", "--algo", "transparent2", "--env", "/nonexistent/faces"}, "/nonexistent/faces/px.png"},
        {{"render", "--algo", "transparent2", "--env", "sky", "--eta", "0.5,0.6"}, "--eta"},
        {{"render", "--algo", "transparent2", "--env", "sky", "--env-layers", "many"}, "--env-layers"},
        {{"render", "--algo", "depthpeel", "--layers", "0"}, "--layers"},
        {{"render", "--algo", "pbr2p1", "--shade", "gouraud"}, "--shade"},
        {{"render", "--algo", "pbr2p1", "--shade", "phong", "--material", "0.1,0.2,0.3,0"}, "--material"},
        {{"render", "--algo", "pbr2p1", "--shade", "phong", "--light", "0,0,0"}, "--light"},
        {{"render", "--model", "builtin:sphere", "--balls", "65"}, "--balls"},
        {{"render", "--model", "builtin:sphere", "--balls", "64"}, "room for only"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char err[4096];
        int rc = run_args(cases[i].argv, out, err, sizeof err);
        printf("cli: %s %s: exit %d: %s", cases[i].argv[1], cases[i].argv[2], rc, err);
        ck_assert_msg(rc != 0 && rc < 128, "%s: exit %d", cases[i].says, rc);
        ck_assert_msg(strstr(err, cases[i].says) && one_line(err), "%s: %s", cases[i].says, err);
        ck_assert_msg(access(out, F_OK) != 0, "%s: an image was written", cases[i].says);
    }
    /* compare: two renders of different sizes */
    char *r1[] = {"splatref", "render", "--model", "builtin:sphere", "--points", "500", "--size", "16x16", "--out", (char *)path_in("a.png"), "--quiet", NULL};
    char *r2[] = {"splatref", "render", "--model", "builtin:sphere", "--points", "500", "--size", "16x12", "--out", (char *)path_in("b.png"), "--quiet", NULL};
    char err[4096];
    ck_assert_int_eq(run(r1, err, sizeof err), 0);
    ck_assert_int_eq(run(r2, err, sizeof err), 0);
    char *cmp[] = {"splatref", "compare", (char *)path_in("a.png"), (char *)path_in("b.png"), "--metric", "zp-eps", NULL};
    int rc = run(cmp, err, sizeof err);
    printf("cli: compare 16x16 16x12: exit %d: %s", rc, err);
    ck_assert_msg(rc == 2 && strstr(err, "16x12") && one_line(err), "compare: exit %d: %s", rc, err);
}
END_TEST

/* domains --basis-out: one line per point in input order, "x y z strict
 * j:phi …", the phis summing to 1 and the strict domain their argmax;
 * --stats prints one row per level; --basis-out without --level is refused. */
START_TEST(domains_command)
{
    setup_dir();
    const char *out = path_in("basis.txt");
    const char *args[] = {"domains", "--model", "builtin:octahedron", "--points", "2000", "--stats", "--level", "2", "--basis-out", out, NULL};
    char err[4096];
    int rc = run_args(args, NULL, err, sizeof err);
    ck_assert_msg(rc == 0, "domains: exit %d: %s", rc, err);
    FILE *f = fopen(out, "r");
    ck_assert_ptr_nonnull(f);
    char line[4096];
    int lines = 0;
    while (fgets(line, sizeof line, f)) {
        double x, y, z;
        int strict, used;
        ck_assert_int_eq(sscanf(line, "%lf %lf %lf %d%n", &x, &y, &z, &strict, &used), 4);
        double sum = 0.0, best = -1.0;
        int arg = -1, j;
        double phi;
        char *p = line + used;
        int k;
        while (sscanf(p, " %d:%lf%n", &j, &phi, &k) == 2) {
            sum += phi;
            if (phi > best) best = phi, arg = j;
            p += k;
        }
        ck_assert_msg(fabs(sum - 1.0) < 1e-6, "line %d: phis sum to %.9g", lines + 1, sum);
        ck_assert_int_eq(arg, strict);
        lines++;
    }
    fclose(f);
    ck_assert_int_ge(lines, 1500); /* the octahedron of 2000 points: 8·m² sub-triangles */
    const char *bad[] = {"domains", "--model", "builtin:octahedron", "--points", "500", "--basis-out", out, NULL};
    rc = run_args(bad, NULL, err, sizeof err);
    ck_assert_msg(rc == 2 && strstr(err, "--level") && one_line(err), "exit %d: %s", rc, err);
    /* --dump: the coloured cloud and the level's textures, 8 faces side by side in one atlas */
    const char *ply = path_in("dom.ply"), *atlas = path_in("dom-atlas.png");
    const char *dump[] = {"domains", "--model", "builtin:octahedron", "--points", "2000", "--level", "2", "--domain", "strict", "--dump", ply, NULL};
    rc = run_args(dump, NULL, err, sizeof err);
    ck_assert_msg(rc == 0, "domains --dump: exit %d: %s", rc, err);
    float *img = NULL;
    int w = 0, h = 0, ch = 0;
    spr_error e = {0};
    ck_assert_msg(spr_read_png(atlas, &img, &w, &h, &ch, &e) == SPR_OK, "%s", e.msg);
    ck_assert_msg(w > 8 * 3 && h > 2 && ch == 4, "atlas %dx%d, %d channels", w, h, ch);
    free(img);
    /* a domain method renders; domain options are refused where no domain algorithm reads them */
    const char *png = path_in("dom.png");
    const char *draw[] = {"render", "--model", "builtin:octahedron", "--points", "2000", "--algo", "domain-prefix", "--level", "2", "--size", "64x64", NULL};
    rc = run_args(draw, png, err, sizeof err);
    ck_assert_msg(rc == 0 && access(png, F_OK) == 0, "render domain-prefix: exit %d: %s", rc, err);
    const char *unused[] = {"render", "--model", "builtin:octahedron", "--points", "500", "--algo", "pbr2p1", "--level", "2", NULL};
    rc = run_args(unused, png, err, sizeof err);
    ck_assert_msg(rc == 2 && strstr(err, "--level"), "exit %d: %s", rc, err);
}
END_TEST

START_TEST(unused_options_are_refused)
{
    setup_dir();
    static const struct { const char *argv[8]; const char *names; } cases[] = {
        {{"group", "--model", "builtin:sphere", "--eps", "1"}, "--eps"},
        {{"group", "--model", "builtin:sphere", "--kernel", "linear"}, "--kernel"},
        {{"group", "--model", "builtin:sphere", "--voronoi"}, "--voronoi"},
        {{"group", "--model", "builtin:sphere", "--method", "hash", "--c", "0.5"}, "--c"},
        {{"group", "--model", "builtin:sphere", "--eye", "1,2,3"}, "--eye"},
        {{"render", "--algo", "pbr2p1", "--voronoi"}, "--voronoi"},
        {{"render", "--algo", "pbr2p1", "--groups", "hash"}, "--groups"},
        {{"render", "--groups", "hash", "--c", "0.5"}, "--c"},
        {{"render", "--groups", "mgc", "--mode", "2"}, "--mode"},
        {{"render", "--lowres-n", "16"}, "--lowres-n"},
        {{"render", "--model", "x.ply", "--points", "100"}, "--points"},
        {{"parity", "--algo", "pbr2p1", "--k", "4"}, "--k"},
        {{"info", "--model", "x.ply", "--points", "100"}, "--points"},
        {{"bench", "--scene", "bunny", "--points", "1000"}, "--points"},
        {{"bench", "--scene", "grouping", "--size", "64x64"}, "--size"},
        {{"render", "--backend", "cpu", "--gl-device", "0"}, "--gl-device"},
        {{"reference", "--update", "--only", "none", "--gl-device", "0"}, "--gl-device"},
        {{"render", "--backend", "cpu", "--gl-driver", "zink"}, "--gl-driver"},
        {{"parity", "--gl-driver", "zink", "--gl-device", "0"}, "--gl-driver zink runs on the surfaceless platform, not on --gl-device 0"},
        {{"render", "--algo", "zbuffer", "--shade", "phong"}, "--shade"},
        {{"render", "--algo", "deferred", "--env", "sky"}, "--env"},
        {{"render", "--algo", "pbr2p1", "--layers", "3"}, "--layers"},
        {{"render", "--algo", "pbr2p1", "--light", "1,0,0"}, "--light"},
        {{"render", "--algo", "transparent2", "--eta", "0.5"}, "--eta"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char err[4096];
        int rc = run_args(cases[i].argv, NULL, err, sizeof err);
        printf("cli: %s ... %s: exit %d: %s", cases[i].argv[0], cases[i].names, rc, err);
        ck_assert_msg(rc == 2, "%s %s: exit %d", cases[i].argv[0], cases[i].names, rc);
        ck_assert_msg(strstr(err, cases[i].names) && one_line(err), "%s: %s", cases[i].names, err);
    }
}
END_TEST

/* render --trace writes the backend calls of SPEC §4.1 in order: a
 * visibility draw (LESS on d_f + eps_t, depth write on), a blend draw
 * (LEQUAL on d_f, no depth write, add), one normalise composite, a read. */
START_TEST(trace_lists_the_passes_in_order)
{
    setup_dir();
    char err[4096];
    char *argv[] = {"splatref", "render", "--algo", "pbr2p1", "--size", "64x64", "--out", (char *)path_in("t.png"), "--trace",
                    (char *)path_in("t.txt"), "--quiet", NULL};
    ck_assert_int_eq(run(argv, err, sizeof err), 0);
    char *txt;
    size_t len;
    spr_error e = {0};
    ck_assert_int_eq(spr__read_file(path_in("t.txt"), &txt, &len, &e), SPR_OK);
    static const char *const want[] = {"set_view 64x64", "target_create t0", "draw t0:", "test LESS d_f+eps_t, depth write on",
                                       "draw t0:", "test LEQUAL d_f, depth write off, blend rgb add alpha add",
                                       "composite normalize of t0 -> t1", "read t1 color"};
    const char *at = txt;
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        const char *hit = strstr(at, want[i]);
        ck_assert_msg(hit != NULL, "trace lacks \"%s\" after offset %td:\n%s", want[i], at - txt, txt);
        at = hit + strlen(want[i]);
    }
    free(txt);
}
END_TEST

/* A command that fails after it began writing a dump directory leaves no
 * directory behind (files go to DIR.tmpPID first); one that succeeds
 * leaves the whole dump. */
START_TEST(no_partial_dump_directory)
{
    setup_dir();
    char err[4096];
    const char *dump = path_in("dump_fail");
    char *argv[] = {"splatref", "render", "--size", "32x32", "--out", (char *)path_in("p.png"), "--dump", (char *)dump, "--stats",
                    "/nonexistent/dir/s.json", "--quiet", NULL};
    int before = count_files();
    ck_assert_int_eq(run(argv, err, sizeof err), 2);
    ck_assert_ptr_nonnull(strstr(err, "s.json"));
    ck_assert_int_ne(access(dump, F_OK), 0);
    ck_assert_int_eq(count_files(), before + 1); /* the PNG, written before the failing stats; no dump, no temporary */
    argv[8] = "--float";
    argv[9] = (char *)path_in("p.pfm");
    ck_assert_int_eq(run(argv, err, sizeof err), 0);
    ck_assert_int_eq(access(path_in("dump_fail/000_geometry_k000_color.pfm"), F_OK), 0);
}
END_TEST

/* One line, not libpng's own (issue 42).  libpng's default handlers print "libpng error: Write Error" /
 * "libpng warning: …" on stderr before the command's line. */

/* Exactly one line on stderr, naming `path`, with what libpng said and none of libpng's own lines. */
static void expect_libpng_line(const char *what, const char *err, const char *path)
{
    ck_assert_msg(one_line(err), "%s: not exactly one line: [%s]", what, err);
    ck_assert_msg(!strstr(err, "libpng error") && !strstr(err, "libpng warning"), "%s: a line of libpng's own: [%s]", what, err);
    ck_assert_msg(strstr(err, path) && strstr(err, "(libpng: "), "%s: the line lacks the file or libpng's text: [%s]", what, err);
}

/* A full disk: render's PNG under a 1 KiB RLIMIT_FSIZE with SIGXFSZ ignored (set by sh in the child only), so its
 * writes fail with EFBIG as they do with ENOSPC on a full filesystem: exit 2, one line, no PNG, no temporary. */
START_TEST(full_disk_is_one_line)
{
    setup_dir();
    char err[4096];
    const char *out = path_in("x.png");
    char *argv[] = {"sh", "-c", "trap '' XFSZ; ulimit -f 2; exec \"$0\" \"$@\"", SPR_CLI, "render", "--size", "256x256", "--out", (char *)out, "--quiet", NULL};
    int rc = tu_run("/bin/sh", NULL, 0, argv, err, sizeof err);
    printf("cli: full disk: exit %d: %s", rc, err);
    ck_assert_msg(rc == 2, "full disk: exit status %d: %s", rc, err);
    expect_libpng_line("full disk", err, out);
    ck_assert_msg(count_files() == 0, "full disk: %d files left in %s", count_files(), dir);
}
END_TEST

/* The first chunk type `tag` in the n bytes of a PNG at b (NULL: none); memmem is not C11. */
static const char *png_chunk(const char *b, size_t n, const char *tag)
{
    for (size_t i = 0; i + 4 <= n; i++)
        if (!memcmp(b + i, tag, 4)) return b + i;
    return NULL;
}

/* Reading PNGs (check): image data that libpng refuses is one line naming the file; a chunk libpng only warns about
 * (an ancillary tEXt with a wrong CRC) is no line at all. */
START_TEST(damaged_png_is_one_line)
{
    setup_dir();
    char err[4096];
    const char *png = path_in("t.png"), *scene = path_in("s.json");
    char *render[] = {"splatref", "render", "--model", "builtin:torus", "--points", "500", "--size", "5x5", "--out", (char *)png, "--save-scene",
                      (char *)scene, "--quiet", NULL};
    ck_assert_int_eq(run(render, err, sizeof err), 0);
    char *b;
    size_t n;
    spr_error e = {0};
    ck_assert_int_eq(spr__read_file(png, &b, &n, &e), SPR_OK);
    const char *idat = png_chunk(b, n, "IDAT"), *iend = png_chunk(b, n, "IEND");
    ck_assert(idat && iend && idat + 7 < iend);
    const size_t deflate0 = (size_t)(idat - b) + 6; /* the first deflate byte after the zlib header */
    b[deflate0] ^= 0xff;
    write_text("bad.png", b, n);
    b[deflate0] ^= 0xff;
    const size_t at = (size_t)(iend - 4 - b); /* a tEXt chunk before IEND whose CRC is 0 */
    write_text("warn.png", b, at);
    FILE *f = fopen(path_in("warn.png"), "ab");
    ck_assert(f && fwrite("\0\0\0\4tEXtab\0c\0\0\0\0", 1, 16, f) == 16 && fwrite(b + at, 1, n - at, f) == n - at && !fclose(f));
    free(b);
    const char *bad = path_in("bad.png"), *warn = path_in("warn.png");
    char *check[] = {"splatref", "check", "--scene", (char *)scene, "--image", (char *)bad, "--out", (char *)path_in("r1"), "--quiet", NULL};
    int rc = run(check, err, sizeof err);
    printf("cli: damaged PNG: exit %d: %s", rc, err);
    ck_assert_msg(rc == 2, "damaged PNG: exit status %d: %s", rc, err);
    expect_libpng_line("damaged PNG", err, bad);
    check[5] = (char *)warn;
    check[7] = (char *)path_in("r2");
    rc = run(check, err, sizeof err);
    ck_assert_msg(rc == 0 && !err[0], "PNG with a warning: exit status %d: [%s]", rc, err);
}
END_TEST

START_TEST(no_gl_context)
{
    /* No EGL vendor at all: render --backend gl fails with one line and no
     * file; the GL suite reports "skipped" (77) with the reason. */
    setup_dir();
    char err[4096];
    const char *out = path_in("gl.png");
    char *argv[] = {"splatref", "render", "--backend", "gl", "--out", (char *)out, "--quiet", NULL};
    int rc = tu_run(NULL, "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent", 0, argv, err, sizeof err);
    printf("cli: no GL context: exit %d: %s", rc, err);
    ck_assert_int_eq(rc, 2);
    ck_assert_ptr_nonnull(strstr(err, "gl: "));
    ck_assert(one_line(err));
    ck_assert_int_ne(access(out, F_OK), 0);
    char *targv[] = {"splatref_tests", "gl", NULL};
    setenv("SPLATREF_REQUIRE_GL", "0", 1); /* this process runs forked: CI's setting is restored after */
    rc = tu_run("/proc/self/exe", "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent", 1, targv, err, sizeof err);
    ck_assert_int_eq(rc, 77);
    ck_assert_ptr_nonnull(strstr(err, "gl: skipped (no device"));
    /* where a context is required (CI), the same situation is a failure */
    setenv("SPLATREF_REQUIRE_GL", "1", 1);
    rc = tu_run("/proc/self/exe", "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent", 1, targv, err, sizeof err);
    ck_assert_int_eq(rc, 1);
    ck_assert_ptr_nonnull(strstr(err, "gl: FAILED (no device"));
}
END_TEST

/* Bytes of a file (NULL when unreadable); *n its length. */
static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    rewind(f);
    unsigned char *b = malloc((size_t)len + 1);
    *n = fread(b, 1, (size_t)len, f);
    fclose(f);
    return b;
}

/* Every file of dump directory a equals the same name in b; returns how many. */
static int same_dumps(const char *a, const char *b, const char *what)
{
    DIR *d = opendir(a);
    ck_assert_ptr_nonnull(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        char pa[512], pb[512];
        snprintf(pa, sizeof pa, "%s/%s", a, e->d_name);
        snprintf(pb, sizeof pb, "%s/%s", b, e->d_name);
        ck_assert_msg(access(pb, F_OK) == 0, "%s: --stream wrote no %s", what, e->d_name);
        ck_assert_msg(tu_same_file(pa, pb), "%s: %s differs between the whole cloud and --stream", what, e->d_name);
        n++;
    }
    closedir(d);
    return n;
}

/* A cloud drawn chunk by chunk (--stream, chunks of 97 splats, so group
 * members and chunks interleave) gives every plane of every pass with the
 * same bits as the whole cloud loaded at once: ids (id_base), colours,
 * depths, counts; and what cannot stream is refused with one line. */
START_TEST(stream_equals_whole_cloud)
{
    setup_dir();
    spr_cloud c = tu_builtin("builtin:torus", 3000);
    spr_error e = {0};
    ck_assert_int_eq(spr_write_ply(path_in("t.ply"), &c, &e), SPR_OK);
    static const char *const variants[][8] = {
        {"pbr2p1", NULL},
        {"pbr2p1", "--shade", "phong", NULL},
        {"deferred", "--groups", "hash", NULL},
        {"deferred", "--groups", "hash", "--voronoi", "--mode", "2", NULL},
        {"deferred", "--groups", "none", NULL},
        {"deferred", "--groups", "hash", "--extend", "radius", NULL},
        {"zbuffer", NULL},
        {"depthpeel", "--layers", "3", NULL},
    };
    char err[4096];
    int planes = 0;
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        for (int st = 0; st < 2; st++) {
            char dump[128], pfm[128];
            snprintf(dump, sizeof dump, "%s/d%zu_%d", dir, v, st);
            snprintf(pfm, sizeof pfm, "%s/f%zu_%d.pfm", dir, v, st);
            const char *args[20] = {"render", "--model", path_in("t.ply"), "--size", "64x48", "--dump", dump, "--float", pfm, "--algo"};
            int n = 10;
            for (int k = 0; variants[v][k]; k++) args[n++] = variants[v][k];
            if (st) args[n++] = "--stream", args[n++] = "--chunk", args[n++] = "97";
            char *argv[24] = {"splatref"};
            for (int k = 0; k < n; k++) argv[k + 1] = (char *)args[k];
            argv[n + 1] = "--quiet";
            argv[n + 2] = NULL;
            ck_assert_msg(run(argv, err, sizeof err) == 0, "%s%s: %s", variants[v][0], st ? " --stream" : "", err);
        }
        char a[128], b[128];
        snprintf(a, sizeof a, "%s/d%zu_0", dir, v);
        snprintf(b, sizeof b, "%s/d%zu_1", dir, v);
        int k = same_dumps(a, b, variants[v][0]);
        snprintf(a, sizeof a, "%s/f%zu_0.pfm", dir, v);
        snprintf(b, sizeof b, "%s/f%zu_1.pfm", dir, v);
        ck_assert_msg(tu_same_file(a, b), "%s: final images differ", variants[v][0]);
        ck_assert_int_gt(k, 3);
        planes += k;
    }
    printf("cli: --stream (chunks of 97 of 3000 splats), %zu variants: %d dumped planes identical to the whole cloud's\n",
           sizeof variants / sizeof variants[0], planes);

    /* what cannot stream, and bad files, refused with one line and no output */
    static const char *const bad[][6] = {
        {"transparent1", "--groups", "hash", NULL, "needs the whole cloud"},
        {"deferred", NULL, "overlap graph"},
        {"domain-twopass", NULL, "needs the whole cloud"},
    };
    for (size_t v = 0; v < sizeof bad / sizeof bad[0]; v++) {
        const char *args[16] = {"render", "--model", path_in("t.ply"), "--stream", "--algo"};
        int n = 5, k = 0;
        for (; k < 5 && bad[v][k]; k++) args[n++] = bad[v][k];
        const char *must = k == 5 ? bad[v][5] : bad[v][k + 1];
        args[n] = NULL;
        int before = count_files();
        int rc = run_args(args, path_in("bad.png"), err, sizeof err);
        printf("cli: --stream %s: exit %d: %s", bad[v][0], rc, err);
        ck_assert_msg(rc == 2 && strstr(err, must) && one_line(err), "%s: %s", bad[v][0], err);
        ck_assert_int_eq(count_files(), before);
    }
    /* a NaN at splat 2500 (in the 26th chunk): found while reading, before any output, by position */
    {
        size_t len;
        unsigned char *b = slurp(path_in("t.ply"), &len);
        const char *eh = strstr((const char *)b, "end_header\n");
        size_t body = (size_t)(eh - (const char *)b) + 11, at = body + 2500 * 32 + 4;
        const float nan = NAN;
        memcpy(b + at, &nan, 4);
        write_text("nan.ply", (const char *)b, len);
        free(b);
        char pos[64];
        snprintf(pos, sizeof pos, "byte %zu: vertex 2500: coordinate y", at);
        const char *args[] = {"render", "--model", path_in("nan.ply"), "--stream", "--chunk", "97", "--algo", "pbr2p1", NULL};
        int rc = run_args(args, path_in("bad.png"), err, sizeof err);
        printf("cli: --stream NaN: exit %d: %s", rc, err);
        ck_assert_msg(rc == 2 && strstr(err, pos), "%s", err);
        ck_assert_int_ne(access(path_in("bad.png"), F_OK), 0);
    }
    const char *ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n";
    write_text("a.ply", ascii, strlen(ascii));
    static const char *const files[][3] = {{"a.ply", "--stream", "binary PLY"},
                                           {"nor.ply", "--stream", "needs normals and radii"},
                                           {"t.ply", "--chunk=5", "--chunk goes with --stream"}};
    c.flags = 0;
    ck_assert_int_eq(spr_write_ply(path_in("t2.ply"), &c, &e), SPR_OK);
    {
        /* the same cloud without its radius column: PLY from the header only */
        size_t len;
        unsigned char *b = slurp(path_in("t2.ply"), &len);
        char *p = strstr((char *)b, "property float radius\n");
        memcpy(p, "property float weight\n", 22);
        write_text("nor.ply", (const char *)b, len);
        free(b);
    }
    for (int v = 0; v < 3; v++) {
        const char *args[] = {"render", "--model", path_in(files[v][0]), "--algo", "pbr2p1", files[v][1], NULL};
        int rc = run_args(args, path_in("bad.png"), err, sizeof err);
        printf("cli: %s %s: exit %d: %s", files[v][0], files[v][1], rc, err);
        ck_assert_msg(rc == 2 && strstr(err, files[v][2]) && one_line(err), "%s", err);
        ck_assert_int_ne(access(path_in("bad.png"), F_OK), 0);
    }
    spr_cloud_free(&c);
}
END_TEST

/* --gauss-profile (SPEC 10.9): unknown names, another skeleton's --algo, both names at once, explain --vs's bad
 * names are one line with no output; the old name is saved under the new one and gives the same image. */
START_TEST(gauss_profile_options)
{
    char model[600];
    snprintf(model, sizeof model, "%s/tests/data/captures/splat-transform/2.7.1/sheet.ply", SPR_SOURCE_DIR);
    char err[4096];
    char *unknown[] = {"splatref", "render", "--model", model, "--gauss-profile", "unity", "--out", (char *)path_in("o.png"), NULL};
    ck_assert_int_eq(run(unknown, err, sizeof err), 2);
    ck_assert_msg(strstr(err, "--gauss-profile: 'unity' is not a profile (inria, gsplat") && one_line(err), "%s", err);
    char *two[] = {"splatref", "render", "--model", model, "--gauss-profile", "spark", "--algo", "gauss3d", "--out", (char *)path_in("o.png"), NULL};
    ck_assert_int_eq(run(two, err, sizeof err), 2);
    ck_assert_msg(strstr(err, "--gauss-profile spark belongs to --algo gauss-blend, not gauss3d"), "%s", err);
    ck_assert_int_ne(access(path_in("o.png"), F_OK), 0);
    char *both[] = {"splatref", "render", "--model", model, "--gauss-profile", "gsplat", "--gauss-flavor", "gsplat", NULL};
    ck_assert_int_eq(run(both, err, sizeof err), 2);
    ck_assert_msg(strstr(err, "old name of --gauss-profile"), "%s", err);
    char *vs[] = {"splatref", "explain", "--model", model, "--gauss-profile", "inria", "--vs", "nope", "--pixel", "1,1", NULL};
    ck_assert_int_eq(run(vs, err, sizeof err), 2);
    ck_assert_msg(strstr(err, "--vs: 'nope' is not a profile"), "%s", err);
    /* the alias: saved as gauss-profile, and the scene file gives the same image */
    const char *old[] = {"render", "--model", model, "--gauss-flavor", "gsplat-1.5", "--size", "48x40", "--save-scene", path_in("s.json"), NULL};
    ck_assert_int_eq(run_args(old, path_in("a.png"), err, sizeof err), 0);
    char text[8192] = "";
    FILE *f = fopen(path_in("s.json"), "rb");
    ck_assert_ptr_nonnull(f);
    text[fread(text, 1, sizeof text - 1, f)] = 0;
    fclose(f);
    ck_assert_msg(strstr(text, "\"gauss-profile\":\t\"gsplat-1.5\"") && !strstr(text, "flavor"), "%s", text);
    const char *again[] = {"render", "--scene", path_in("s.json"), NULL};
    ck_assert_int_eq(run_args(again, path_in("b.png"), err, sizeof err), 0);
    ck_assert_msg(tu_same_file(path_in("a.png"), path_in("b.png")), "the saved scene draws another image");
}
END_TEST

/* ---- gradients (issue 43 item 3): check --grads and explain --gaussian G --grad ---- */

/* The scene of the gradient tests: 256 Gaussians of a sheet at 48x40, gauss3d, and an upstream gradient
 * dL/dimage (float32 [40, 48, 3], a fixed pattern of both signs) in up.npy. */
#define GRAD_SCENE "--algo", "gauss3d", "--size", "48x40", "--dl-dimage", (char *)path_in("up.npy")
static const char *grad_model(void)
{
    static char model[600];
    snprintf(model, sizeof model, "%s/tests/data/captures/splat-transform/2.7.1/sheet.ply", SPR_SOURCE_DIR);
    return model;
}

static void grad_upstream(void)
{
    static float g[40 * 48 * 3];
    for (size_t i = 0; i < sizeof g / sizeof g[0]; i++) g[i] = (float)(((i * 2654435761u) >> 7) % 2001) / 1000.0f - 1.0f;
    spr_npy a = {.ndim = 3, .shape = {40, 48, 3}, .type = SPR_NPY_F4, .data = g};
    spr_error e = {0};
    ck_assert_msg(spr_npy_write(path_in("up.npy"), &a, &e) == SPR_OK, "%s", e.msg);
}

/* `splatref grad` of the scene into name. */
static void grad_npz(const char *name)
{
    char err[4096];
    const char *args[] = {"grad", "--model", grad_model(), GRAD_SCENE, NULL};
    const int rc = run_args(args, path_in(name), err, sizeof err);
    ck_assert_msg(rc == 0, "grad: exit %d: %s", rc, err);
}

/* The upstream gradient written, `splatref grad` of the scene into g.npz, and its arrays read: *a (spr_npz_free it), their count. */
static int grad_arrays(spr_npy **a)
{
    grad_upstream();
    grad_npz("g.npz");
    int n = 0;
    spr_error e = {0};
    ck_assert_msg(spr_npz_read(path_in("g.npz"), a, &n, &e) == SPR_OK, "%s", e.msg);
    return n;
}

/* How many times what occurs in s. */
static int count_of(const char *s, const char *what)
{
    int n = 0;
    for (const char *p = s; (p = strstr(p, what)); p++) n++;
    return n;
}

/* The end of a long output, for a failure's message (Check's messages are short). */
static const char *tail(const char *s)
{
    const size_t n = strlen(s);
    return n > 1500 ? s + n - 1500 : s;
}

static spr_npy *npz_member(spr_npy *a, int n, const char *name)
{
    for (int k = 0; k < n; k++)
        if (!strcmp(a[k].name, name)) return &a[k];
    ck_abort_msg("no member %s", name);
    return NULL;
}

/* check --grads THEIRS (extra: one more option and its value, or NULL) with stdout and stderr into out. */
static int check_grads(const char *theirs, const char *extra, const char *value, char *out, size_t cap)
{
    char *argv[24] = {"splatref", "check", "--model", (char *)grad_model(), "--algo", "gauss3d", "--size", "48x40", "--dl-dimage", (char *)path_in("up.npy"),
                      "--grads", (char *)theirs, "--quiet", NULL};
    int n = 13;
    if (extra) argv[n++] = (char *)extra, argv[n++] = (char *)value;
    argv[n] = NULL;
    return tu_run(NULL, NULL, 1, argv, out, cap);
}

/* (a) the reference's own .npz passes; (b) one value of one Gaussian changed fails, naming it, in the text and the
 * JUnit report; (c) a missing array, a wrong shape, an integer array are refused in one line (exit 2). */
START_TEST(check_grads_verdicts)
{
    static char out[1 << 16];
    spr_npy *a = NULL;
    const int n = grad_arrays(&a);
    spr_error e = {0};
    int rc = check_grads(path_in("g.npz"), "--junit", path_in("ok.xml"), out, sizeof out);
    ck_assert_msg(rc == 0 && strstr(out, "verdict: PASS (11 arrays"), "own gradients: exit %d: %s", rc, tail(out));
    ck_assert_msg(strstr(out, "check: means: 256 Gaussians, 0 fail, max |diff| 0") && strstr(out, "check: counts: 256 Gaussians, 0 fail"), "%s", tail(out));
    ck_assert_int_eq(n, 11);
    /* (b) opacities of Gaussian 37, 1% off (far beyond rtol 2^-10 of the value itself) */
    spr_npy *op = npz_member(a, n, "opacities");
    float *o = op->data;
    const float keep = o[37];
    ck_assert_msg(keep != 0.0f, "Gaussian 37 has no opacity gradient to change");
    o[37] = keep * 1.01f;
    ck_assert_msg(spr_npz_write(path_in("m.npz"), a, n, &e) == SPR_OK, "%s", e.msg);
    o[37] = keep;
    rc = check_grads(path_in("m.npz"), "--junit", path_in("bad.xml"), out, sizeof out);
    ck_assert_msg(rc == 1 && strstr(out, "check: opacities: 256 Gaussians, 1 fail") && strstr(out, "worst Gaussian 37 ") &&
                      strstr(out, "check:   opacities Gaussian 37: ref ") && strstr(out, "verdict: FAIL (opacities;"),
                  "one changed value: exit %d: %s", rc, tail(out));
    ck_assert_msg(strstr(out, "check: colors: 256 Gaussians, 0 fail"), "%s", tail(out));
    size_t len = 0;
    char *xml = NULL;
    ck_assert_int_eq(spr__read_file(path_in("bad.xml"), &xml, &len, &e), SPR_OK);
    ck_assert_msg(strstr(xml, "tests=\"11\" failures=\"1\"") && strstr(xml, "name=\"opacities\""), "%s", xml);
    free(xml);
    /* and the same file passes with a tolerance wide enough (the option is printed in the verdict) */
    rc = check_grads(path_in("m.npz"), "--rtol", "0.05", out, sizeof out);
    ck_assert_msg(rc == 0 && strstr(out, "verdict: PASS (11 arrays; rtol 0.05,"), "--rtol 0.05: exit %d: %s", rc, tail(out));
    /* (c) refused in one line: a missing array, a wrong shape, an integer array where float is expected */
    spr_npy *m = npz_member(a, n, "means"), *c = npz_member(a, n, "colors");
    spr_npy fewer[11];
    int k = 0;
    for (int i = 0; i < n; i++)
        if (strcmp(a[i].name, "conics")) fewer[k++] = a[i];
    ck_assert_int_eq(spr_npz_write(path_in("missing.npz"), fewer, k, &e), SPR_OK);
    rc = check_grads(path_in("missing.npz"), NULL, NULL, out, sizeof out);
    ck_assert_msg(rc == 2 && one_line(out) && strstr(out, "has no array 'conics' (expected [256, 3];"), "missing: exit %d: %s", rc, tail(out));
    m->ndim = 1, m->shape[0] = 768;
    ck_assert_int_eq(spr_npz_write(path_in("shape.npz"), a, n, &e), SPR_OK);
    m->ndim = 2, m->shape[0] = 256;
    rc = check_grads(path_in("shape.npz"), NULL, NULL, out, sizeof out);
    ck_assert_msg(rc == 2 && one_line(out) && strstr(out, "means has shape [768]; expected [256, 3]"), "shape: exit %d: %s", rc, tail(out));
    c->type = SPR_NPY_I4;
    ck_assert_int_eq(spr_npz_write(path_in("int.npz"), a, n, &e), SPR_OK);
    rc = check_grads(path_in("int.npz"), NULL, NULL, out, sizeof out);
    ck_assert_msg(rc == 2 && one_line(out) && strstr(out, "colors is an integer array of shape [256, 3]; expected float"), "int: exit %d: %s", rc, tail(out));
    spr_npz_free(a, n);
}
END_TEST

/* explain --gaussian G --grad: G's pixels with their terms, in the backward's order, and sums that are splatref
 * grad's values to the bit (read from both: the printed %.9g sums and the .npz). */
START_TEST(explain_grad_sums_to_the_bit)
{
    static char out[1 << 20];
    spr_npy *a = NULL;
    const int n = grad_arrays(&a);
    const size_t G = 58; /* 54 pixels in 4 tiles of this scene */
    char *argv[] = {"splatref", "explain", "--model", (char *)grad_model(), GRAD_SCENE, "--gaussian", "58", "--grad", "--quiet", NULL};
    const int rc = tu_run(NULL, NULL, 1, argv, out, sizeof out);
    const int tiles = count_of(out, "\ntile "), pixels = count_of(out, "\n  pixel x ");
    ck_assert_msg(tiles >= 2 && pixels >= 2, "%d tiles, %d pixels: %s", tiles, pixels, tail(out));
    const int32_t *counts = npz_member(a, n, "counts")->data;
    ck_assert_int_eq(pixels, counts[G]);
    static const struct { const char *name; int per; } arr[] = {{"colors", 3}, {"opacities", 1}, {"conics", 3}, {"means2d", 2}, {"absgrad", 2}};
    for (int i = 0; i < 5; i++) {
        char key[64];
        snprintf(key, sizeof key, "\nsum %s = ", arr[i].name);
        const char *p = strstr(out, key);
        ck_assert_msg(p, "no line %s", key + 1);
        p += strlen(key);
        const float *want = (const float *)npz_member(a, n, arr[i].name)->data + G * (size_t)arr[i].per;
        for (int k = 0; k < arr[i].per; k++) {
            char *end;
            const float v = strtof(p, &end);
            ck_assert_msg(end != p, "%s: no number at %.40s", arr[i].name, p);
            ck_assert_msg(!memcmp(&v, &want[k], sizeof v), "%s[%zu][%d]: explain sums to %.9g, splatref grad has %.9g", arr[i].name, G, k, v, want[k]);
            p = end + (*end == ',');
        }
    }
    /* and explain's own comparison says so (after the independent one above) */
    ck_assert_msg(rc == 0 && strstr(out, "explain: sums back to the array's value: yes (bit-identical)"), "exit %d: %s", rc, tail(out));
    spr_npz_free(a, n);
}
END_TEST

/* step --grad-gaussian G: the page's "Backward pass" section under the upstream options of the gradient tests: the chosen
 * pixel's reverse walk, G's pixels in summation order (as many as the .npz's counts[G]) and its sums, which the page
 * states equal splatref grad's values bit for bit; then with a G that blends at the chosen pixel, its row of the walk
 * equals the backward's own term. */
static char *step_page(const char *G, const char *name)
{
    static char out[1 << 14];
    char *argv[] = {"splatref", "step", "--model", (char *)grad_model(), GRAD_SCENE, "--grad-gaussian", (char *)G, "--out", (char *)path_in(name), "--quiet", NULL};
    const int rc = tu_run(NULL, NULL, 1, argv, out, sizeof out);
    ck_assert_msg(rc == 0 && strstr(out, "its sums equal splatref grad's values bit for bit: yes"), "step --grad-gaussian %s: exit %d: %s", G, rc, tail(out));
    char p[400];
    snprintf(p, sizeof p, "%s/index.html", path_in(name));
    char *html = NULL;
    size_t len = 0;
    spr_error e = {0};
    ck_assert_msg(spr__read_file(p, &html, &len, &e) == SPR_OK, "%s", e.msg);
    return html;
}

START_TEST(step_backward_section)
{
    spr_npy *a = NULL;
    const int n = grad_arrays(&a);
    const int32_t *counts = npz_member(a, n, "counts")->data;
    char *html = step_page("58", "walk");
    ck_assert_msg(strstr(html, "<section id=\"backward\"><h2>Backward pass"), "no backward section");
    ck_assert_msg(strstr(html, "id=\"backward-pixel-table\"") && count_of(html, "<tr class=\"bpx\"") >= 1, "no pixel walk");
    ck_assert_msg(strstr(html, "&part;L/&part;&alpha;<sub>k</sub>    = T<sub>k</sub>"), "no equations above the pixel's table");
    ck_assert_msg(strstr(html, "id=\"backward-bits\" data-same=\"yes\"") && strstr(html, "bit for bit: <b>yes</b>"), "sums not stated bit-identical");
    const char *c = strstr(html, "id=\"backward-count\" data-pixels=\"");
    ck_assert_msg(c, "no pixel count");
    ck_assert_int_eq(atoi(c + strlen("id=\"backward-count\" data-pixels=\"")), counts[58]);
    ck_assert_int_eq(count_of(html, "<tr class=\"gpx\""), counts[58]);
    ck_assert_msg(strstr(html, "id=\"backward-chain-table\"") && strstr(html, "<td>quats</td>") && strstr(html, "<td>sh0</td>"), "no chain");
    /* the front Gaussian of the chosen pixel's walk (its last row): its row equals the backward's own term for that pixel */
    const char *t = strstr(html, "id=\"backward-pixel-table\""), *last = NULL;
    for (const char *p = t; (p = strstr(p, "<tr class=\"bpx\"")) && p < strstr(t, "</table>"); p++) last = p;
    ck_assert_ptr_nonnull(last);
    const char *cell = last;
    for (int k = 0; k < 3; k++) cell = strstr(cell, "<td>") + 4; /* step, k, Gaussian */
    char G[16];
    snprintf(G, sizeof G, "%d", atoi(cell));
    free(html);
    html = step_page(G, "walk2");
    ck_assert_msg(strstr(html, "id=\"backward-pixel-check\" data-same=\"yes\""), "Gaussian %s's row of the walk differs from the backward's term", G);
    c = strstr(html, "id=\"backward-count\" data-pixels=\"");
    ck_assert_msg(c && atoi(c + strlen("id=\"backward-count\" data-pixels=\"")) == counts[atoi(G)], "Gaussian %s: pixel count", G);
    printf("step --grad-gaussian: Gaussian 58, %d pixels; Gaussian %s (front at the chosen pixel), %d pixels\n", counts[58], G, counts[atoi(G)]);
    free(html);
    spr_npz_free(a, n);
}
END_TEST

/* Issue 44: `splatref --help` names every algorithm of the registry on render's line (it said "pbr2p1 or deferred
 * blending" long after fourteen more were added); the line is made from the registry, so it cannot go stale. */
START_TEST(help_names_every_algorithm)
{
    char out[16384];
    char *argv[] = {"splatref", "--help", NULL};
    ck_assert_int_eq(tu_run(NULL, NULL, 1, argv, out, sizeof out), 0);
    const char *line = strstr(out, "\n  render ");
    ck_assert_msg(line, "no render line in: %s", out);
    char render[4096];
    const char *eol = strchr(line + 1, '\n');
    const size_t len = eol ? (size_t)(eol - line) : strlen(line);
    ck_assert_uint_lt(len, sizeof render);
    memcpy(render, line, len);
    render[len] = '\0';
    for (int a = 0; a < SPR_ALGO__COUNT; a++) {
        char name[64];
        snprintf(name, sizeof name, "%s%s", spr_algo_name((spr_algo)a), a + 1 < SPR_ALGO__COUNT ? "," : ";");
        ck_assert_msg(strstr(render, name), "render's help line lacks %s: %s", spr_algo_name((spr_algo)a), render);
    }
}
END_TEST

Suite *make_cli_suite(void)
{
    Suite *s = suite_create("cli");
    TCase *tc = tcase_create("cli");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, bad_inputs);
    tcase_add_test(tc, help_names_every_algorithm);
    tcase_add_test(tc, render_writes_outputs);
    tcase_add_test(tc, sample_then_info);
    tcase_add_test(tc, no_gl_context);
    tcase_add_test(tc, full_disk_is_one_line);
    tcase_add_test(tc, damaged_png_is_one_line);
    tcase_add_test(tc, group_command);
    tcase_add_test(tc, explicit_origin_target_is_used);
    tcase_add_test(tc, unused_options_are_refused);
    tcase_add_test(tc, transparency_options);
    tcase_add_test(tc, domains_command);
    tcase_add_test(tc, trace_lists_the_passes_in_order);
    tcase_add_test(tc, no_partial_dump_directory);
    tcase_add_test(tc, stream_equals_whole_cloud);
    tcase_add_test(tc, gauss_profile_options);
    tcase_add_test(tc, check_grads_verdicts);
    tcase_add_test(tc, explain_grad_sums_to_the_bit);
    tcase_add_test(tc, step_backward_section);
    suite_add_tcase(s, tc);
    return s;
}
