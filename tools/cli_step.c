/* cli_step.c — `splatref step --out DIR`: a step-by-step walk-through of
 * one frame as a self-contained web page (DIR/index.html, its PNGs and the
 * scene file; no network).  One section per pass: what the pass does and
 * the equation it implements (SPEC / [ZP] / [R] numbers), its state, its
 * statistics, and a picture of every plane of its target (colour, weight,
 * depth and test heat maps with legends, ids, counts, the group of the
 * nearest layer, the ε-test mask of a composite).  Every plane value of
 * every pass is embedded, so a click on any picture shows that pixel in
 * every pass; the pixel histories of a few pixels (splatref explain) are
 * embedded too.  Grouping gets its own section: which splat went to which
 * group, with its overlapping neighbours' groups, on a small cloud. */
#include "cli.h"
#include "cli_grad.h"
#include "spr__scene_opts.h"
#include "spr_image.h"
#include "spr_swrast.h"
#include "spr_arith_c.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const spr__opt step_opts[] = {
    {"out", "DIR", "the walk-through: DIR/index.html, its pictures and scene.json (required)"},
    {"pixels", "N", "pixel histories to embed, 0..16 (default 6)"},
    {"grad-gaussian", "G", "gauss3d under a profile that trains: a backward pass section (SPEC 10.10) for the first embedded pixel and for Gaussian G "
                           "(its index in the model), under the upstream gradient of --loss or --dl-dimage (as splatref grad)"},
    CLI_GRAD_OPTS,
    SPR__SCENE_OPTS,
    {NULL, NULL, NULL}};

/* The passes come from spr_capture (planes as floats); a composite's test
 * plane repeats its depth and is left out, as --dump leaves it out. */
static const float *plane_of(const spr_captured_pass *p, int q)
{
    return p->composite && q == SPR_PLANE_TEST ? NULL : (const float *)p->plane[q];
}

/* ---- pictures ---- */
/* The heat map's colour stops (also the legends' CSS gradient). */
static const float heat_stops[5][3] = {{0.05f, 0.03f, 0.35f}, {0.25f, 0.2f, 0.8f}, {0.1f, 0.65f, 0.6f}, {0.75f, 0.85f, 0.15f}, {1.0f, 1.0f, 0.85f}};
static void heat(double u, float *rgb)
{
    if (!(u >= 0.0)) u = 0.0;
    if (u > 1.0) u = 1.0;
    double s = u * 4.0;
    int i = (int)s;
    if (i > 3) i = 3;
    double f = s - i;
    for (int c = 0; c < 3; c++) rgb[c] = (float)(heat_stops[i][c] * (1.0 - f) + heat_stops[i + 1][c] * f);
}
/* Well spread colours for ids and groups. */
static void id_colour(long id, float *rgb)
{
    if (id < 0) { rgb[0] = rgb[1] = rgb[2] = 0.0f; return; }
    double h = fmod((double)id * 0.618033988749895, 1.0) * 6.0;
    int i = (int)h;
    double f = h - i, v = 0.95, s = 0.7, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    double r[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
    for (int c = 0; c < 3; c++) rgb[c] = (float)r[i % 6][c];
}

typedef struct view_out {
    char file[64], caption[160], legend[160];
} view_out;

/* Range of finite values other than `skip` (a plane's clear value). */
static void range(const float *v, size_t n, int stride, float skip, double *lo, double *hi)
{
    *lo = INFINITY, *hi = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        float x = v[i * stride];
        if (!isfinite(x) || x == skip) continue;
        if (x < *lo) *lo = x;
        if (x > *hi) *hi = x;
    }
    if (!(*hi >= *lo)) *lo = 0.0, *hi = 1.0;
}

static int write_view(spr__args *a, const char *dir, const float *rgb, int W, int H, view_out *vo)
{
    char path[1400];
    snprintf(path, sizeof path, "%s/%s", dir, vo->file);
    spr_error err = {0};
    if (spr_write_png(path, rgb, W, H, 3, &err)) { fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg); return -1; }
    return 0;
}

/* ---- text helpers ---- */
static void html_escape(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '<') fputs("&lt;", f);
        else if (*s == '>') fputs("&gt;", f);
        else if (*s == '&') fputs("&amp;", f);
        else if (*s == '"') fputs("&quot;", f);
        else fputc(*s, f);
    }
}

/* Base64 of raw bytes into f (the embedded planes; 20 lines are simpler
 * than a dependency for this one use). */
static void base64(FILE *f, const unsigned char *p, size_t n)
{
    static const char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t i = 0;
    for (; i + 2 < n; i += 3) {
        unsigned v = (unsigned)p[i] << 16 | (unsigned)p[i + 1] << 8 | p[i + 2];
        fputc(t[v >> 18], f), fputc(t[v >> 12 & 63], f), fputc(t[v >> 6 & 63], f), fputc(t[v & 63], f);
    }
    if (i < n) {
        unsigned v = (unsigned)p[i] << 16 | (i + 1 < n ? (unsigned)p[i + 1] << 8 : 0u);
        fputc(t[v >> 18], f), fputc(t[v >> 12 & 63], f);
        fputc(i + 1 < n ? t[v >> 6 & 63] : '=', f), fputc('=', f);
    }
}

static const char *const depth_eq[SPR_DEPTH__COUNT] = {
    "z = d<sub>f</sub> (SPEC 3.3)",
    "z = d<sub>f</sub> + &epsilon;<sub>t</sub> (SPEC 3.3; the visibility pass of [ZP] 3.1)",
    "z = floor(((d<sub>f</sub> &minus; d<sub>min</sub>)/(d<sub>max</sub> &minus; d<sub>min</sub>))&middot;n)&middot;(1/n) ([ZP] Eq. 10, SPEC 3.3)",
    "z = z&#771; + &rho;&middot;(1/n): Voronoi depth, the fragment nearest its own splat centre wins within a layer ([ZP] Eq. 14, SPEC 3.3)"};
static const char *const blend_eq[SPR_BLEND__COUNT] = {"dst = src", "dst = src + dst", "dst = src&middot;&alpha; + dst&middot;(1 &minus; &alpha;)",
                                                      "dst = dst &minus; src", "dst = src + dst&middot;(1 &minus; &alpha;)"};
static const char *const func_eq[SPR_FUNC__COUNT] = {"passes when z &lt; the stored test value", "passes when z &le; the stored test value",
                                                    "always passes"};

/* ---- the page ---- */
typedef struct page {
    FILE *f;
    int W, H;
} page;

static void legend_css(FILE *f)
{
    fprintf(f, "linear-gradient(to right");
    for (int i = 0; i < 5; i++)
        fprintf(f, ", rgb(%d,%d,%d)", (int)(heat_stops[i][0] * 255), (int)(heat_stops[i][1] * 255), (int)(heat_stops[i][2] * 255));
    fprintf(f, ")");
}

static void figure(page *pg, const view_out *vo, int pass, const char *plane, int heat_legend, double lo, double hi)
{
    FILE *f = pg->f;
    fprintf(f, "<figure><img class=\"plane\" src=\"%s\" width=\"%d\" height=\"%d\" data-pass=\"%d\" data-plane=\"%s\" alt=\"", vo->file, pg->W * 3,
            pg->H * 3, pass, plane);
    html_escape(f, vo->caption);
    fprintf(f, "\"><figcaption>");
    html_escape(f, vo->caption);
    if (heat_legend) {
        fprintf(f, "<div class=\"legend\"><span>%.6g</span><span class=\"bar\" style=\"background:", lo);
        legend_css(f);
        fprintf(f, "\"></span><span>%.6g</span></div>", hi);
    } else if (vo->legend[0]) {
        fprintf(f, "<div class=\"note\">");
        html_escape(f, vo->legend);
        fprintf(f, "</div>");
    }
    fprintf(f, "</figcaption></figure>\n");
}

/* The pictures of one pass; writes its PNGs into dir. */
static int pass_views(spr__args *a, page *pg, const char *dir, const spr_captured_pass *p, const spr_captured_pass *all, const spr_composite_op *op,
                      const int *inputs, int n_inputs, float eps_t, int list)
{
    const int W = pg->W, H = pg->H;
    if (list) { /* a list draw writes no plane: its fragments live in the lists the next composite reads */
        fprintf(pg->f, "<p class=\"note\">No plane is written by a list draw; the next composite reads the lists (its pictures follow).</p>\n");
        return 0;
    }
    const size_t np = (size_t)W * H;
    float *rgb = malloc(np * 3 * sizeof *rgb);
    if (!rgb) { spr__error(a, "out of memory"); return -1; }
    int rc = 0;
    for (int q = 0; q < SPR_PLANE__COUNT && !rc; q++) {
        const float *v = plane_of(p, q);
        if (!v) continue;
        view_out vo = {{0}, {0}, {0}};
        const char *pname = spr_plane_name((spr_plane)q);
        double lo = 0, hi = 1;
        int legend = 0;
        if (q == SPR_PLANE_COLOR) {
            const int weighted = !p->composite && p->state.output == SPR_OUT_WEIGHTED;
            for (size_t i = 0; i < np; i++)
                for (int c = 0; c < 3; c++) rgb[3 * i + c] = weighted ? (v[4 * i + 3] > 0.0f ? v[4 * i + c] / v[4 * i + 3] : 0.0f) : v[4 * i + c];
            snprintf(vo.file, sizeof vo.file, "p%03d_color.png", p->index);
            snprintf(vo.caption, sizeof vo.caption, weighted ? "colour, normalised: (sum w*c)/(sum w)" : "colour (rgb)");
            rc = write_view(a, dir, rgb, W, H, &vo);
            if (!rc) figure(pg, &vo, p->index, "color", 0, 0, 0);
            /* the fourth channel */
            range(v + 3, np, 4, 0.0f, &lo, &hi);
            for (size_t i = 0; i < np; i++) {
                if (v[4 * i + 3] == 0.0f) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = 0.0f;
                else heat(hi > lo ? (v[4 * i + 3] - lo) / (hi - lo) : 1.0, rgb + 3 * i);
            }
            snprintf(vo.file, sizeof vo.file, "p%03d_weight.png", p->index);
            snprintf(vo.caption, sizeof vo.caption, weighted ? "weight sum w (black: none)" : p->composite ? "coverage (4th channel)" : "alpha / 4th channel");
            if (!rc && !(rc = write_view(a, dir, rgb, W, H, &vo))) figure(pg, &vo, p->index, "weight", 1, lo, hi);
            continue;
        }
        const spr_plane_type ty = spr_plane_info_of((spr_plane)q)->type;
        const int ch = spr_plane_channels((spr_plane)q);
        if (q == SPR_PLANE_ID) {
            for (size_t i = 0; i < np; i++) id_colour(v[i] < 0.0f ? -1 : (long)v[i], rgb + 3 * i);
            snprintf(vo.legend, sizeof vo.legend, "a colour per id (black: none); click for the number");
            snprintf(vo.caption, sizeof vo.caption, "id of the last write");
        } else if (ch == 4) { /* normals: (sum w*n)/(sum w) as 0.5*n + 0.5 */
            for (size_t i = 0; i < np; i++)
                for (int c = 0; c < 3; c++) rgb[3 * i + c] = v[4 * i + 3] > 0.0f ? 0.5f * (v[4 * i + c] / v[4 * i + 3]) + 0.5f : 0.0f;
            snprintf(vo.caption, sizeof vo.caption, "normal (sum w*n)/(sum w) as 0.5*n + 0.5");
        } else {
            const float clear = (float)spr_plane_info_of((spr_plane)q)->clear;
            range(v, np, 1, ty == SPR_PLANE_COUNTER || ty == SPR_PLANE_U32_IMAGE ? -2.0f : clear, &lo, &hi);
            for (size_t i = 0; i < np; i++) {
                if (v[i] == clear && ty != SPR_PLANE_COUNTER) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = 0.12f;
                else if (ty == SPR_PLANE_COUNTER && v[i] == 0.0f) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = 0.0f;
                else heat(hi > lo ? (v[i] - lo) / (hi - lo) : 1.0, rgb + 3 * i);
            }
            legend = 1;
            snprintf(vo.caption, sizeof vo.caption, "%s%s", pname,
                     ty == SPR_PLANE_COUNTER ? " (fragments that passed)" : q == SPR_PLANE_TEST ? " (test value z; grey: cleared)" : " (grey: cleared)");
        }
        snprintf(vo.file, sizeof vo.file, "p%03d_%s.png", p->index, pname);
        if (!(rc = write_view(a, dir, rgb, W, H, &vo))) figure(pg, &vo, p->index, pname, legend, lo, hi);
    }
    /* composites of the §4.2 loop: the ε-test mask and the group of the nearest layer */
    if (!rc && op && (*op == SPR_COMP_DEFERRED || *op == SPR_COMP_NEAREST) && n_inputs > 0) {
        const float *col[SPR_MAX_COMPOSITE_INPUTS], *dep[SPR_MAX_COMPOSITE_INPUTS];
        int ok = 1;
        for (int k = 0; k < n_inputs; k++) { /* the input targets as the latest pass before left them */
            const spr_captured_pass *src = NULL;
            for (const spr_captured_pass *q = all; q < p; q++)
                if (q->target == inputs[k]) src = q;
            if (!src || !src->plane[SPR_PLANE_COLOR] || !src->plane[SPR_PLANE_DEPTH]) { ok = 0; break; }
            col[k] = plane_of(src, SPR_PLANE_COLOR), dep[k] = plane_of(src, SPR_PLANE_DEPTH);
        }
        spr_probe *pr = ok ? malloc(sizeof *pr) : NULL;
        float *mask = ok ? malloc(np * sizeof *mask) : NULL;
        if (ok && pr && mask) {
            static const float no_params[SPR_PRM_COUNT];
            int maxc = 0;
            for (size_t i = 0; i < np; i++) { /* the shared §4.2 loop, its notes counted */
                spr_pixel_in px = {.color = col, .depth = dep, .i = i, .x = (int)(i % (size_t)W), .y = (int)(i / (size_t)W), .probe = pr};
                float acc[4], nacc[4], opac;
                pr->n_notes = 0;
                float dmin = spr_eps_composite(&px, n_inputs, eps_t, no_params, 0, acc, nacc, &opac);
                int blended = 0, nearest = -1;
                for (int k = 0; k < pr->n_notes; k++)
                    if (pr->note[k].tag == SPR_NOTE_EPS_INPUT && pr->note[k].v[2] != 0.0f && pr->note[k].v[0] < 1.0f) {
                        blended++;
                        if (nearest < 0 && pr->note[k].v[0] == dmin) nearest = pr->note[k].k;
                    }
                mask[i] = (float)blended;
                if (blended > maxc) maxc = blended;
                id_colour(nearest, rgb + 3 * i);
            }
            view_out vo = {"", "group of the nearest layer (argmin of the inputs' depth)", "a colour per group, as in the grouping section"};
            snprintf(vo.file, sizeof vo.file, "p%03d_group.png", p->index);
            if (!(rc = write_view(a, dir, rgb, W, H, &vo))) figure(pg, &vo, p->index, "group", 0, 0, 0);
            for (size_t i = 0; i < np; i++) {
                if (mask[i] == 0.0f) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = 0.0f;
                else heat(maxc > 1 ? (mask[i] - 1.0) / (maxc - 1.0) : 0.0, rgb + 3 * i);
            }
            view_out vm = {"", "eps-test mask: inputs within d + eps_t, blended (SPEC 4.2)", ""};
            snprintf(vm.file, sizeof vm.file, "p%03d_epsmask.png", p->index);
            if (!rc && !(rc = write_view(a, dir, rgb, W, H, &vm))) figure(pg, &vm, p->index, "epsmask", 1, 1, maxc > 1 ? maxc : 1);
        }
        free(pr);
        free(mask);
    }
    free(rgb);
    return rc;
}

/* The passes of the Gaussian references (SPEC 10): preprocessing with its records, the host's sort, the loop or the blend. */
static void gauss_header(page *pg, const spr_captured_pass *p, const spr_hist_event *ev)
{
    FILE *f = pg->f;
    if (p->records) {
        size_t kept = 0, near = 0, det = 0;
        for (size_t i = 0; i < p->n_records; i++) {
            const float cull = p->records[i * SPR_GREC_FLOATS + SPR_GREC_CULL];
            kept += cull == SPR_GCULL_NONE, near += cull == SPR_GCULL_NEAR, det += cull == SPR_GCULL_DET;
        }
        fprintf(f, "<p>Per-Gaussian preprocessing (SPEC 10.3; gauss2d 10.5) of %zu Gaussians: t = R&middot;&mu; + t, the screen covariance "
                   "&Sigma;' = (J&middot;W)&middot;R<sub>q</sub>S&sup2;R<sub>q</sub><sup>T</sup>&middot;(J&middot;W)<sup>T</sup> dilated by 0.3, its conic, "
                   "the radius ceil(3&middot;sqrt(&lambda;<sub>max</sub>)), the centre in pixel-index coordinates and the 16&times;16 tiles it touches. "
                   "%zu kept, %zu culled at the near plane, %zu degenerate.</p>", p->n_records, kept, near, det);
        fprintf(f, "<details><summary>Gaussian by Gaussian (the first 300 kept)</summary><table class=\"groups\"><tr><th>Gaussian</th><th>centre (i, j)</th>"
                   "<th>conic A, B, C</th><th>opacity</th><th>depth t.z</th><th>radius</th><th>tiles x, y</th><th>colour</th></tr>");
        size_t shown = 0;
        for (size_t i = 0; i < p->n_records && shown < 300; i++) {
            const float *R = p->records + i * SPR_GREC_FLOATS;
            if (R[SPR_GREC_CULL] != SPR_GCULL_NONE) continue;
            fprintf(f, "<tr><td>%zu</td><td>%.6g, %.6g</td><td>%.4g, %.4g, %.4g</td><td>%.4g</td><td>%.6g</td><td>%g</td><td>%g&ndash;%g, %g&ndash;%g</td>"
                       "<td>%.3g, %.3g, %.3g</td></tr>", i, R[SPR_GREC_M], R[SPR_GREC_M + 1], R[SPR_GREC_CONIC], R[SPR_GREC_CONIC + 1], R[SPR_GREC_CONIC + 2],
                    R[SPR_GREC_OPACITY], R[SPR_GREC_DEPTH], R[SPR_GREC_RADIUS], R[SPR_GREC_RECT], R[SPR_GREC_RECT + 2] - 1, R[SPR_GREC_RECT + 1],
                    R[SPR_GREC_RECT + 3] - 1, R[SPR_GREC_COLOR], R[SPR_GREC_COLOR + 1], R[SPR_GREC_COLOR + 2]);
            shown++;
        }
        fprintf(f, "</table></details>");
    } else if (!strcmp(p->name, "sort")) {
        fprintf(f, "<p>The host sorts (shared by both backends): every kept Gaussian joins the list of each tile its rectangle covers, in file "
                   "order, then each list is sorted by depth t.z, ties keeping file order (gauss-blend: every Gaussian by its distance to the eye, "
                   "farthest first). %llu Gaussians, %llu entries.</p>", (unsigned long long)p->stats.splats, (unsigned long long)p->stats.generated);
    } else if (ev && ev->kind == SPR_HIST_GAUSS_RASTER) {
        fprintf(f, "<p>Per pixel, front to back over its tile's list (SPEC %s): power from the conic (gauss2d: the ray&ndash;disk hit and the "
                   "screen low-pass), power &gt; 0 skipped, &alpha; = min(%.9g, o&middot;e<sup>power</sup>), &alpha; &lt; 1/255 skipped, "
                   "T' = T(1 &minus; &alpha;), the loop stops when T' &lt; %.9g; C += c&middot;&alpha;&middot;T. Out: C + T&middot;background, "
                   "the transmittance T, the last contributor, %s.</p>", ev->gprm[SPR_GPRM_MODE] == SPR_GMODE_2D ? "10.5" : "10.4",
                ev->gprm[SPR_GPRM_CAP], ev->gprm[SPR_GPRM_T_MIN],
                ev->gprm[SPR_GPRM_MODE] == SPR_GMODE_2D ? "the surface depth and normal" : "the inverse depth &Sigma;(1/t.z)&alpha;T");
        fprintf(f, "<p class=\"stats\">%llu Gaussians visited, %llu blended over all pixels (%.2f ms on the CPU reference).</p>",
                (unsigned long long)p->stats.generated, (unsigned long long)p->stats.passed, p->ms);
    } else if (ev) {
        fprintf(f, "<p>Each of %llu Gaussians once, farthest first, as a screen-space ellipse over its box (SPEC 10.7): cut at power &lt; "
                   "&minus;4.5 (3&sigma;), (c&middot;&alpha;, &alpha;) blended premultiplied over, dst = src + (1 &minus; &alpha;)&middot;dst.</p>"
                   "<p class=\"stats\">%llu fragments, %llu blended (%.2f ms on the CPU reference).</p>",
                (unsigned long long)p->stats.splats, (unsigned long long)p->stats.generated, (unsigned long long)p->stats.passed, p->ms);
    }
}

static void pass_header(page *pg, const spr_captured_pass *p, const spr_hist_event *ev)
{
    FILE *f = pg->f;
    fprintf(f, "<section class=\"pass\" id=\"pass%d\"><h2>Pass %d: %s", p->index, p->index, p->name);
    if (p->group >= 0) fprintf(f, " (group %d)", p->group);
    fprintf(f, "</h2>\n<div class=\"eq\">");
    if (p->records || !strcmp(p->name, "sort") || (ev && (ev->kind == SPR_HIST_GAUSS_RASTER || ev->kind == SPR_HIST_GAUSS_DRAW))) {
        gauss_header(pg, p, ev);
        fprintf(f, "</div>\n<div class=\"views\">\n");
        return;
    }
    if (!p->composite) {
        const spr_pass_state *s = &p->state;
        const int rects = ev && ev->kind == SPR_HIST_RECTS;
        fprintf(f, "<p>%s draw of %llu %s into target %d.", ev && ev->list ? "A list" : "A", (unsigned long long)p->stats.splats,
                rects ? "textured rectangles (domain primitives, SPEC 7.7, [R] 4.3&ndash;4.4)" : "splats (ray&ndash;disk test, SPEC 2)", p->target);
        if (ev && ev->list) fprintf(f, " Every fragment joins its pixel's list (t, primitive, colour); nothing is tested or written.</p>");
        else {
            fprintf(f, " Test value: %s; the depth test %s (%s); depth write %s.</p>", depth_eq[s->depth_value], func_eq[s->depth_func],
                    s->depth_func == SPR_FUNC_LESS ? "LESS" : s->depth_func == SPR_FUNC_LEQUAL ? "LEQUAL" : "ALWAYS", s->depth_write ? "on" : "off");
            fprintf(f, "<p>Fragment colour: %s; blending rgb: %s, fourth channel: %s (SPEC 3.4).",
                    rects ? "the texel's (&alpha;&middot;c, &alpha;) or as the algorithm says ([R] 3.3)"
                          : s->output == SPR_OUT_WEIGHTED ? "(w&middot;c, w) with the kernel weight w(&rho;) (SPEC 3.1, [ZP] Eq. 1)"
                                                         : "(c, &alpha;): colour and opacity (SPEC 6)",
                    blend_eq[s->blend], blend_eq[s->blend_alpha]);
            fprintf(f, " &epsilon;<sub>t</sub> = %.9g", s->eps_t);
            if (s->depth_value >= SPR_DEPTH_LOWRES) fprintf(f, ", d<sub>min</sub> = %.9g, d<sub>max</sub> = %.9g, n = %.9g", s->lowres.d_min, s->lowres.d_max, s->lowres.n);
            fprintf(f, ".</p>");
        }
        if (ev && ev->list)
            fprintf(f, "<p class=\"stats\">%llu fragments joined the lists (%.2f ms on the CPU reference).</p>", (unsigned long long)p->stats.generated, p->ms);
        else
            fprintf(f, "<p class=\"stats\">%llu fragments covered a pixel, %llu passed the depth test (%.2f ms on the CPU reference).</p>",
                    (unsigned long long)p->stats.generated, (unsigned long long)p->stats.passed, p->ms);
    } else if (ev) {
        fprintf(f, "<p>Composite <b>%s</b> of", spr_composite_info_of(ev->op)->name);
        for (int k = 0; k < ev->n_inputs; k++) fprintf(f, " t%d", ev->inputs[k]);
        fprintf(f, " into t%d: ", ev->target);
        html_escape(f, spr_composite_info_of(ev->op)->summary);
        if (ev->op == SPR_COMP_DEFERRED || ev->op == SPR_COMP_NEAREST)
            fprintf(f, ". Per pixel: d = min<sub>k</sub> d<sub>f</sub>(k); input k is blended when d<sub>f</sub>(k) &le; d + &epsilon;<sub>t</sub> "
                       "(&epsilon;<sub>t</sub> = %.9g), then C = &Sigma;(w&middot;c) / &Sigma;w ([ZP] Fig. 6, SPEC 4.2)",
                    ev->eps_t);
        fprintf(f, ".</p>");
    }
    fprintf(f, "</div>\n<div class=\"views\">\n");
}

/* Embedded data: every plane of every pass, base64 float32 (little-endian
 * host, as the PFM writer assumes). */
static void data_script(page *pg, const spr_capture *cc)
{
    FILE *f = pg->f;
    const size_t np = (size_t)pg->W * pg->H;
    fprintf(f, "<script>\nconst SPR = {w: %d, h: %d, passes: [\n", pg->W, pg->H);
    for (int i = 0; i < cc->n; i++) {
        const spr_captured_pass *p = &cc->passes[i];
        fprintf(f, " {index: %d, name: \"%s\", group: %d, planes: {", p->index, p->name, p->group);
        int first = 1;
        for (int q = 0; q < SPR_PLANE__COUNT; q++) {
            if (!plane_of(p, q)) continue;
            fprintf(f, "%s\"%s\": [%d, \"", first ? "" : ", ", spr_plane_name((spr_plane)q), spr_plane_channels((spr_plane)q));
            base64(f, (const unsigned char *)plane_of(p, q), np * (size_t)spr_plane_channels((spr_plane)q) * 4);
            fprintf(f, "\"]");
            first = 0;
        }
        fprintf(f, "}},\n");
    }
    fprintf(f, "], histories: {}};\n</script>\n");
}

static const char *const page_css =
    "body{font-family:sans-serif;margin:1.5em;max-width:1400px;color:#222}h1{font-size:1.5em}h2{font-size:1.2em;border-top:1px solid #ccc;"
    "padding-top:.6em}.eq{background:#f6f6f2;padding:.2em .8em;border-left:3px solid #8a8}.views{display:flex;flex-wrap:wrap;gap:12px}"
    "figure{margin:0;font-size:.8em;max-width:%dpx}img.plane{image-rendering:pixelated;cursor:crosshair;border:1px solid #999}"
    ".legend{display:flex;align-items:center;gap:4px}.legend .bar{display:inline-block;width:120px;height:10px}"
    "#info{position:sticky;top:0;background:#fff;border:1px solid #bbb;padding:.5em;max-height:45vh;overflow:auto;font-size:.85em;z-index:2}"
    "#info table{border-collapse:collapse}#info td{padding:1px 6px;border-bottom:1px solid #eee;font-family:monospace}"
    "pre{font-size:.75em;overflow:auto;background:#fafafa;border:1px solid #ddd;padding:.4em}.note{color:#555}#tip{position:fixed;"
    "background:#ffd;border:1px solid #aa8;padding:2px 5px;font:12px monospace;pointer-events:none;display:none}"
    "table.groups td,table.groups th{padding:1px 6px;font-size:.8em;border-bottom:1px solid #eee}table.bwd td{font-family:monospace;white-space:nowrap;vertical-align:top}.wide{overflow-x:auto}pre.bwdeq{font-size:.9em}";

/* The page's script: decode the planes, show a pixel's values on click,
 * one value on hover; #test=X,Y clicks that pixel once the pictures have
 * loaded and reports into #selftest (the browser test). */
static const char *const page_js =
    "const errors=[];window.addEventListener('error',e=>{errors.push(String(e.message))});\n"
    "const oe=console.error;console.error=function(...a){errors.push(a.join(' '));oe.apply(console,a)};\n"
    "function dec(b64){const s=atob(b64);const u=new Uint8Array(s.length);for(let i=0;i<s.length;i++)u[i]=s.charCodeAt(i);return new Float32Array(u.buffer)}\n"
    "for(const p of SPR.passes){for(const k in p.planes){const e=p.planes[k];p.planes[k]={ch:e[0],v:dec(e[1])}}}\n"
    "function fmt(x){return Number.isInteger(x)?String(x):x.toPrecision(9)}\n"
    "function val(p,k,x,y){const e=p.planes[k];if(!e)return null;const i=(y*SPR.w+x)*e.ch;return Array.from(e.v.subarray(i,i+e.ch))}\n"
    "function show(x,y){const el=document.getElementById('info');let h='<b>pixel x '+x+', y '+y+'</b> (from the bottom, GL; row '+(SPR.h-1-y)+' from the top)"
    "<table><tr><th>pass</th><th>plane</th><th>value</th></tr>';\n"
    " for(const p of SPR.passes){for(const k in p.planes){const v=val(p,k,x,y);h+='<tr><td>'+p.index+' '+p.name+(p.group>=0?' k'+p.group:'')+'</td><td>'+k+"
    "'</td><td class=\"v\" data-pass=\"'+p.index+'\" data-plane=\"'+k+'\" data-value=\"'+v.map(fmt).join(',')+'\">'+v.map(fmt).join(', ')+'</td></tr>'}}\n"
    " h+='</table>';const key=x+','+y;if(SPR.histories[key])h+='<p>Pixel history (splatref explain):</p><pre>'+SPR.histories[key]+'</pre>';"
    "else h+='<p>Its full history: <code>splatref explain --scene scene.json --pixel '+key+'</code></p>';el.innerHTML=h;el.dataset.pixel=key}\n"
    "function at(img,ev){const r=img.getBoundingClientRect();const x=Math.floor((ev.clientX-r.left)*SPR.w/r.width);"
    "const yt=Math.floor((ev.clientY-r.top)*SPR.h/r.height);return[Math.min(SPR.w-1,Math.max(0,x)),Math.min(SPR.h-1,Math.max(0,SPR.h-1-yt))]}\n"
    "const tip=document.getElementById('tip');\n"
    "for(const img of document.querySelectorAll('img.plane')){img.addEventListener('click',ev=>{const [x,y]=at(img,ev);show(x,y)});\n"
    " img.addEventListener('mousemove',ev=>{const [x,y]=at(img,ev);const p=SPR.passes.find(q=>q.index==img.dataset.pass);"
    "const v=p?val(p,img.dataset.plane,x,y):null;tip.style.display='block';tip.style.left=(ev.clientX+12)+'px';tip.style.top=(ev.clientY+12)+'px';"
    "tip.textContent=x+','+y+(v?': '+v.map(fmt).join(', '):'')});img.addEventListener('mouseleave',()=>{tip.style.display='none'})}\n"
    "for(const a of document.querySelectorAll('a.px')){a.addEventListener('click',ev=>{ev.preventDefault();const [x,y]=a.dataset.px.split(',').map(Number);show(x,y)})}\n"
    "function selftest(){const imgs=[...document.getElementsByTagName('img')];const bad=imgs.filter(i=>!(i.complete&&i.naturalWidth>0));"
    "const m=/test=(\\d+),(\\d+)/.exec(location.hash);if(m){const x=+m[1],y=+m[2];const img=document.querySelector('img.plane');"
    "const r=img.getBoundingClientRect();const cx=r.left+(x+0.5)*r.width/SPR.w,cy=r.top+(SPR.h-1-y+0.5)*r.height/SPR.h;"
    "img.dispatchEvent(new MouseEvent('click',{clientX:cx,clientY:cy,bubbles:true}))}\n"
    " const st=document.getElementById('selftest');st.dataset.images=imgs.length;st.dataset.decoded=imgs.length-bad.length;"
    "st.dataset.errors=errors.length;st.textContent='images '+(imgs.length-bad.length)+'/'+imgs.length+' decoded; '+errors.length+' errors'+(errors.length?': '+errors.join(' | '):'')}\n"
    "window.addEventListener('load',selftest);\n";

/* The grouping section: sizes, the rule, and for a small cloud which
 * splat went where with its overlapping neighbours' groups. */
static void grouping_section(page *pg, const spr_scene *s)
{
    FILE *f = pg->f;
    const spr_groups *g = &s->g.groups;
    fprintf(f, "<section id=\"grouping\"><h2>Grouping: %s, K = %d (SPEC 5)</h2><div class=\"eq\"><p>", s->group_method ? s->group_method : "none", g->K);
    const char *m = s->group_method ? s->group_method : "none";
    if (!strcmp(m, "mgc"))
        fprintf(f, "MGC ([ZP] 4.1, SPEC 5.1): splats are visited largest degree first in the conflict graph (splats that overlap, "
                   "relaxed by c for coplanar or opposite neighbours); each takes the smallest group no conflicting neighbour already has.");
    else if (!strcmp(m, "wgc"))
        fprintf(f, "WGC ([ZP] 4.2, SPEC 5.2): K groups; each splat goes to the group where its overlap area with same-group neighbours "
                   "([ZP] Eq. 8) is smallest, then local moves reduce the total.");
    else if (!strcmp(m, "hash"))
        fprintf(f, "Hash grouping ([ZP] 4.3, Eq. 9, SPEC 5.3): a splat's group is a hash of its quantised position along an axis, "
                   "(x + 3y) mod K, so neighbours on a surface land in different groups without a graph.");
    else fprintf(f, "One group: nothing overlapping inside it can blend.");
    fprintf(f, " Overlapping neighbours in the same group cannot blend: one hides the other in that group's target.</p></div>\n");
    fprintf(f, "<table class=\"groups\"><tr><th>group</th><th>colour</th><th>splats</th></tr>");
    for (int k = 0; k < g->K; k++) {
        float c[3];
        id_colour(k, c);
        fprintf(f, "<tr><td>%d</td><td style=\"background:rgb(%d,%d,%d)\"></td><td>%zu</td></tr>", k, (int)(c[0] * 255), (int)(c[1] * 255),
                (int)(c[2] * 255), (size_t)(g->start[k + 1] - g->start[k]));
    }
    fprintf(f, "</table>\n");
    const size_t n = s->cloud.n;
    if (n > 4000 || !s->g.labels) {
        fprintf(f, "<p class=\"note\">%zu splats: the splat-by-splat table is written for clouds of at most 4,000 (try --points 1500).</p></section>\n", n);
        return;
    }
    spr_overlap_graph og;
    spr_error err = {0};
    memset(&og, 0, sizeof og);
    if (spr_overlap_graph_build(&s->cloud, 1e-6, s->threads, NULL, &og, &err)) {
        fprintf(f, "<p class=\"note\">overlap graph: %s</p></section>\n", err.msg);
        return;
    }
    size_t same = 0;
    for (size_t i = 0; i < n; i++)
        for (uint64_t e = og.g.start[i]; e < og.g.start[i + 1]; e++) same += s->g.labels[og.g.adj[e]] == s->g.labels[i];
    fprintf(f, "<p>%zu overlapping pairs; %zu of them inside one group (those cannot blend with each other).</p>", (size_t)(og.g.start[n] / 2), same / 2);
    fprintf(f, "<details><summary>splat by splat (first 400)</summary><table class=\"groups\"><tr><th>splat</th><th>position</th><th>radius</th><th>group</th>"
               "<th>overlapping neighbours</th><th>their groups</th></tr>");
    for (size_t i = 0; i < n && i < 400; i++) {
        const float *p = s->cloud.pos + 3 * i;
        fprintf(f, "<tr><td>%zu</td><td>%.4g, %.4g, %.4g</td><td>%.4g</td><td>%d</td><td>%llu</td><td>", i, p[0], p[1], p[2], s->cloud.radius[i],
                s->g.labels[i], (unsigned long long)(og.g.start[i + 1] - og.g.start[i]));
        int cnt[SPR_MAX_GROUPS] = {0};
        for (uint64_t e = og.g.start[i]; e < og.g.start[i + 1]; e++) {
            int32_t l = s->g.labels[og.g.adj[e]];
            if (l >= 0 && l < SPR_MAX_GROUPS) cnt[l]++;
        }
        for (int k = 0; k < g->K && k < SPR_MAX_GROUPS; k++)
            if (cnt[k]) fprintf(f, "%s%d&times;%d", k == s->g.labels[i] ? "<b>" : "", cnt[k], k), fprintf(f, "%s ", k == s->g.labels[i] ? "</b>" : "");
        fprintf(f, "</td></tr>");
    }
    fprintf(f, "</table></details></section>\n");
    spr_overlap_graph_free(&og);
}

/* ---- the backward pass (SPEC 10.10, docs/gradients.md): one pixel and one Gaussian ---- */
/* n floats as "a, b, c" (%.9g: a float's bits). */
static void fvals(FILE *f, const float *v, int n)
{
    for (int k = 0; k < n; k++) fprintf(f, "%s%.9g", k ? ", " : "", v[k]);
}
/* the same in a table's cell: one value a line */
static void fcell(FILE *f, const float *v, int n)
{
    for (int k = 0; k < n; k++) fprintf(f, "%s%.9g", k ? "<br>" : "", v[k]);
}

/* A list entry's partial (or a pixel's terms) as the last cells of a row: colour, conic, centre, absgrad; the row ends. */
static void part_cells(FILE *f, const float *part)
{
    fcell(f, part + SPR_GPART_COLOR, 3);
    fprintf(f, "</td><td>");
    fcell(f, part + SPR_GPART_CONIC, 3);
    fprintf(f, "</td><td>");
    fcell(f, part + SPR_GPART_M, 2);
    fprintf(f, "</td><td>");
    fcell(f, part + SPR_GPART_ABS, 2);
    fprintf(f, "</td></tr>\n");
}

typedef struct grad_view {
    const spr_gauss_grads *g;
    const spr_grad_explain *x;
    const spr_grad_desc *gd;
    const float *bg;
    const spr_gauss_profile *pf;
    const float *rec; /* the preprocessing's records (SPR_GREC_FLOATS a Gaussian), or NULL */
    const spr_history *h; /* the page's chosen pixel (its history), or NULL */
} grad_view;

/* One step of the pixel's reverse walk, as spr_gauss_blend_bwd computes it. */
typedef struct bwd_row {
    int G, rank;
    float power, alpha, T, ab, Tk, acc[4], dc[4], td, tb, va, vo, vp, dp[5];
    int gated;
} bwd_row;

/* The pixel's upstream gradient (∂L/∂C, ∂L/∂A, ∂L/∂D), as the backward's host computes it from the forward's image. */
static void pixel_upstream(const spr_grad_desc *gd, const float *rgba, int W, int H, size_t i, float up[5])
{
    const double inv = 1.0 / (3.0 * (double)((size_t)W * H));
    for (int ch = 0; ch < 3; ch++) {
        double v;
        if (gd->loss == SPR_LOSS_GIVEN) v = gd->dl_dimage[3 * i + ch];
        else {
            const double r = (double)rgba[4 * i + ch] - (gd->target ? (double)gd->target[3 * i + ch] : 0.0);
            v = gd->loss == SPR_LOSS_L1 ? (r > 0.0 ? 1.0 : r < 0.0 ? -1.0 : 0.0) * inv : 2.0 * r * inv;
        }
        up[ch] = (float)v;
    }
    up[3] = gd->dl_dalpha ? gd->dl_dalpha[i] : 0.0f;
    up[4] = gd->dl_ddepth ? gd->dl_ddepth[i] : 0.0f;
}

static const char *const bwd_eq =
    "<p>g = &part;L/&part;C at the pixel (the upstream gradient), bg the background, T<sub>f</sub> the forward's final T. The walk runs back to front "
    "over the Gaussians the forward blended, with the forward's own &alpha; and T (SPEC 10.10 item 3), and inria's recurrence for the colour behind:</p>"
    "<pre class=\"bwdeq\">acc        = &alpha;'&middot;c' + (1 &minus; &alpha;')&middot;acc            (&alpha;', c': the Gaussian walked before, i.e. behind; acc = 0 at first;"
    " a 4th channel carries 1/t.z)\n"
    "&part;L/&part;c<sub>k</sub>    = (&alpha;<sub>k</sub>&middot;T<sub>k</sub>)&middot;g\n"
    "&part;L/&part;&alpha;<sub>k</sub>    = T<sub>k</sub>&middot;&Sigma;<sub>ch</sub>(c<sub>k</sub> &minus; acc)&middot;g  &minus;  "
    "(T<sub>f</sub>/(1 &minus; &alpha;<sub>k</sub>))&middot;(&lang;bg, g&rang; &minus; &part;L/&part;A)     (the 4th channel: (1/t.z &minus; acc)&middot;&part;L/&part;D)\n"
    "&alpha;<sub>k</sub>       = min(cap, o<sub>k</sub>&middot;G<sub>k</sub>),  G<sub>k</sub> = e<sup>power<sub>k</sub></sup>\n"
    "power<sub>k</sub>   = &minus;&frac12;(A dx&sup2; + C dy&sup2;) &minus; B dx dy,  (dx, dy) = m &minus; pixel\n"
    "&part;L/&part;o      = G&middot;&part;L/&part;&alpha;,   &part;L/&part;power = o&middot;G&middot;&part;L/&part;&alpha;     "
    "(both 0 where o&middot;G &gt; cap under a profile with the cap gate)\n"
    "&part;L/&part;(A, B, C) = &part;L/&part;power&middot;(&minus;&frac12;dx&sup2;, &minus;dx&middot;dy, &minus;&frac12;dy&sup2;)\n"
    "&part;L/&part;m      = &part;L/&part;power&middot;(&minus;(A dx + B dy), &minus;(B dx + C dy))        (means2d, pixels)</pre>";

/* The chosen pixel: its blended Gaussians walked back to front. */
static void backward_pixel(page *pg, const grad_view *gv, size_t Gsel)
{
    FILE *f = pg->f;
    const int W = pg->W, H = pg->H;
    const spr_history *h = gv->h;
    if (!h) {
        fprintf(f, "<h3 id=\"backward-pixel\">The chosen pixel</h3><p class=\"note\">No pixel is embedded (--pixels 0): give --pixels 1 or more.</p>\n");
        return;
    }
    fprintf(f, "<h3 id=\"backward-pixel\">Pixel x %d, y %d (row %d from the top): its blended Gaussians, back to front</h3>\n", h->x, h->y, H - 1 - h->y);
    const spr_hist_event *ev = NULL;
    for (int e = 0; e < h->n; e++)
        if (h->ev[e].kind == SPR_HIST_GAUSS_RASTER) ev = &h->ev[e];
    if (!ev || !gv->rec) {
        fprintf(f, "<p class=\"note\">The pixel's history has no Gaussian raster call or the frame no records: nothing to walk.</p>\n");
        return;
    }
    if (h->overflow) fprintf(f, "<p class=\"note\">The pixel's history overflowed (more than %d notes): the walk below is incomplete.</p>\n", SPR_PROBE_MAX);
    const float *g = ev->gprm;
    int nb = 0, tile = -1;
    float Tf = 1.0f;
    for (int k = 0; k < ev->n_notes; k++) {
        const spr_probe_note *n = &ev->notes[k];
        if (n->tag == SPR_NOTE_GAUSS_BLEND) nb++;
        else if (n->tag == SPR_NOTE_GAUSS_TILE) tile = n->k;
        else if (n->tag == SPR_NOTE_GAUSS_END) Tf = n->v[0];
    }
    bwd_row *rows = nb ? calloc((size_t)nb, sizeof *rows) : NULL;
    if (nb && !rows) { fprintf(f, "<p class=\"note\">out of memory</p>\n"); return; }
    int r = 0;
    for (int k = 0; k < ev->n_notes; k++) { /* front to back, as the forward blended them */
        const spr_probe_note *n = &ev->notes[k];
        if (n->tag != SPR_NOTE_GAUSS_BLEND) continue;
        rows[r].G = n->k, rows[r].rank = r, rows[r].power = n->v[0], rows[r].alpha = n->v[1], rows[r].T = n->v[2];
        r++;
    }
    const size_t i = (size_t)h->y * W + (size_t)h->x;
    float up[5];
    pixel_upstream(gv->gd, gv->g->image, W, H, i, up);
    const float fi = (float)h->x, fj = (float)(H - 1 - h->y);
    const unsigned fp = spr__grad_fp_enter(); /* the backend's float environment, for the host's retrace of the pixel */
    const float bgg = spr_sum3(gv->bg[0], up[0], gv->bg[1], up[1], gv->bg[2], up[2]);
    const float bt = bgg - up[3];
    float acc[4] = {0, 0, 0, 0}, behind[5] = {0, 0, 0, 0, 0};
    const float gk[4] = {up[0], up[1], up[2], up[4]};
    float Tb = Tf;
    for (int k = nb - 1; k >= 0; k--) { /* spr_gauss_tile_bwd's profile rules, then spr_gauss_blend_bwd, operation by operation */
        bwd_row *w = &rows[k];
        w->ab = w->alpha, w->Tk = w->T;
        if (g[SPR_GPRM_CAP_BWD] > 0.0f && w->ab > g[SPR_GPRM_CAP_BWD]) w->ab = g[SPR_GPRM_CAP_BWD];
        if (g[SPR_GPRM_TDIV] != 0.0f) { /* T recovered by division from T_f (OpenSplat) */
            const float om = 1.0f - w->ab, ra = 1.0f / om;
            Tb = Tb * ra;
            w->Tk = Tb;
        }
        const float *R = gv->rec + (size_t)w->G * SPR_GREC_FLOATS;
        const float c[4] = {R[SPR_GREC_COLOR], R[SPR_GREC_COLOR + 1], R[SPR_GREC_COLOR + 2], R[SPR_GREC_INVZ]};
        const float ob = 1.0f - behind[4];
        for (int ch = 0; ch < 4; ch++) {
            const float xx = behind[4] * behind[ch];
            const float yy = ob * acc[ch];
            acc[ch] = xx + yy;
        }
        const float aT = w->ab * w->Tk;
        float d = 0.0f;
        for (int ch = 0; ch < 4; ch++) {
            w->dc[ch] = aT * gk[ch];
            const float df = c[ch] - acc[ch];
            const float dg = df * gk[ch];
            d = d + dg;
        }
        w->td = w->Tk * d;
        const float oma = 1.0f - w->ab, tf = Tf / oma;
        w->tb = tf * bt;
        w->va = w->td - w->tb;
        memcpy(w->acc, acc, sizeof acc);
        const float power = spr_gauss_power(R[SPR_GREC_M], R[SPR_GREC_M + 1], R[SPR_GREC_CONIC], R[SPR_GREC_CONIC + 1], R[SPR_GREC_CONIC + 2], fi, fj);
        spr_gauss_alpha_bwd(g, R[SPR_GREC_OPACITY], power, w->va, &w->vo, &w->vp);
        spr_gauss_power_bwd(R[SPR_GREC_M], R[SPR_GREC_M + 1], R[SPR_GREC_CONIC], R[SPR_GREC_CONIC + 1], R[SPR_GREC_CONIC + 2], fi, fj, w->vp, w->dp);
        if (g[SPR_GPRM_HALF_B] != 0.0f) w->dp[1] = 0.5f * w->dp[1]; /* the profile's halved off-diagonal (OpenSplat) */
        const float oe = R[SPR_GREC_OPACITY] * spr_exp(power);
        w->gated = oe > g[SPR_GPRM_CAP] && g[SPR_GPRM_GATE] != 0.0f;
        for (int ch = 0; ch < 4; ch++) behind[ch] = c[ch];
        behind[4] = w->ab;
    }
    spr__grad_fp_leave(fp);
    const float *C = gv->g->image + 4 * i;
    fprintf(f, "<p>Tile %d; %d Gaussians blended; C = (", tile, nb);
    fvals(f, C, 3);
    fprintf(f, "), T<sub>f</sub> = %.9g, bg = (", Tf);
    fvals(f, gv->bg, 3);
    fprintf(f, "). Upstream: g = &part;L/&part;C = (");
    fvals(f, up, 3);
    fprintf(f, ")%s, &part;L/&part;A = %.9g, &part;L/&part;D = %.9g; &lang;bg, g&rang; &minus; &part;L/&part;A = %.9g. Profile %s: cap %.9g, cap gate %s.</p>\n",
            gv->gd->loss == SPR_LOSS_L2 ? " (2(C &minus; target)/(3WH))" : gv->gd->loss == SPR_LOSS_L1 ? " (sign(C &minus; target)/(3WH))" : " (given)",
            up[3], up[4], bt, gv->pf->name, g[SPR_GPRM_CAP], g[SPR_GPRM_GATE] != 0.0f ? "on" : "off (&part;&alpha;/&part;o = G even when capped)");
    if (g[SPR_GPRM_CAP_BWD] > 0.0f || g[SPR_GPRM_TDIV] != 0.0f || g[SPR_GPRM_HALF_B] != 0.0f) {
        fprintf(f, "<p>The profile's backward rules (SPEC 10.10 item 3):");
        if (g[SPR_GPRM_CAP_BWD] > 0.0f) fprintf(f, " its own &alpha; cap %.9g;", g[SPR_GPRM_CAP_BWD]);
        if (g[SPR_GPRM_TDIV] != 0.0f) fprintf(f, " T recovered by division from T<sub>f</sub>, T<sub>k</sub> = T<sub>k+1</sub>/(1 &minus; &alpha;<sub>k</sub>);");
        if (g[SPR_GPRM_HALF_B] != 0.0f) fprintf(f, " &part;L/&part;B halved;");
        fprintf(f, " where the backward's &alpha; or T differs from the forward's, the cell shows the backward's and then the forward's.</p>\n");
    }
    fprintf(f, "<div class=\"eq\">%s</div>\n", bwd_eq);
    fprintf(f, "<div class=\"wide\"><table class=\"groups bwd\" id=\"backward-pixel-table\"><tr><th>step</th><th>k (1: front)</th><th>Gaussian</th><th>power</th><th>&alpha;</th>"
               "<th>T</th><th>acc (r, g, b, 1/z)</th><th>&part;L/&part;&alpha;</th><th>= T&middot;&Sigma;(c &minus; acc)&middot;g</th>"
               "<th>&minus; background term</th><th>&part;L/&part;o</th><th>&part;L/&part;power</th><th>&part;L/&part;(A, B, C)</th><th>&part;L/&part;m</th>"
               "<th>&part;L/&part;c</th></tr>\n");
    const bwd_row *mine = NULL;
    for (int k = nb - 1, step = 1; k >= 0; k--, step++) {
        const bwd_row *w = &rows[k];
        if ((size_t)w->G == Gsel) mine = w;
        fprintf(f, "<tr class=\"bpx\"%s><td>%d</td><td>%d</td><td>%d</td><td>%.9g</td><td>%.9g", (size_t)w->G == Gsel ? " style=\"background:#ffe\"" : "",
                step, k + 1, w->G, w->power, w->ab);
        if (memcmp(&w->ab, &w->alpha, sizeof w->ab)) fprintf(f, "<br>(forward %.9g)", w->alpha);
        fprintf(f, "</td><td>%.9g", w->Tk);
        if (memcmp(&w->Tk, &w->T, sizeof w->Tk)) fprintf(f, "<br>(forward %.9g)", w->T);
        fprintf(f, "</td><td>");
        fcell(f, w->acc, 4);
        fprintf(f, "</td><td>%.9g</td><td>%.9g</td><td>%.9g</td><td>%.9g%s</td><td>%.9g</td><td>", w->va, w->td, w->tb, w->vo, w->gated ? " (gated)" : "", w->vp);
        fcell(f, w->dp, 3);
        fprintf(f, "</td><td>");
        fcell(f, w->dp + 3, 2);
        fprintf(f, "</td><td>");
        fcell(f, w->dc, 3);
        fprintf(f, "</td></tr>\n");
    }
    fprintf(f, "</table></div>\n");
    /* G's row, when G blends here, against the backward's own term for this pixel (spr_gauss_grad_explain) */
    const spr_grad_term *t = NULL;
    for (size_t p = 0; p < gv->x->n_terms; p++)
        if (gv->x->terms[p].x == h->x && gv->x->terms[p].y == h->y) t = &gv->x->terms[p];
    if (!mine) fprintf(f, "<p class=\"note\">Gaussian %zu does not blend at this pixel.</p>\n", Gsel);
    else if (t) {
        /* the forward's α and T, and the terms the backward itself added to G's partial at this pixel */
        int same = !memcmp(&mine->alpha, &t->alpha, sizeof t->alpha) && !memcmp(&mine->T, &t->T, sizeof t->T) &&
                   !memcmp(&mine->vo, t->part + SPR_GPART_OPACITY, sizeof(float)) && !memcmp(mine->dp, t->part + SPR_GPART_CONIC, 3 * sizeof(float)) &&
                   !memcmp(mine->dp + 3, t->part + SPR_GPART_M, 2 * sizeof(float)) && !memcmp(mine->dc, t->part + SPR_GPART_COLOR, 4 * sizeof(float));
        fprintf(f, "<p id=\"backward-pixel-check\" data-same=\"%s\">Gaussian %zu's row (highlighted): its terms (&part;L/&part;c, &part;L/&part;o, "
                   "&part;L/&part;(A, B, C), &part;L/&part;m) equal what the backward added to its partial at this pixel (the table below) bit for bit: "
                   "<b>%s</b>.</p>\n", same ? "yes" : "no", Gsel, same ? "yes" : "no");
    }
    free(rows);
}

/* Gaussian G: its pixels in summation order, the tiles' partials, the sums against splatref grad's arrays, and the chain. */
static int backward_gaussian(page *pg, const grad_view *gv)
{
    FILE *f = pg->f;
    const int W = pg->W, H = pg->H;
    const spr_grad_explain *x = gv->x;
    const spr_gauss_grads *g = gv->g;
    const size_t G = x->G;
    fprintf(f, "<h3 id=\"backward-gaussian\">Gaussian %zu: every pixel that gave it a gradient, in summation order</h3>\n", G);
    if (gv->rec) {
        const float *R = gv->rec + G * SPR_GREC_FLOATS;
        fprintf(f, "<p>Its record: centre m = (%.9g, %.9g), conic (A, B, C) = (%.9g, %.9g, %.9g), opacity o = %.9g, colour c = (%.9g, %.9g, %.9g), "
                   "depth t.z = %.9g.</p>\n", R[SPR_GREC_M], R[SPR_GREC_M + 1], R[SPR_GREC_CONIC], R[SPR_GREC_CONIC + 1], R[SPR_GREC_CONIC + 2],
                R[SPR_GREC_OPACITY], R[SPR_GREC_COLOR], R[SPR_GREC_COLOR + 1], R[SPR_GREC_COLOR + 2], R[SPR_GREC_DEPTH]);
    }
    fprintf(f, "<div class=\"eq\"><p>The order of the sums (SPEC 10.10 item 4): each tile that lists Gaussian %zu owns a partial, its pixels' terms "
               "added in float in the tile's row-major order from the top row; G's value is those partials added in tile order. Per pixel the terms "
               "are the equations above: &part;L/&part;c = &alpha;T&middot;g (colors), &part;L/&part;o (opacities), &part;L/&part;(A, B, C) (conics), "
               "&part;L/&part;m (means2d), |&part;L/&part;m| per axis (absgrad) and 1 (counts).</p></div>\n", G);
    fprintf(f, "<p id=\"backward-count\" data-pixels=\"%zu\" data-tiles=\"%zu\">%zu pixels in %zu tiles gave Gaussian %zu a gradient.</p>\n", x->n_terms,
            x->n_tiles, x->n_terms, x->n_tiles, G);
    const size_t cap = 20000;
    if (x->n_terms > cap)
        fprintf(f, "<p class=\"note\">The first %zu pixels are listed (the partials and sums below count them all); every one: "
                   "<code>splatref explain --scene scene.json --gaussian %zu --grad</code> with the same upstream options.</p>\n", cap, G);
    fprintf(f, "<details open><summary>pixel by pixel</summary><div class=\"wide\"><table class=\"groups bwd\" id=\"backward-gaussian-table\"><tr><th>pixel x, y</th>"
               "<th>row from the top</th><th>k of blended</th><th>power</th><th>&alpha;</th><th>T</th><th>acc (r, g, b, 1/z)</th><th>&part;L/&part;&alpha;</th>"
               "<th>&part;L/&part;o</th><th>&part;L/&part;power</th><th>colors</th><th>conics</th><th>means2d</th><th>absgrad</th></tr>\n");
    size_t shown = 0;
    for (size_t k = 0; k < x->n_tiles; k++) {
        const spr_grad_tile *t = &x->tiles[k];
        const int gx = (W + 15) / 16, i0 = (t->tile % gx) * 16, j0 = (t->tile / gx) * 16;
        fprintf(f, "<tr class=\"gtile\"><th colspan=\"14\" style=\"text-align:left;background:#eef\">tile %d (list entry %u; x %d&ndash;%d, rows %d&ndash;%d "
                   "from the top): %zu pixel%s</th></tr>\n", t->tile, t->entry, i0, i0 + 15 < W ? i0 + 15 : W - 1, j0, j0 + 15 < H ? j0 + 15 : H - 1,
                t->count, t->count == 1 ? "" : "s");
        for (size_t p = t->first; p < t->first + t->count; p++) {
            if (shown++ >= cap) continue;
            const spr_grad_term *m = &x->terms[p];
            const int chosen = gv->h && gv->h->x == m->x && gv->h->y == m->y;
            fprintf(f, "<tr class=\"gpx\"%s><td>%d, %d</td><td>%d</td><td>%d of %d</td><td>%.9g</td><td>%.9g</td><td>%.9g</td><td>", chosen ? " style=\"background:#ffe\"" : "",
                    m->x, m->y, H - 1 - m->y, m->rank + 1, m->blended, m->power, m->alpha, m->T);
            fcell(f, m->acc, 4);
            fprintf(f, "</td><td>%.9g</td><td>%.9g%s</td><td>%.9g</td><td>", m->dl_dalpha, m->dl_do, m->gated ? " (gated)" : "", m->dl_dpower);
            part_cells(f, m->part);
        }
        fprintf(f, "<tr class=\"gpart\" style=\"font-weight:bold\"><td colspan=\"7\">partial of tile %d</td><td></td><td>%.9g</td><td>count %.9g</td><td>", t->tile,
                t->part[SPR_GPART_OPACITY], t->part[SPR_GPART_COUNT]);
        part_cells(f, t->part);
    }
    fprintf(f, "</table></div></details>\n");
    /* the sums against splatref grad's arrays, bit for bit */
    static const struct { const char *name; int off, n; } arr[] = {
        {"colors", SPR_GPART_COLOR, 3}, {"opacities", SPR_GPART_OPACITY, 1}, {"conics", SPR_GPART_CONIC, 3}, {"means2d", SPR_GPART_M, 2}, {"absgrad", SPR_GPART_ABS, 2}};
    const float *have[] = {g->colors + 3 * G, g->opacities + G, g->conics + 3 * G, g->means2d + 2 * G, g->absgrad + 2 * G};
    fprintf(f, "<table class=\"groups bwd\" id=\"backward-sums\"><tr><th>array</th><th>the partials summed in tile order</th><th>splatref grad's value "
               "(spr_gauss_grad)</th><th>bit-identical</th></tr>\n");
    int same = 1;
    for (int a = 0; a < 5; a++) {
        const int eq = !memcmp(x->sum + arr[a].off, have[a], (size_t)arr[a].n * sizeof(float));
        same &= eq;
        fprintf(f, "<tr><td>%s[%zu]</td><td>", arr[a].name, G);
        fvals(f, x->sum + arr[a].off, arr[a].n);
        fprintf(f, "</td><td>");
        fvals(f, have[a], arr[a].n);
        fprintf(f, "</td><td>%s</td></tr>\n", eq ? "yes" : "<b>NO</b>");
    }
    const int ceq = (double)x->sum[SPR_GPART_COUNT] == (double)g->counts[G];
    same &= ceq;
    fprintf(f, "<tr><td>counts[%zu]</td><td>%.9g</td><td>%d</td><td>%s</td></tr></table>\n", G, x->sum[SPR_GPART_COUNT], (int)g->counts[G], ceq ? "yes" : "<b>NO</b>");
    fprintf(f, "<p id=\"backward-bits\" data-same=\"%s\">These sums equal <code>splatref grad</code>'s values for Gaussian %zu bit for bit: <b>%s</b>.</p>\n",
            same ? "yes" : "no", G, same ? "yes" : "no");
    if (!x->consistent)
        fprintf(f, "<p class=\"note\">Warning: a pixel's recomputed &part;L/&part;o differs from the term the shared arithmetic added (the intermediates "
                   "above do not retrace it).</p>\n");
    /* the chain */
    fprintf(f, "<h3 id=\"backward-chain\">From Gaussian %zu's sums to its parameters</h3>\n<div class=\"eq\"><p>The chain runs SPEC 10.3 backwards, per "
               "Gaussian (arith/gauss.h, spr_gauss_preprocess3d_bwd): conics &rarr; &Sigma;&prime; = conic<sup>&minus;1</sup> &rarr; "
               "&Sigma; = &Sigma;&prime; &minus; %g&middot;I (the profile's dilation) = J&middot;W&middot;&Sigma;<sub>3</sub>&middot;W<sup>T</sup>&middot;J<sup>T</sup> &rarr; "
               "&Sigma;<sub>3</sub> = R&middot;S&middot;S<sup>T</sup>&middot;R<sup>T</sup> &rarr; quats (the unit quaternion's tangent part) and scales; "
               "means2d and J's dependence on t &rarr; means; 1/t.z (from &part;L/&part;D) &rarr; means; opacities pass as they are; colors &rarr; the "
               "SH coefficients sh0 and shN through the basis of the view direction (on the host, in double, rounded once), and the direction's share "
               "&rarr; means.</p></div>\n", G, gv->pf->dilation.eps2d);
    fprintf(f, "<table class=\"groups bwd\" id=\"backward-chain-table\"><tr><th></th><th>value</th></tr>\n");
    fprintf(f, "<tr><th colspan=\"2\" style=\"text-align:left\">the sums that enter the chain</th></tr>\n<tr><td>means2d (&part;L/&part;m)</td><td>");
    fvals(f, x->sum + SPR_GPART_M, 2);
    fprintf(f, "</td></tr><tr><td>conics (&part;L/&part;(A, B, C))</td><td>");
    fvals(f, x->sum + SPR_GPART_CONIC, 3);
    fprintf(f, "</td></tr><tr><td>colors (&part;L/&part;c)</td><td>");
    fvals(f, x->sum + SPR_GPART_COLOR, 3);
    fprintf(f, "</td></tr><tr><td>opacities (&part;L/&part;o)</td><td>%.9g</td></tr><tr><td>1/t.z (&part;L/&part;(1/t.z))</td><td>%.9g</td></tr>\n",
            x->sum[SPR_GPART_OPACITY], x->sum[SPR_GPART_INVZ]);
    fprintf(f, "<tr><th colspan=\"2\" style=\"text-align:left\">splatref grad's values (spr_gauss_grad)</th></tr>\n<tr><td>means</td><td>");
    fvals(f, g->means + 3 * G, 3);
    fprintf(f, "</td></tr><tr><td>quats</td><td>");
    fvals(f, g->quats + 4 * G, 4);
    fprintf(f, "</td></tr><tr><td>scales</td><td>");
    fvals(f, g->scales + 3 * G, 3);
    fprintf(f, "</td></tr><tr><td>opacities</td><td>%.9g</td></tr>", g->opacities[G]);
    const float *sh = g->sh ? g->sh + G * 3 * (size_t)g->sh_k : NULL;
    if (sh && g->sh_k > 0) {
        fprintf(f, "<tr><td>sh0</td><td>");
        fvals(f, sh, 3);
        fprintf(f, "</td></tr>");
    }
    if (sh && g->sh_k > 1) {
        fprintf(f, "<tr><td>shN (%d coefficients &times; 3)</td><td>", g->sh_k - 1);
        for (int k = 1; k < g->sh_k; k++) { /* a coefficient a line */
            if (k > 1) fprintf(f, "<br>");
            fvals(f, sh + 3 * k, 3);
        }
        fprintf(f, "</td></tr>");
    } else fprintf(f, "<tr><td>shN</td><td>none (degree 0)</td></tr>");
    fprintf(f, "</table>\n");
    return same;
}

/* The "Backward pass" section; returns whether G's sums are splatref grad's values to the bit. */
static int backward_section(page *pg, const grad_view *gv, const char *upstream_text)
{
    FILE *f = pg->f;
    fprintf(f, "<section id=\"backward\"><h2>Backward pass (SPEC 10.10)</h2>\n<p>gauss3d under %s; the upstream gradient: ", gv->pf->name);
    html_escape(f, upstream_text);
    fprintf(f, ". The same frame and arithmetic as <code>splatref grad</code> on the CPU (docs/gradients.md): per pixel a reverse walk of the "
               "Gaussians it blended, adding each one's terms to its tile's partials; per Gaussian the partials summed in tile order, then the chain "
               "to its parameters.</p>\n");
    backward_pixel(pg, gv, gv->x->G);
    const int same = backward_gaussian(pg, gv);
    fprintf(f, "</section>\n");
    return same;
}

int cmd_step(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "step", step_opts, "--out DIR [scene options | --scene S.json]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    const char *dir = spr__get(&a, "out");
    int npix = 6;
    if (!dir) { spr__error(&a, "--out DIR is required"); return 2; }
    if (spr__get_int(&a, "pixels", &npix, 0, 16) < 0) return 2;
    /* the backward pass: Gaussian G under the upstream options (read after the scene's setup, which knows the size) */
    size_t gradG = 0;
    const int want_grad = spr__get(&a, "grad-gaussian") != NULL;
    if (want_grad && spr__get_size(&a, "grad-gaussian", &gradG, 0, (size_t)1 << 40) < 0) return 2;
    static const char *const grad_names[] = {"loss", "loss-target", "dl-dimage", "dl-dalpha", "dl-ddepth", "grad-batch"};
    const char *grad_given = NULL;
    for (size_t k = 0; k < sizeof grad_names / sizeof grad_names[0]; k++)
        if (!grad_given && spr__get(&a, grad_names[k])) grad_given = grad_names[k];
    if (grad_given && !want_grad) { spr__error(&a, "--%s goes with --grad-gaussian G (the backward pass section)", grad_given); return 2; }
    cli_grad_claim(&a);
    /* small by default: every pixel is shown and embedded */
    for (int k = 0; a.opts[k].name; k++)
        if (!strcmp(a.opts[k].name, "size") && !a.value[k]) a.value[k] = "128x128";
    spr_scene s;
    spr_render_desc rd;
    spr_capture cc = {1, NULL, 0, 0, 0, {0}}; /* planes as floats */
    spr_backend *b = NULL;
    spr_render_result res = {0};
    spr_error err = {0};
    char tmp[1200] = "", path[1400];
    int open_dir = 0, rc = 2;
    cli_history_run hist[16];
    int nh = 0;
    FILE *f = NULL;
    spr_grad_desc gd;
    cli_grad_inputs gin = {0};
    spr_gauss_grads gg = {0};
    spr_grad_explain gx = {0};
    int grad_same = -1;
    memset(hist, 0, sizeof hist);
    memset(&gd, 0, sizeof gd);
    if (spr__scene_setup(&a, &s, &rd, 0)) goto done;
    if (want_grad) {
        if (cli_grad_upstream(&a, s.view.width, s.view.height, &gd, &gin)) goto done;
        if (gradG >= s.cloud.n) {
            spr__error(&a, "--grad-gaussian %zu: %s has %zu Gaussians (0 … %zu)", gradG, s.model, s.cloud.n, s.cloud.n ? s.cloud.n - 1 : 0);
            goto done;
        }
    }
    if (cli_outdir_begin(&a, "out", dir, tmp, sizeof tmp)) goto done;
    open_dir = 1;
    snprintf(path, sizeof path, "%s/scene.json", tmp);
    if (spr__scene_save(&a, &s, &rd, path, 0)) goto done;
    rd.hook = spr_capture_hook;
    rd.hook_user = &cc;
    if (!(b = spr_swrast_create(s.threads, &err)) || spr_render(b, &s.view, &s.cloud, &rd, &res, &err)) {
        fprintf(stderr, "splatref step: %s\n", err.msg);
        goto done;
    }
    if (cc.failed) { fprintf(stderr, "splatref step: %s\n", cc.err.msg); goto done; }
    if (want_grad) { /* splatref grad's arrays and G's terms in the backward's order (the CPU reference, the frame without the capture) */
        spr_render_desc gr = rd;
        gr.hook = NULL, gr.hook_user = NULL;
        if (spr_gauss_grad(b, &s.view, &s.cloud, &gr, &gd, &gg, &err) || spr_gauss_grad_explain(b, &s.view, &s.cloud, &gr, &gd, gradG, &gx, &err)) {
            fprintf(stderr, "splatref step: %s\n", err.msg);
            goto done;
        }
    }
    const int W = s.view.width, H = s.view.height;
    /* pixels to explain: covered ones spread over the image, blended ones first */
    {
        int want = npix, tries = 0;
        for (int stride = 7; nh < want && tries < 4; tries++, stride += 3)
            for (int y = H / 5; y < H && nh < want; y += stride)
                for (int x = W / 5 + (y % 3); x < W && nh < want; x += stride * 2) {
                    if (!(res.rgba[4 * ((size_t)y * W + x) + 3] > 0.0f)) continue;
                    int dup = 0;
                    for (int i = 0; i < nh; i++) dup |= hist[i].h.x == x && hist[i].h.y == y;
                    if (dup) continue;
                    if (cli_run_history(&s, &rd, "cpu", NULL, x, y, &hist[nh]) < 0) goto done;
                    nh++;
                }
    }
    snprintf(path, sizeof path, "%s/index.html", tmp);
    if (!(f = fopen(path, "w"))) { spr__error(&a, "cannot write %s", path); goto done; }
    page pg = {f, W, H};
    const spr_algo_info *ai = spr_algo_info_of(rd.algo);
    fprintf(f, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>splatref step: %s</title><style>", spr_algo_name(rd.algo));
    fprintf(f, page_css, W * 3 + 10);
    fprintf(f, "</style></head><body>\n<h1>%s, step by step</h1>\n<p><b>%s</b> (SPEC %s): ", spr_algo_name(rd.algo), spr_algo_name(rd.algo), ai->spec);
    html_escape(f, ai->summary);
    fprintf(f, ".</p><p>Scene: ");
    html_escape(f, s.model);
    fprintf(f, ", %zu splats, %dx%d pixels, K = %d; <code>scene.json</code> in this folder reproduces it "
               "(<code>splatref render --scene scene.json</code>). Click any picture to see that pixel in every pass; "
               "pixels with an embedded history: ", s.cloud.n, W, H, res.K);
    for (int i = 0; i < nh; i++) fprintf(f, "<a href=\"#\" class=\"px\" data-px=\"%d,%d\">%d,%d</a> ", hist[i].h.x, hist[i].h.y, hist[i].h.x, hist[i].h.y);
    fprintf(f, "</p>\n<div id=\"info\">Click a pixel of any picture.</div><div id=\"tip\"></div>\n");
    if (want_grad) fprintf(f, "<p>Backward pass for Gaussian %zu: <a href=\"#backward\">below</a>.</p>\n", gradG);
    if (rd.groups) grouping_section(&pg, &s);
    /* the passes, each with the history call that matches it */
    const spr_hist_event *events = nh ? hist[0].h.ev : NULL;
    const int n_events = nh ? hist[0].h.n : 0;
    for (int i = 0; i < cc.n; i++) {
        const spr_captured_pass *p = &cc.passes[i];
        const spr_hist_event *ev = NULL;
        for (int e = 0; e < n_events; e++)
            if (events[e].pass == p->index) ev = &events[e];
        pass_header(&pg, p, ev);
        if (pass_views(&a, &pg, tmp, p, cc.passes, ev && ev->kind == SPR_HIST_COMPOSITE ? &ev->op : NULL, ev ? ev->inputs : NULL,
                       ev ? ev->n_inputs : 0, ev ? ev->eps_t : 0.0f, ev && ev->list))
            goto done;
        fprintf(f, "</div></section>\n");
    }
    /* the final image */
    {
        float *rgb = malloc((size_t)W * H * 3 * sizeof *rgb);
        if (!rgb) { spr__error(&a, "out of memory"); goto done; }
        for (size_t i = 0; i < (size_t)W * H; i++)
            for (int c = 0; c < 3; c++) rgb[3 * i + c] = res.rgba[4 * i + c];
        view_out vo = {"final.png", "the final image", ""};
        int wr = write_view(&a, tmp, rgb, W, H, &vo);
        free(rgb);
        if (wr) goto done;
        fprintf(f, "<section id=\"final\"><h2>The final image</h2><div class=\"views\">");
        figure(&pg, &vo, cc.n ? cc.passes[cc.n - 1].index : 0, "color", 0, 0, 0);
        fprintf(f, "</div></section>\n");
    }
    if (want_grad) {
        const float *rec = NULL;
        for (int i = 0; i < cc.n; i++)
            if (cc.passes[i].records && cc.passes[i].n_records == s.cloud.n) rec = cc.passes[i].records;
        char up_text[600];
        const char *loss = spr__get(&a, "loss"), *lt = spr__get(&a, "loss-target"), *dl = spr__get(&a, "dl-dimage");
        const char *da = spr__get(&a, "dl-dalpha"), *dd = spr__get(&a, "dl-ddepth");
        if (loss) snprintf(up_text, sizeof up_text, "--loss %s, target %s", loss, lt ? lt : "black");
        else snprintf(up_text, sizeof up_text, "--dl-dimage %s", dl ? dl : "?");
        if (da) snprintf(up_text + strlen(up_text), sizeof up_text - strlen(up_text), ", --dl-dalpha %s", da);
        if (dd) snprintf(up_text + strlen(up_text), sizeof up_text - strlen(up_text), ", --dl-ddepth %s", dd);
        grad_view gv = {&gg, &gx, &gd, rd.background, spr_gauss_profile_of(rd.algo, rd.gauss_profile), rec, nh ? &hist[0].h : NULL};
        grad_same = backward_section(&pg, &gv, up_text);
    }
    fprintf(f, "<p id=\"selftest\" class=\"note\"></p>\n");
    data_script(&pg, &cc);
    fprintf(f, "<script>\n");
    for (int i = 0; i < nh; i++) { /* the histories as text */
        char *buf = NULL;
        size_t len = 0;
        FILE *m = open_memstream(&buf, &len);
        if (!m) { spr__error(&a, "out of memory"); goto done; }
        for (int e = 0; e < hist[i].h.n; e++) cli_explain_event(m, &hist[i].h.ev[e], e, NULL, -1, -1, "");
        fclose(m);
        cJSON *str = cJSON_CreateString(buf ? buf : "");
        char *js = str ? cJSON_PrintUnformatted(str) : NULL;
        cJSON_Delete(str);
        free(buf);
        if (!js) { spr__error(&a, "out of memory"); goto done; }
        /* a JSON string is a JS string; escape what would end the script element, then HTML-escape in the page */
        fprintf(f, "SPR.histories[\"%d,%d\"] = ", hist[i].h.x, hist[i].h.y);
        for (const char *c = js; *c; c++) {
            if (*c == '<') fputs("\\u003c", f);
            else if (*c == '>') fputs("\\u003e", f);
            else if (*c == '&') fputs("\\u0026", f);
            else fputc(*c, f);
        }
        fprintf(f, ".replace(/&/g,'&amp;').replace(/</g,'&lt;');\n");
        free(js);
    }
    fprintf(f, "</script>\n<script>\n%s</script>\n</body></html>\n", page_js);
    if (ferror(f) | fclose(f)) { f = NULL; spr__error(&a, "cannot write %s", path); goto done; }
    f = NULL;
    rc = 0;
done:
    if (f) fclose(f);
    if (open_dir && cli_outdir_end(&a, "out", tmp, dir, rc == 0)) rc = 2;
    if (rc == 0 && want_grad)
        printf("step: backward pass for Gaussian %zu: %zu pixels in %zu tiles; its sums equal splatref grad's values bit for bit: %s\n", gradG, gx.n_terms,
               gx.n_tiles, grad_same == 1 ? "yes" : "no");
    if (rc == 0) printf("step: %s, %d passes, %d pixel histories -> %s/index.html\n", spr_algo_name(rd.algo), cc.n, nh, dir);
    spr_grad_explain_free(&gx);
    spr_gauss_grads_free(&gg);
    cli_grad_inputs_free(&gin);
    for (int i = 0; i < nh; i++) spr_history_free(&hist[i].h);
    spr_capture_free(&cc);
    spr_render_result_free(&res);
    spr_backend_destroy(b);
    spr_scene_free(&s);
    return rc;
}
