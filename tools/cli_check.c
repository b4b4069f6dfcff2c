/* cli_check.c — `splatref check` (someone else's image against the
 * reference of a scene) and `splatref compare` (two images), both under
 * PARITY.md's tiers (spr_check.h): a one-screen verdict, report.json, a
 * heat map and a side-by-side picture, exit 0 (pass) or 1 (fail). */
#include "cli.h"
#include "cli_grad.h"
#include "spr__scene_opts.h"
#include "spr__inspect.h"
#include "spr_check.h"
#include "spr_image.h"
#include "spr_swrast.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <errno.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

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
    {"junit", "F.xml", "also write a JUnit XML report (one test case: the plane checked; --camera all: one per view) for CI servers"},
    {"images", "DIR", "with --cameras F.json --camera all: every view's image from DIR (one verdict per view, then a summary)"},
    {"image-names", "position|name", "--images: position, the training code's render.py names (00000.png for the file's first entry, …; default), "
                                     "or name, the entry's img_name (.png or .pfm added when it has neither)"},
    {"views", "FIRST..LAST", "--camera all: only the entries FIRST to LAST of the file (0-based, LAST may be left out: to the end); by position "
                             "the image of entry FIRST is 00000.png (a model trained with --eval: cameras.json lists its T test views first, "
                             "render.py numbers test/ and train/ from 00000 each: --views 0..T-1 and --views T..)"},
    CLI_CHECK_GRADS_OPTS,
    CLI_GRAD_OPTS,
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

/* The tier options claimed and their numbers checked before any image is read (--camera all: each view reads them
 * with its own image's bits, after the options no view reads are refused).  0 or −1. */
static int tier_claim(spr__args *a)
{
    int lsb = -1, pos = 0;
    double u = -1.0;
    (void)spr__get(a, "tier");
    return spr__get_double(a, "ulp", &u, 0.0, 4294967296.0) < 0 || spr__get_int(a, "lsb", &lsb, 0, 65535) < 0 ||
                   spr__get_int(a, "position-tolerance", &pos, 0, 1) < 0
               ? -1
               : 0;
}

typedef struct check_io {
    const char *ref_label, *test_label, *what;
    const char *explain;   /* command explaining a pixel, "%d,%d" for it (NULL: none) */
    const char *out_shown; /* the report folder as the text names it (NULL: out itself) */
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
                            const spr_check_desc *d, const char *out, int pictures, spr_check_result *res)
{
    /* pictures: 1 always, 2 only when the image fails */
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
    if (pictures == 2) pictures = !r.pass && d->tier != SPR_TIER_C;
    if (out) {
        const char *shown = io->out_shown ? io->out_shown : out;
        char tmp[1200], path[1400];
        if (cli_outdir_begin(a, "out", out, tmp, sizeof tmp)) { free(heat); return 2; }
        spr_error err = {0};
        snprintf(path, sizeof path, "%s/heatmap.png", tmp);
        if (pictures && spr_write_png(path, heat, w, h, 3, &err)) { fprintf(stderr, "splatref %s: %s\n", cmd, err.msg); rc = 2; }
        snprintf(path, sizeof path, "%s/side-by-side.png", tmp);
        if (pictures && !rc && write_side_by_side(a, path, ref, test, heat, w, h, ch)) rc = 2;
        cJSON *o = spr__check_json(io->ref_label, io->test_label, io->what, w, h, ch, d, &r, explain);
        cJSON_DeleteItemFromObject(o, "verdict"); /* last, after the pictures */
        if (pictures) {
            cJSON_AddStringToObject(o, "heatmap", "heatmap.png");
            cJSON_AddStringToObject(o, "side_by_side", "side-by-side.png");
        }
        cJSON_AddStringToObject(o, "verdict", d->tier == SPR_TIER_C ? "diagnostic" : r.pass ? "pass" : "fail");
        snprintf(path, sizeof path, "%s/report.json", tmp);
        if (!rc && spr__write_json(a, path, o)) rc = 2;
        if (cli_outdir_end(a, "out", tmp, out, rc == 0)) rc = 2;
        if (!rc && !pictures) fprintf(tx, "%s: report %s/report.json\n", cmd, shown);
        else if (!rc) fprintf(tx, "%s: report %s/report.json, heat map %s/heatmap.png (blue within bounds, yellow only within one pixel, red failing), "
                        "side by side %s/side-by-side.png (reference | image | heat map)\n", cmd, shown, shown, shown);
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
static void explain_command(spr__args *a, const char *camera, char *s, size_t cap)
{
    size_t at = (size_t)snprintf(s, cap, "splatref explain");
    for (int k = 0; a->opts[k].name && at < cap; k++) {
        const char *n = a->opts[k].name, *v = camera && !strcmp(n, "camera") ? camera : a->value[k];
        if (!a->value[k] || (a->from_scene[k] && v == a->value[k]) || !spr__is_scene_option(n)) continue;
        if (!a->opts[k].arg) at += (size_t)snprintf(s + at, cap - at, " --%s", n);
        else at += (size_t)snprintf(s + at, cap - at, strpbrk(v, " \t'\"$") ? " --%s '%s'" : " --%s %s", n, v);
    }
}

/* ---- check --cameras F.json --camera all --images DIR: every view ---- */

/* The image of view k (entry e) in dir, into path: by position (the training code's render.py: "%05d.png" for the
 * file's k-th entry) or by the entry's img_name; ".png", then ".pfm", added when the name has neither.  0 found,
 * −1 none (path: the first name tried; why: the reason). */
static int view_image(const char *dir, int by_name, size_t k, const spr_camera_entry *e, char *path, size_t cap, char *why, size_t wcap)
{
    char stem[300];
    if (by_name && !e->img_name[0]) {
        snprintf(path, cap, "%s/?", dir);
        snprintf(why, wcap, "the entry has no img_name (--image-names position takes 00000.png, … instead)");
        return -1;
    }
    if (by_name) snprintf(stem, sizeof stem, "%s", e->img_name);
    else snprintf(stem, sizeof stem, "%05zu", k);
    const size_t n = strlen(stem);
    const int has_ext = n > 4 && (!strcasecmp(stem + n - 4, ".png") || !strcasecmp(stem + n - 4, ".pfm"));
    static const char *const ext[] = {".png", ".pfm"};
    for (int i = 0; i < (has_ext ? 1 : 2); i++) {
        char p[1400];
        snprintf(p, sizeof p, "%s/%s%s", dir, stem, has_ext ? "" : ext[i]);
        if (i == 0) snprintf(path, cap, "%s", p);
        if (access(p, F_OK) == 0) {
            snprintf(path, cap, "%s", p);
            return 0;
        }
    }
    snprintf(why, wcap, "no image %s%s", path, has_ext ? "" : " (nor .pfm)");
    return -1;
}

typedef struct view_outcome {
    int status;            /* 0 pass, 1 fail (its image differs, is missing or unreadable), 2 the run cannot go on */
    char image[1400];
    char line[4400];       /* the verdict's line (after "check: view … :") */
    char *text;            /* the full report, owned (NULL: line alone) */
    spr_check_result r;
    int checked;           /* compared (r is set) */
} view_outcome;

/* Check one view: its image, if found and of the view's size, against the reference of the moved scene. */
static void check_view(spr__args *a, spr_scene *s, const spr_render_desc *rd, const char *pname, int pass, const char *dir, int by_name,
                       size_t k, const spr_camera_entry *e, const char *out, const char *out_shown, view_outcome *vo)
{
    float *theirs = NULL, *ref = NULL;
    int tw, th, tch, bits, rch;
    char why[1600] = "", what[96];
    spr_error err = {0};
    vo->status = 1;
    if (view_image(dir, by_name, k, e, vo->image, sizeof vo->image, why, sizeof why)) goto failed;
    if (spr_image_size(vo->image, &tw, &th, &bits, &err) || spr_read_image_bits(vo->image, &theirs, &tw, &th, &tch, &bits, &err)) {
        snprintf(why, sizeof why, "%s", err.msg);
        goto failed;
    }
    if (tw != s->view.width || th != s->view.height) {
        snprintf(why, sizeof why, "%s is %dx%d, the view renders %dx%d", vo->image, tw, th, s->view.width, s->view.height);
        goto failed;
    }
    spr_check_desc d;
    if (tier_opts(a, bits, &d) || spr__check_reference(a, s, rd, pname, pass, &ref, &rch, what, sizeof what) ||
        spr__check_channels(a, vo->image, &theirs, &tch, rch, tw, th)) {
        vo->status = 2;
        goto done;
    }
    char ref_label[160], explain[2400], id[32], sub[1400], shown[1400];
    snprintf(ref_label, sizeof ref_label, "reference (cpu, %s, camera %ld)", spr_algo_name(rd->algo), e->id);
    snprintf(id, sizeof id, "%ld", e->id);
    explain_command(a, id, explain, sizeof explain);
    snprintf(sub, sizeof sub, "%s/%05zu", out, k);
    snprintf(shown, sizeof shown, "%s/%05zu", out_shown, k);
    check_io io = {ref_label, vo->image, what, explain, shown};
    cli_text tx;
    int rc = check_and_report(cli_text_begin(&tx), a, &io, ref, theirs, tw, th, rch, &d, sub, 2, &vo->r);
    vo->text = strdup(cli_text_close(&tx));
    cli_text_free(&tx);
    if (rc == 2) { vo->status = 2; goto done; }
    vo->status = rc, vo->checked = 1;
    const spr_check_result *r = &vo->r;
    const int n = snprintf(vo->line, sizeof vo->line, "%s: %s, %zu of %zu pixels fail, max %d LSB", vo->image,
                           d.tier == SPR_TIER_C ? "DIAGNOSTIC" : rc ? "FAIL" : "PASS", r->failing, r->pixels, r->max_lsb);
    if (rc && r->first_x >= 0 && n > 0 && (size_t)n < sizeof vo->line)
        snprintf(vo->line + n, sizeof vo->line - (size_t)n, "; first x %d, y %d; why: %s --pixel %d,%d", r->first_x, r->first_y, explain,
                 r->first_x, r->first_y);
    goto done;
failed:
    snprintf(vo->line, sizeof vo->line, "FAIL: %s", why);
done:
    free(theirs);
    free(ref);
}

/* --views FIRST..LAST (LAST may be left out) over the n entries of file into [*lo, *hi]; 0, or −1 with the error said. */
static int views_range(spr__args *a, const char *file, size_t n, size_t *lo, size_t *hi)
{
    const char *r = spr__get(a, "views");
    *lo = 0, *hi = n ? n - 1 : 0;
    if (!r) return 0;
    const char *dots = strstr(r, "..");
    char *end = NULL;
    errno = 0;
    const long first = dots && dots > r ? strtol(r, &end, 10) : -1;
    const int first_ok = end == dots && first >= 0 && errno == 0;
    long last = (long)n - 1;
    int last_ok = 1;
    if (first_ok && dots[2]) {
        last = strtol(dots + 2, &end, 10);
        last_ok = *end == '\0' && errno == 0 && last >= first;
    }
    if (!first_ok || !last_ok) {
        spr__error(a, "--views '%s': give FIRST..LAST or FIRST.. (positions in the cameras file, from 0)", r);
        return -1;
    }
    if ((size_t)first >= n || (size_t)last >= n) {
        spr__error(a, "--views '%s': %s has %zu entries (0..%zu)", r, file, n, n ? n - 1 : 0);
        return -1;
    }
    *lo = (size_t)first, *hi = (size_t)last;
    return 0;
}

/* Images in dir named as render.py names them (00000.png, …: five digits, .png or .pfm). */
static size_t position_images(const char *dir)
{
    DIR *d = opendir(dir);
    size_t m = 0;
    if (!d) return 0;
    for (struct dirent *e; (e = readdir(d));) {
        const char *n = e->d_name;
        int digits = 0;
        while (n[digits] >= '0' && n[digits] <= '9') digits++;
        m += digits == 5 && (!strcasecmp(n + 5, ".png") || !strcasecmp(n + 5, ".pfm"));
    }
    closedir(d);
    return m;
}

static int check_views(spr__args *a, const char *dir, const char *pname, int pass, const char *out, const char *junit)
{
    const char *names = spr__get(a, "image-names"), *file = NULL;
    if (names && strcmp(names, "position") && strcmp(names, "name")) { spr__error(a, "--image-names: '%s' is not position or name", names); return 2; }
    const int by_name = names && !strcmp(names, "name"), tty = isatty(2) && !spr__flag(a, "quiet");
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) { spr__error(a, "--images: %s is not a folder", dir); return 2; }
    spr_camera_entry *v = NULL;
    size_t n = 0;
    spr_error err = {0};
    spr_scene s;
    spr_render_desc rd;
    memset(&s, 0, sizeof s);
    int rc = 2, open_out = 0;
    size_t pass_n = 0, fail_n = 0, missing_n = 0;
    char tmp[1200] = "", failed[400] = "";
    cli_junit *ju = junit ? cli_junit_new("splatref check") : NULL;
    cJSON *rep = cJSON_CreateObject(), *arr = cJSON_AddArrayToObject(rep, "views");
    if (tier_claim(a) || spr__scene_setup(a, &s, &rd, 0) || spr__reject_unused(a)) goto done; /* --scene's values are read here */
    rd.progress = (spr_progress){NULL, NULL}; /* the terminal line is the views' (below), not each frame's passes */
    file = spr__get(a, "cameras");
    if (spr_cameras_json_all(file, &v, &n, &err)) { spr__error(a, "--cameras: %s", err.msg); goto done; }
    size_t lo, hi;
    if (views_range(a, file, n, &lo, &hi)) goto done;
    const size_t nv = hi - lo + 1; /* the views checked: entries lo..hi, view j = entry lo + j, its image by position j */
    if (cli_outdir_begin(a, "out", out, tmp, sizeof tmp)) goto done;
    open_out = 1;
    for (size_t j = 0; j < nv; j++) {
        const size_t k = lo + j;
        const spr_camera_entry *e = &v[k];
        if (tty) fprintf(stderr, "\r\033[Kcheck: view %zu of %zu (camera %ld)", j + 1, nv, e->id);
        const double t0 = spr_now_ms();
        view_outcome vo;
        memset(&vo, 0, sizeof vo);
        if (spr__scene_move_camera(a, &s, &e->pinhole, e->width, e->height)) goto done;
        check_view(a, &s, &rd, pname, pass, dir, by_name, j, e, tmp, out, &vo);
        if (vo.status == 2) { free(vo.text); goto done; }
        char head[400];
        snprintf(head, sizeof head, "view %zu of %zu (camera %ld%s%s)", j + 1, nv, e->id, e->img_name[0] ? ", " : "", e->img_name);
        if (tty) fputs("\r\033[K", stderr);
        printf("check: %s: %s\n", head, vo.line);
        fflush(stdout);
        if (vo.status == 0) pass_n++;
        else {
            if (vo.checked) fail_n++;
            else missing_n++;
            const size_t at = strlen(failed);
            if (at < sizeof failed - 40) snprintf(failed + at, sizeof failed - at, "%s%ld", at ? ", " : "", e->id);
            else if (!strstr(failed, "…")) snprintf(failed + at, sizeof failed - at, ", …");
        }
        char name[1900];
        snprintf(name, sizeof name, "%s: %s", head, vo.image);
        cli_junit_add(ju, "splatref.check", name, (spr_now_ms() - t0) / 1000.0, vo.status ? CLI_JUNIT_FAILURE : CLI_JUNIT_PASS,
                      vo.status ? vo.line : "", vo.text ? vo.text : vo.line);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "camera", (double)e->id);
        cJSON_AddStringToObject(o, "img_name", e->img_name);
        cJSON_AddStringToObject(o, "image", vo.image);
        cJSON_AddStringToObject(o, "verdict", vo.status ? "fail" : "pass");
        if (vo.checked) {
            char sub[24];
            snprintf(sub, sizeof sub, "%05zu", j);
            cJSON_AddNumberToObject(o, "failing", (double)vo.r.failing);
            cJSON_AddNumberToObject(o, "pixels", (double)vo.r.pixels);
            cJSON_AddNumberToObject(o, "max_lsb", vo.r.max_lsb);
            cJSON_AddStringToObject(o, "report", sub);
        } else {
            cJSON_AddStringToObject(o, "why", vo.line + 6);
        }
        cJSON_AddItemToArray(arr, o);
        free(vo.text);
    }
    if (tty) fputs("\r\033[K", stderr);
    const int every = nv == n; /* no --views, or all of them */
    char entries[64] = "";
    if (!every) snprintf(entries, sizeof entries, " (entries %zu..%zu)", lo, hi);
    printf("check: %zu views%s of %s: %zu pass, %zu fail, %zu without a usable image\n", nv, entries, file, pass_n, fail_n, missing_n);
    if (!by_name && pass_n < nv && every) { /* by position, a folder of fewer images than views: an --eval model's? */
        const size_t m = position_images(dir);
        if (m && m < n)
            printf("check: hint: %s holds %zu images 00000.png, … for %zu views. A model trained with --eval lists its test views first "
                   "in cameras.json, and render.py numbers test/ and train/ each from 00000: for its training views give --views %zu.., "
                   "for its test views --views 0..%zu\n",
                   dir, m, n, n - m, m - 1);
    }
    cJSON_AddNumberToObject(rep, "pass", (double)pass_n);
    cJSON_AddNumberToObject(rep, "fail", (double)fail_n);
    cJSON_AddNumberToObject(rep, "missing", (double)missing_n);
    cJSON_AddStringToObject(rep, "verdict", pass_n == nv ? "pass" : "fail");
    char path[1400];
    snprintf(path, sizeof path, "%s/report.json", tmp);
    rc = spr__write_json(a, path, rep) ? 2 : pass_n == nv ? 0 : 1; /* it takes rep */
    rep = NULL;
    if (cli_outdir_end(a, "out", tmp, out, rc != 2)) rc = 2;
    open_out = 0;
    if (rc != 2) printf("check: report %s/report.json (one folder a view: heat map and side by side where it fails)\n", out);
    if (ju && rc != 2 && cli_junit_write(a, ju, junit)) rc = 2;
    if (rc == 0) printf("verdict: PASS (all %zu views)\n", nv);
    else if (rc == 1) printf("verdict: FAIL (camera%s %s)\n", pass_n + 1 < nv ? "s" : "", failed);
done:
    if (open_out) cli_outdir_end(a, "out", tmp, out, 0);
    cJSON_Delete(rep);
    cli_junit_free(ju);
    spr_scene_free(&s);
    free(v);
    return rc;
}

int cmd_check(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "check", check_opts, "--scene S.json | [scene options]  --image THEIRS.png|.pfm [--plane P] [--tier A|B|C] [--ulp N] [--lsb N] [--position-tolerance 1]  |  --grads THEIRS.npz --dl-dimage G.npy|--loss l1|l2 --target IMG [--rtol R] [--atol A]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    const char *image = spr__get(&a, "image"), *pname = spr__get(&a, "plane"), *out = spr__get(&a, "out"), *junit = spr__get(&a, "junit");
    const char *images = spr__get(&a, "images"), *camera = spr__get(&a, "camera");
    const int all = camera && !strcmp(camera, "all");
    const char *grads = spr__get(&a, "grads");
    if (grads && (image || images)) { spr__error(&a, "--grads checks gradients, --image%s an image: give one", images ? "s" : ""); return 2; }
    if (grads) {
        a.camera_all = all;
        return cli_check_grads(&a, grads, out, junit);
    }
    if (image && images) { spr__error(&a, "--image and --images both name what to check: give one"); return 2; }
    if (all && !images) { spr__error(&a, "--camera all checks every view: give --images DIR (their images)"); return 2; }
    if (images && !all) { spr__error(&a, "--images DIR goes with --cameras F.json --camera all (every view)"); return 2; }
    if (spr__get(&a, "views") && !all) { spr__error(&a, "--views goes with --cameras F.json --camera all --images DIR"); return 2; }
    if (!image && !images) { spr__error(&a, "--image is required (the picture your renderer made of the scene), or --grads THEIRS.npz (its gradients)"); return 2; }
    if (!out) out = "check-report";
    int pass = -1;
    if (spr__get_int(&a, "pass", &pass, 0, 100000) < 0) return 2;
    a.camera_all = all;
    if (all) return check_views(&a, images, pname, pass, out, junit);
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
    explain_command(&a, NULL, explain, sizeof explain);
    check_io io = {ref_label, image, what, explain, NULL};
    cli_text tx;
    spr_check_result r;
    memset(&r, 0, sizeof r);
    rc = check_and_report(cli_text_begin(&tx), &a, &io, ref, theirs, tw, th, rch, &d, out, 1, &r);
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
    check_io io = {a.positional[0], a.positional[1], "images", NULL, NULL};
    spr_check_result r;
    rc = check_and_report(stdout, &a, &io, im[0], im[1], w[0], h[0], ch[0], &d, out, 1, &r);
done:
    free(im[0]);
    free(im[1]);
    return rc;
}
