/* cli_check.c — `splatref check` (someone else's image against the
 * reference of a scene) and `splatref compare` (two images), both under
 * PARITY.md's tiers (spr_check.h): a one-screen verdict, report.json, a
 * heat map and a side-by-side picture, exit 0 (pass) or 1 (fail). */
#include "cli.h"
#include "spr__scene_opts.h"
#include "spr__inspect.h"
#include "spr_check.h"
#include "spr_image.h"
#include "spr_swrast.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CLI_TIER_OPTS \
    {"tier", "A|B|C", "A bit-exact (default), B bounded (--ulp/--lsb/--position-tolerance; default --lsb 1), C diagnostics only"}, \
    {"ulp", "N", "Tier B, float images: a channel passes within N ulps"}, \
    {"lsb", "N", "Tier B: a channel passes within N LSB (float images: of their 8-bit values)"}, \
    {"position-tolerance", "P", "Tier B: 1 = a failing pixel passes when a match lies within one pixel both ways (edges)"}

static const spr__opt check_opts[] = {
    {"image", "F.png|F.pfm", "the image to check (PNG 8/16-bit or PFM; row 0 of a PNG is the top)"},
    {"plane", "NAME", "what the image holds: color (final image, default) | weight | depth | test | id | count | opacity; gauss*: transmittance | contrib | invdepth | surfdepth"},
    {"pass", "N", "the plane after pass N (as numbered by render --dump; default: the last pass that has it)"},
    CLI_TIER_OPTS,
    {"out", "DIR", "report.json, heatmap.png and side-by-side.png (default check-report)"},
    {"junit", "F.xml", "also write a JUnit XML report (one test case: the plane checked) for CI servers"},
    SPR__SCENE_OPTS,
    {NULL, NULL, NULL}};

static const spr__opt compare_opts[] = {
    CLI_TIER_OPTS,
    {"out", "DIR", "report.json, heatmap.png and side-by-side.png (default: none)"},
    {"metric", "NAME", "also print: covered (mean and max over pixels not background in both, default) | zp-eps ([ZP] 6.3's eps)"},
    {"background", "R,G,B", "pixels of this colour are not covered (covered: in both images; zp-eps: the part of eps where B has it) (default 0,0,0)"},
    {"heatmap", "FILE.png", "write the per-pixel sum of |dR|+|dG|+|dB| as a heat map (black equal, white the largest)"},
    {NULL, NULL, NULL}};

/* A picture of a plane for the side-by-side: colour as is, one channel as
 * grey over [lo, hi]. */
static void to_rgb(const float *im, int ch, size_t np, double lo, double hi, float *rgb)
{
    for (size_t p = 0; p < np; p++)
        for (int c = 0; c < 3; c++) {
            float v = im[p * ch + (ch == 1 ? 0 : c)];
            rgb[3 * p + c] = ch == 1 ? (float)(hi > lo && isfinite(v) ? (v - lo) / (hi - lo) : 0.0) : v;
        }
}

/* The tier options into d; bits: of the image under test.  0 or −1. */
static int tier_opts(spr__args *a, int bits, spr_check_desc *d)
{
    int lsb = -1, pos = 0;
    double u = -1.0;
    if (spr__get_double(a, "ulp", &u, 0.0, 4294967296.0) < 0 || spr__get_int(a, "lsb", &lsb, 0, 65535) < 0 ||
        spr__get_int(a, "position-tolerance", &pos, 0, 1) < 0)
        return -1;
    return spr__check_tier(a, spr__get(a, "tier"), u, lsb, pos, bits, d);
}

typedef struct check_io {
    const char *ref_label, *test_label, *what;
    const char *explain;   /* command explaining a pixel, "%d,%d" for it (NULL: none) */
} check_io;

static int write_side_by_side(spr__args *a, const char *path, const float *ref, const float *test, const float *heat, int w, int h, int ch)
{
    const int gap = 4, W = 3 * w + 2 * gap;
    const size_t np = (size_t)w * h;
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; ch == 1 && i < np; i++)
        for (int k = 0; k < 2; k++) {
            float v = (k ? test : ref)[i];
            if (isfinite(v)) lo = v < lo ? v : lo, hi = v > hi ? v : hi;
        }
    float *img = calloc((size_t)W * h * 3, sizeof *img), *tmp = malloc(np * 3 * sizeof *tmp);
    int rc = -1;
    if (img && tmp) {
        for (int panel = 0; panel < 3; panel++) {
            if (panel < 2) to_rgb(panel ? test : ref, ch, np, lo, hi, tmp);
            const float *src = panel < 2 ? tmp : heat;
            for (int y = 0; y < h; y++)
                memcpy(img + ((size_t)y * W + (size_t)panel * (w + gap)) * 3, src + (size_t)y * w * 3, (size_t)w * 3 * sizeof *img);
        }
        for (int y = 0; y < h; y++) /* grey separators */
            for (int g = 0; g < gap; g++)
                for (int c = 0; c < 3; c++) img[((size_t)y * W + w + g) * 3 + c] = img[((size_t)y * W + 2 * w + gap + g) * 3 + c] = 0.5f;
        spr_error err = {0};
        rc = spr_write_png(path, img, W, h, 3, &err) ? -1 : 0;
        if (rc) fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg);
    } else {
        spr__error(a, "out of memory for the side-by-side picture");
    }
    free(img);
    free(tmp);
    return rc;
}

/* Compare, print the verdict, write the report directory (out may be NULL).
 * 0 pass, 1 fail, 2 error. */
static int check_and_report(FILE *tx, spr__args *a, const check_io *io, const float *ref, const float *test, int w, int h, int ch,
                            const spr_check_desc *d, const char *out, spr_check_result *res)
{
    const size_t np = (size_t)w * h;
    float *heat = malloc(np * 3 * sizeof *heat);
    if (!heat) { spr__error(a, "out of memory"); return 2; }
    spr_check_result r;
    spr_check_images(ref, test, w, h, ch, d, &r, heat);
    const char *cmd = a->cmd;
    char bounds[160];
    spr__check_bounds_text(d, bounds, sizeof bounds);
    fprintf(tx, "%s: %s vs %s: %s, %dx%d, %d channel%s, %s\n", cmd, io->ref_label, io->test_label, io->what, w, h, ch, ch > 1 ? "s" : "",
           d->bits == 32 ? "float" : d->bits == 16 ? "16-bit" : "8-bit");
    fprintf(tx, "%s: Tier %s (%s): %zu of %zu pixels differ, %zu fail%s", cmd, spr_tier_name(d->tier), bounds, r.differing, r.pixels, r.failing,
           r.failing == 1 ? "s" : "");
    if (d->position) fprintf(tx, ", %zu pass only within one pixel (edges)", r.rescued);
    fprintf(tx, "\n%s: ", cmd);
    if (d->bits == 32) fprintf(tx, "max %llu ulp, ", (unsigned long long)r.max_ulp);
    fprintf(tx, "max %d LSB (%s), max abs %.9g, mean abs %.3g, [ZP] eps %.4f\n", r.max_lsb, d->bits == 16 ? "16-bit" : "8-bit", r.max_abs,
           r.mean_abs, r.zp_eps);
    char explain[2600] = "";
    if (r.first_x >= 0) {
        fprintf(tx, "%s: first %s pixel x %d, y %d (row %d from the top), channel %d: reference %.9g, %s %.9g", cmd,
               r.failing ? "failing" : "differing", r.first_x, r.first_y, h - 1 - r.first_y, r.first_channel, r.first_ref, io->test_label,
               r.first_test);
        if (d->bits == 8) fprintf(tx, " (8-bit %d and %d)", spr_to_u8((float)r.first_ref), spr_to_u8((float)r.first_test));
        fprintf(tx, "\n");
        if (io->explain) {
            snprintf(explain, sizeof explain, "%s --pixel %d,%d", io->explain, r.first_x, r.first_y);
            fprintf(tx, "%s: why: %s\n", cmd, explain);
        }
    }
    int rc = 0;
    if (out) {
        char tmp[1200], path[1400];
        if (cli_outdir_begin(a, "out", out, tmp, sizeof tmp)) { free(heat); return 2; }
        spr_error err = {0};
        snprintf(path, sizeof path, "%s/heatmap.png", tmp);
        if (spr_write_png(path, heat, w, h, 3, &err)) { fprintf(stderr, "splatref %s: %s\n", cmd, err.msg); rc = 2; }
        snprintf(path, sizeof path, "%s/side-by-side.png", tmp);
        if (!rc && write_side_by_side(a, path, ref, test, heat, w, h, ch)) rc = 2;
        cJSON *o = spr__check_json(io->ref_label, io->test_label, io->what, w, h, ch, d, &r, explain);
        cJSON_DeleteItemFromObject(o, "verdict"); /* last, after the pictures */
        cJSON_AddStringToObject(o, "heatmap", "heatmap.png");
        cJSON_AddStringToObject(o, "side_by_side", "side-by-side.png");
        cJSON_AddStringToObject(o, "verdict", d->tier == SPR_TIER_C ? "diagnostic" : r.pass ? "pass" : "fail");
        snprintf(path, sizeof path, "%s/report.json", tmp);
        if (!rc && spr__write_json(a, path, o)) rc = 2;
        if (cli_outdir_end(a, "out", tmp, out, rc == 0)) rc = 2;
        if (!rc) fprintf(tx, "%s: report %s/report.json, heat map %s/heatmap.png (blue within bounds, yellow only within one pixel, red failing), "
                        "side by side %s/side-by-side.png (reference | image | heat map)\n", cmd, out, out, out);
    }
    free(heat);
    if (rc) return rc;
    if (d->tier == SPR_TIER_C) fprintf(tx, "verdict: DIAGNOSTIC (Tier C never passes or fails on its own)\n");
    else fprintf(tx, "verdict: %s (Tier %s)\n", r.pass ? "PASS" : "FAIL", spr_tier_name(d->tier));
    *res = r;
    return r.pass ? 0 : 1;
}

/* The command explaining a pixel of this scene: the scene options given
 * on the command line (--scene among them). */
static void explain_command(spr__args *a, char *s, size_t cap)
{
    size_t at = (size_t)snprintf(s, cap, "splatref explain");
    for (int k = 0; a->opts[k].name && at < cap; k++) {
        const char *n = a->opts[k].name;
        if (!a->value[k] || a->from_scene[k] || !spr__is_scene_option(n)) continue;
        if (!a->opts[k].arg) at += (size_t)snprintf(s + at, cap - at, " --%s", n);
        else at += (size_t)snprintf(s + at, cap - at, strpbrk(a->value[k], " \t'\"$") ? " --%s '%s'" : " --%s %s", n, a->value[k]);
    }
}

int cmd_check(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "check", check_opts, "--scene S.json | [scene options]  --image THEIRS.png|.pfm [--plane P] [--tier A|B|C] [--ulp N] [--lsb N] [--position-tolerance 1]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    const char *image = spr__get(&a, "image"), *pname = spr__get(&a, "plane"), *out = spr__get(&a, "out"), *junit = spr__get(&a, "junit");
    if (!image) { spr__error(&a, "--image is required (the picture your renderer made of the scene)"); return 2; }
    if (!out) out = "check-report";
    int pass = -1;
    if (spr__get_int(&a, "pass", &pass, 0, 100000) < 0) return 2;
    float *theirs = NULL, *ref = NULL;
    int tw, th, tch, bits, rch;
    spr_error err = {0};
    /* the size its header states first: another size than the scene's is refused before the image is decoded (a
     * small file cannot make check allocate a large image); a header that cannot be read: the full read says why */
    const int header = !spr_image_size(image, &tw, &th, &bits, &err);
    if (!header && spr_read_image_bits(image, &theirs, &tw, &th, &tch, &bits, &err)) {
        fprintf(stderr, "splatref check: %s\n", err.msg);
        return 2;
    }
    spr_check_desc d;
    spr_scene s;
    spr_render_desc rd;
    int rc = 2;
    char what[96];
    memset(&s, 0, sizeof s);
    if (tier_opts(&a, bits, &d) || spr__scene_setup(&a, &s, &rd, 0)) goto done;
    if (tw != s.view.width || th != s.view.height) {
        spr__error(&a, "%s is %dx%d, the scene renders %dx%d", image, tw, th, s.view.width, s.view.height);
        goto done;
    }
    if (header) {
        const int hw = tw, hh = th, hb = bits;
        if (spr_read_image_bits(image, &theirs, &tw, &th, &tch, &bits, &err)) {
            fprintf(stderr, "splatref check: %s\n", err.msg);
            goto done;
        }
        if (tw != hw || th != hh || bits != hb) { /* cannot happen for a file that is not changing under us */
            spr__error(&a, "%s: its header says %dx%d, %d bits; its data %dx%d, %d bits", image, hw, hh, hb, tw, th, bits);
            goto done;
        }
    }
    if (spr__check_reference(&a, &s, &rd, pname, pass, &ref, &rch, what, sizeof what) ||
        spr__check_channels(&a, image, &theirs, &tch, rch, tw, th))
        goto done;
    char ref_label[160], explain[2400];
    snprintf(ref_label, sizeof ref_label, "reference (cpu, %s)", spr_algo_name(rd.algo));
    explain_command(&a, explain, sizeof explain);
    check_io io = {ref_label, image, what, explain};
    cli_text tx;
    spr_check_result r;
    memset(&r, 0, sizeof r);
    rc = check_and_report(cli_text_begin(&tx), &a, &io, ref, theirs, tw, th, rch, &d, out, &r);
    const char *text = cli_text_end(&tx);
    if (junit) {
        cli_junit *ju = cli_junit_new("splatref check");
        char name[400], msg[160];
        snprintf(name, sizeof name, "%s: %s", image, what);
        snprintf(msg, sizeof msg, "Tier %s: %zu of %zu pixels fail", spr_tier_name(d.tier), r.failing, r.pixels);
        cli_junit_add(ju, "splatref.check", name, 0.0, rc == 0 ? CLI_JUNIT_PASS : rc == 1 ? CLI_JUNIT_FAILURE : CLI_JUNIT_ERROR,
                      rc == 1 ? msg : "the report could not be written", text);
        if (cli_junit_write(&a, ju, junit)) rc = 2;
        cli_junit_free(ju);
    }
    cli_text_free(&tx);
done:
    free(theirs);
    free(ref);
    spr_scene_free(&s);
    return rc;
}

/* `splatref compare A B`: A is the reference. */
int cmd_compare(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "compare", compare_opts, "A.png|A.pfm B.png|B.pfm [--tier A|B|C] [--ulp N] [--lsb N] [--position-tolerance 1] [--out DIR]", 2,
                       argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    if (a.n_positional != 2) { spr__error(&a, "two images (.png or .pfm) are required"); return 2; }
    const char *metric = spr__get(&a, "metric"), *heatmap = spr__get(&a, "heatmap"), *out = spr__get(&a, "out");
    if (metric && strcmp(metric, "covered") && strcmp(metric, "zp-eps")) { spr__error(&a, "--metric: '%s' is not covered or zp-eps", metric); return 2; }
    double bg[3] = {0, 0, 0};
    if (spr__get_vec3(&a, "background", bg) < 0) return 2;
    float *im[2] = {NULL, NULL};
    int w[2], h[2], ch[2], bits[2];
    spr_error err = {0};
    int rc = 2;
    for (int i = 0; i < 2; i++)
        if (spr_read_image_bits(a.positional[i], &im[i], &w[i], &h[i], &ch[i], &bits[i], &err)) {
            fprintf(stderr, "splatref compare: %s\n", err.msg);
            goto done;
        }
    spr_check_desc d;
    if (tier_opts(&a, bits[1] < bits[0] ? bits[1] : bits[0], &d) || spr__reject_unused(&a)) goto done;
    if (w[0] != w[1] || h[0] != h[1]) {
        spr__error(&a, "%s is %dx%d, %s is %dx%d", a.positional[0], w[0], h[0], a.positional[1], w[1], h[1]);
        goto done;
    }
    if (ch[0] == 1 && spr__check_channels(&a, a.positional[1], &im[1], &ch[1], 1, w[0], h[0])) goto done;
    if (ch[1] == 1 && spr__check_channels(&a, a.positional[0], &im[0], &ch[0], 1, w[0], h[0])) goto done;
    if (spr__check_channels(&a, a.positional[1], &im[1], &ch[1], ch[0], w[0], h[0])) goto done;
    const size_t np = (size_t)w[0] * h[0];
    /* the [ZP] metrics on 8-bit values, as before */
    float *heat = heatmap ? malloc(np * 3 * sizeof *heat) : NULL;
    spr_image_diff_stats st;
    const float bgf[3] = {(float)bg[0], (float)bg[1], (float)bg[2]};
    spr_image_diff(im[0], ch[0], im[1], ch[1], w[0], h[0], bgf, &st, heat);
    if (metric && !strcmp(metric, "zp-eps")) {
        printf("compare: zp-eps %.4f (sum of |dR|+|dG|+|dB| in 8 bits over %zu pixels / %zu), max abs %d/255, mean abs %.4f/255, "
               "%zu pixels differ\n", st.zp_eps, st.pixels, st.pixels, st.max_abs, st.mean_abs, st.differing);
        printf("compare: of which %.4f from the %zu pixels where %s is background (%.9g,%.9g,%.9g)\n", st.zp_eps_bg, st.bg_pixels,
               a.positional[1], bg[0], bg[1], bg[2]);
    } else {
        const int c0 = ch[0] < 3 ? 1 : 3;
        size_t covered = 0, differing = 0;
        double sum = 0.0, maxd = 0.0;
        for (size_t p = 0; p < np; p++) {
            int bg0 = 1, bg1 = 1;
            for (int c = 0; c < c0; c++) {
                bg0 &= im[0][p * ch[0] + c] == (float)bg[c];
                bg1 &= im[1][p * ch[1] + c] == (float)bg[c];
            }
            if (bg0 && bg1) continue;
            covered++;
            int diff = 0;
            for (int c = 0; c < c0; c++) {
                double dd = fabs((double)spr_to_u8(im[0][p * ch[0] + c]) - (double)spr_to_u8(im[1][p * ch[1] + c]));
                sum += dd;
                if (dd > maxd) maxd = dd;
                diff |= dd != 0.0;
            }
            differing += diff;
        }
        printf("compare: %zu covered pixels, %zu differ in 8 bits, mean |diff| %.4f/255 per channel, max %.0f/255\n", covered, differing,
               covered ? sum / ((double)covered * c0) : 0.0, maxd);
    }
    if (heat) {
        if (spr_write_png(heatmap, heat, w[0], h[0], 3, &err)) { fprintf(stderr, "splatref compare: %s\n", err.msg); free(heat); goto done; }
        printf("compare: heat map -> %s\n", heatmap);
        free(heat);
    }
    check_io io = {a.positional[0], a.positional[1], "images", NULL};
    spr_check_result r;
    rc = check_and_report(stdout, &a, &io, im[0], im[1], w[0], h[0], ch[0], &d, out, &r);
done:
    free(im[0]);
    free(im[1]);
    return rc;
}
