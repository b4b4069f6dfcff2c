/* cli_explain.c — `splatref explain --pixel X,Y`: the history of one pixel
 * (SPEC §8), pass by pass, on the CPU reference and on the GL pipeline
 * itself (the probe variant of its programs), side by side with the first
 * difference marked.  --json writes the same as JSON for tools. */
#include "cli.h"
#include "spr__scene_opts.h"
#include "spr__inspect.h"
#include "spr_history.h"
#include "spr_profile_diff.h"
#include "cli_grad.h"
#include "spr_grad.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const spr__opt explain_opts[] = {
    {"pixel", "X,Y", "the pixel, x from the left, y from the bottom (GL convention; check prints both)"},
    {"backend", "WHICH", "both (default: the CPU reference and GL side by side) | cpu | gl"},
    {"gl-device", "N", "GL backend: the N-th EGL device instead of the surfaceless platform"},
    {"json", NULL, "print the history as JSON (for tools)"},
    {"grad", NULL, "gauss3d's backward (SPEC 10.10) for one Gaussian (--gaussian G) with the upstream gradient's options (as splatref grad): every pixel that gave it a gradient, in the order the backward sums them, with its chain-rule terms, each tile's partial and the sums, which must equal splatref grad's arrays to the bit (CPU reference)"},
    {"gaussian", "G", "--grad: the Gaussian (its index in the model, from 0)"},
    CLI_GRAD_OPTS,
    {"vs", "PROFILE", "Gaussian algorithms: compare the scene's --gauss-profile (or the default) with PROFILE at the pixel, Gaussian by Gaussian, naming the rule of SPEC 10.9 behind each difference (CPU reference)"},
    SPR__SCENE_OPTS,
    {NULL, NULL, NULL}};



int cli_run_history(spr_scene *s, const spr_render_desc *rd, const char *which, const spr_gl_desc *gd, int x, int y, cli_history_run *out)
{
    spr_error err = {0};
    const int r = spr__history_run_one(s, rd, which, gd, x, y, out, &err);
    if (r) fprintf(stderr, "splatref explain: %s\n", err.msg);
    return r;
}

/* ---- text ---- */
static void print_value(FILE *f, spr_plane p, const uint32_t v[4])
{
    const int ch = spr_plane_channels(p);
    const spr_plane_type t = spr_plane_info_of(p)->type;
    if (ch == 1) {
        if ((t == SPR_PLANE_U32) && v[0] == UINT32_MAX) fprintf(f, "none");
        else fprintf(f, "%.9g", spr_history_value(p, v[0]));
        return;
    }
    fprintf(f, "(");
    for (int c = 0; c < ch; c++) fprintf(f, "%s%.9g", c ? ", " : "", spr_history_value(p, v[c]));
    fprintf(f, ")");
}

static void print_planes(FILE *f, const char *label, unsigned planes, const uint32_t v[SPR_PLANE__COUNT][4])
{
    fprintf(f, "    %s:", label);
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        if (!(planes & SPR_PLANE_BIT(p))) continue;
        fprintf(f, "  %s ", spr_plane_name((spr_plane)p));
        print_value(f, (spr_plane)p, v[p]);
    }
    fprintf(f, "\n");
}

static void print_planes_mask(FILE *f, unsigned m)
{
    int first = 1;
    for (int p = 0; p < SPR_PLANE__COUNT; p++)
        if (m & SPR_PLANE_BIT(p)) fprintf(f, "%s%s", first ? "" : " ", spr_plane_name((spr_plane)p)), first = 0;
    if (first) fprintf(f, "nothing");
}

static void print_note(FILE *f, const spr_probe_note *n)
{
    switch (n->tag) {
    case SPR_NOTE_EPS_NEAREST:
        fprintf(f, "    SPEC 4.2: d = min_k d_f(k) = %.9g; an input is blended when d_f(k) <= d + eps_t = %.9g (eps_t %.9g, K %d)\n", n->v[0], n->v[1],
               n->v[2], (int)n->v[3]);
        break;
    case SPR_NOTE_EPS_INPUT:
        fprintf(f, "      input %d: d_f %.9g %s %.9g -> %s, sum of weights %.9g\n", n->k, n->v[0], n->v[2] != 0.0f ? "<=" : ">", n->v[1],
               n->v[2] != 0.0f ? "blended" : "left out (farther than eps)", n->v[3]);
        break;
    case SPR_NOTE_PREFIX_NODE:
        fprintf(f, "      rank %d: rectangle %d at t %.9g -> %s, sum of alpha %.9g\n", (int)n->v[2], n->k, n->v[0],
               n->v[1] != 0.0f ? (n->v[2] == 0.0f ? "front-most, summed" : "neighbour of the front-most, summed")
                               : "not a neighbour of the front-most, left out",
               n->v[3]);
        break;
    case SPR_NOTE_GAUSS_TILE:
        fprintf(f, "    SPEC 10.4: pixel-index (i, j) = (%d, %d) lies in tile %d, whose list holds %d Gaussians sorted by depth "
                   "(entries %d …), front to back:\n", (int)n->v[0], (int)n->v[1], n->k, (int)n->v[3], (int)n->v[2]);
        fprintf(f, "      %8s %14s %14s %14s %14s  outcome\n", "Gaussian", "power", "alpha", "T before", "T after");
        break;
    case SPR_NOTE_GAUSS_BLEND: case SPR_NOTE_GAUSS_POWER: case SPR_NOTE_GAUSS_FAINT: case SPR_NOTE_GAUSS_STOP:
    case SPR_NOTE_GAUSS_PARALLEL: case SPR_NOTE_GAUSS_BEHIND: {
        static const char *const why[] = {"blended", "skipped: power > 0", "skipped: alpha < 1/255",
                                          "STOP: T*(1 - alpha) below 1e-4, not blended; the loop ends here",
                                          "skipped: the ray is parallel to the disk", "skipped: the hit lies before the near plane"};
        const int w = n->tag - SPR_NOTE_GAUSS_BLEND;
        if (n->tag == SPR_NOTE_GAUSS_BEHIND)
            fprintf(f, "      %8d %14.9g %14s %14.9g %14.9g  %s (depth %.9g)\n", n->k, n->v[0], "-", n->v[2], n->v[3], why[w], n->v[1]);
        else if (n->tag == SPR_NOTE_GAUSS_POWER || n->tag == SPR_NOTE_GAUSS_PARALLEL)
            fprintf(f, "      %8d %14.9g %14s %14.9g %14.9g  %s\n", n->k, n->v[0], "-", n->v[2], n->v[3], why[w]);
        else fprintf(f, "      %8d %14.9g %14.9g %14.9g %14.9g  %s\n", n->k, n->v[0], n->v[1], n->v[2], n->v[3], why[w]);
        break;
    }
    case SPR_NOTE_GAUSS_OUTSIDE:
        fprintf(f, "      %8d %14s %14s %14.9g %14.9g  skipped: outside its pixel box\n", n->k, "-", "-", n->v[2], n->v[3]);
        break;
    case SPR_NOTE_GAUSS_END:
        fprintf(f, "    the loop ends after %d of the list: %d blended, T = %.9g, D = %.9g, last contributor %d\n", (int)n->v[2], (int)n->v[3], n->v[0],
                n->v[1], n->k);
        break;
    default: fprintf(f, "      note %d: %d %.9g %.9g %.9g %.9g\n", n->tag, n->k, n->v[0], n->v[1], n->v[2], n->v[3]);
    }
}

void cli_explain_event(FILE *f, const spr_hist_event *e, int idx, const spr_hist_event *other, int diff_ev, int diff_frag, const char *other_name)
{
    if (e->kind == SPR_HIST_GAUSS_RASTER) {
        const int two = e->gprm[SPR_GPRM_MODE] == SPR_GMODE_2D;
        fprintf(f, "pass %d %s -- %s of %zu Gaussians into t%d: alpha = min(%.9g, o*exp(power)), skipped below %.9g, stop when T*(1 - alpha) < %.9g%s\n",
                e->pass, e->pass_name, two ? "gauss2d's surfel loop (SPEC 10.5)" : "gauss3d's front-to-back loop (SPEC 10.4)", e->submitted, e->target,
                e->gprm[SPR_GPRM_CAP], e->gprm[SPR_GPRM_ALPHA_MIN], e->gprm[SPR_GPRM_T_MIN], e->gprm[SPR_GPRM_STOP_LE] != 0.0f ? " (or equal)" : "");
        for (int i = 0; i < e->n_notes; i++) print_note(f, &e->notes[i]);
        print_planes(f, "out", e->planes, e->after);
    } else if (e->kind == SPR_HIST_COMPOSITE) {
        fprintf(f, "pass %d %s -- composite %s of", e->pass, e->pass_name, spr_composite_info_of(e->op)->name);
        for (int k = 0; k < e->n_inputs; k++) fprintf(f, " t%d", e->inputs[k]);
        fprintf(f, " into t%d, eps_t %.9g: %s\n", e->target, e->eps_t, spr_composite_info_of(e->op)->summary);
        for (int k = 0; k < e->n_inputs; k++) {
            char lab[32];
            snprintf(lab, sizeof lab, "input %d (t%d)", k, e->inputs[k]);
            print_planes(f, lab, e->in_planes[k] & (SPR_PLANE_BIT(SPR_PLANE_COLOR) | SPR_PLANE_BIT(SPR_PLANE_DEPTH) | SPR_PLANE_BIT(SPR_PLANE_OPACITY)),
                         e->in_vals[k]);
        }
        for (int i = 0; i < e->n_notes; i++) print_note(f, &e->notes[i]);
        print_planes(f, "out", e->planes, e->after);
    } else {
        const spr_pass_state *s = &e->state;
        if (e->group >= 0) fprintf(f, "pass %d %s k%d -- ", e->pass, e->pass_name, e->group);
        else fprintf(f, "pass %d %s -- ", e->pass, e->pass_name);
        fprintf(f, "%s of %zu %s into t%d", e->list ? "list draw" : "draw", e->submitted,
                e->kind == SPR_HIST_SPLATS ? "splats" : e->kind == SPR_HIST_GAUSS_DRAW ? "Gaussian ellipses, farthest first (SPEC 10.7)" : "rectangles", e->target);
        if (e->list) fprintf(f, ": every fragment joins the pixel's list (no test, no plane written)\n");
        else {
            fprintf(f, ": test value %s, depth %s, depth write %s, blend rgb %s alpha %s, writes ", spr__depth_names[s->depth_value], spr__func_names[s->depth_func],
                   s->depth_write ? "on" : "off", spr__blend_names[s->blend], spr__blend_names[s->blend_alpha]);
            print_planes_mask(f, s->write_mask);
            fprintf(f, ", eps_t %.9g", s->eps_t);
            if (s->depth_value >= SPR_DEPTH_LOWRES) fprintf(f, ", d_min %.9g d_max %.9g n %.9g", s->lowres.d_min, s->lowres.d_max, s->lowres.n);
            if (e->depth_mask) fprintf(f, "; fragments within eps_t of t%d's nearest layer are masked (not listed)", e->mask_target);
            fprintf(f, "\n");
            print_planes(f, "before", e->planes, e->before);
        }
        if (e->n_frags && e->kind == SPR_HIST_GAUSS_DRAW)
            fprintf(f, "      #  order      id        power        alpha            z   %-36s  test before  outcome\n", "colour (a*r, a*g, a*b, alpha)");
        else if (e->n_frags)
            fprintf(f, "      #  index      id            t          rho            z   %-36s  test before  outcome\n",
                    e->kind == SPR_HIST_SPLATS && s->output == SPR_OUT_WEIGHTED ? "colour (w*r, w*g, w*b, w)" : "colour (r, g, b, alpha)");
        for (int i = 0; i < e->n_frags; i++) {
            const spr_hist_frag *hf = &e->frags[i];
            char col[96];
            snprintf(col, sizeof col, "(%.5g, %.5g, %.5g, %.5g)", hf->f.src[0], hf->f.src[1], hf->f.src[2], hf->f.src[3]);
            fprintf(f, "    %3d %6u %7u %12.9g %12.9g %12.9g   %-36s %12.9g  %s", i + 1, hf->f.seq, hf->f.prim, hf->f.t, hf->f.rho, hf->f.z, col, hf->z_before,
                   hf->passed < 0 ? "listed" : hf->passed ? "pass" : "fail");
            if (hf->passed > 0) { /* what it changed */
                const uint32_t(*prev)[4] = i ? e->frags[i - 1].after : e->before;
                fprintf(f, " ->");
                for (int p = 0; p < SPR_PLANE__COUNT; p++) {
                    if (!(e->planes & SPR_PLANE_BIT(p)) || !memcmp(prev[p], hf->after[p], 16)) continue;
                    fprintf(f, " %s ", spr_plane_name((spr_plane)p));
                    print_value(f, (spr_plane)p, hf->after[p]);
                }
            }
            if (idx == diff_ev && i == diff_frag) fprintf(f, "   <-- first difference from %s", other_name);
            fprintf(f, "\n");
        }
        if (!e->list) {
            print_planes(f, "after", e->planes, e->after);
            if (e->replay_matches) fprintf(f, "    (replaying the fixed-function stages on these fragments gives exactly these planes)\n");
            else fprintf(f, "    REPLAY DIFFERS from the backend's planes: %s\n", e->replay_note);
        }
    }
    if (other) {
        if (idx < diff_ev || diff_ev < 0) fprintf(f, "    %s: identical (%d fragments, %d steps, planes after)\n", other_name, other->n_frags, other->n_notes);
        else if (idx == diff_ev) fprintf(f, "    %s: FIRST DIFFERENCE in this call (see above)\n", other_name);
    }
}

static void print_bits4(const uint32_t v[4])
{
    float f[4];
    memcpy(f, v, sizeof f);
    printf("(%.6g, %.6g, %.6g, %.6g)", f[0], f[1], f[2], f[3]);
}

/* explain --vs: the two profiles' pixel and every Gaussian they treat differently, with its rule. */
static int explain_vs(spr__args *a, spr_scene *s, const spr_render_desc *rd, const char *vs, int x, int y)
{
    const int pb = spr_gauss_profile_from_name(vs);
    if (pb < 0) { spr__error(a, "--vs: '%s' is not a profile (%s)", vs, spr_gauss_profile_names(", ")); return 2; }
    if (!(spr_algo_info_of(rd->algo)->uses & SPR_USES_GAUSS)) { spr__error(a, "--vs compares Gaussian profiles: give --gauss-profile or a gauss* --algo"); return 2; }
    const int pa = (int)(spr_gauss_profile_of(rd->algo, rd->gauss_profile) - spr_gauss_profile_at(0));
    spr__pdiff d;
    spr_error err = {0};
    if (spr__profile_diff(s, rd, pa, pb, x, y, &d, &err)) { fprintf(stderr, "splatref explain: %s\n", err.msg); return 2; }
    printf("explain --vs: pixel x %d, y %d (row %d from the top) of %s, %zu Gaussians, %dx%d: profile %s (%s) vs %s (%s)\n", x, y,
           s->view.height - 1 - y, s->model, s->cloud.n, s->view.width, s->view.height, d.a->name, spr_algo_name(d.a->skeleton), d.b->name,
           spr_algo_name(d.b->skeleton));
    printf("  %-18s colour ", d.a->name);
    print_bits4(d.color_a);
    printf("\n  %-18s colour ", d.b->name);
    print_bits4(d.color_b);
    printf("\n");
    if (!d.n) printf("explain --vs: every Gaussian at this pixel is treated alike by both profiles\n");
    else printf("explain --vs: %d Gaussians treated differently (outcome under %s | under %s | the rule, SPEC 10.9):\n", d.n, d.a->name, d.b->name);
    for (int k = 0; k < d.n; k++) {
        const spr__pdiff_row *r = &d.rows[k];
        printf("  Gaussian %u\n    %-10s %s\n    %-10s %s\n    rule       %s\n", r->id, d.a->name, r->a, d.b->name, r->b, r->rule);
    }
    if (d.quiet) printf("explain --vs: %d more Gaussians are dropped by both, for different reasons (cut, outside their tiles, below the floor)\n", d.quiet);
    spr__pdiff_free(&d);
    return 0;
}

/* ---- explain --gaussian G --grad ---- */
static void print_vals(const char *name, const float *v, int n)
{
    printf(" %s ", name);
    if (n > 1) printf("(");
    for (int k = 0; k < n; k++) printf("%s%.9g", k ? ", " : "", v[k]);
    if (n > 1) printf(")");
}

static void print_terms(const char *indent, const float *p)
{
    printf("%s", indent);
    print_vals("colors", p + SPR_GPART_COLOR, 3);
    print_vals("opacities", p + SPR_GPART_OPACITY, 1);
    print_vals("conics", p + SPR_GPART_CONIC, 3);
    print_vals("means2d", p + SPR_GPART_M, 2);
    print_vals("absgrad", p + SPR_GPART_ABS, 2);
    printf("\n");
}

static int explain_grad(spr__args *a)
{
    size_t G = 0;
    const char *bname = spr__get(a, "backend");
    if (!spr__get(a, "gaussian")) { spr__error(a, "--grad explains one Gaussian's gradient: give --gaussian G"); return 2; }
    if (spr__get_size(a, "gaussian", &G, 0, (size_t)1 << 40) < 0) return 2;
    if (bname && strcmp(bname, "cpu")) { spr__error(a, "--grad retraces the CPU reference's backward: --backend %s is not available (leave it out)", bname); return 2; }
    spr_scene s;
    spr_render_desc rd;
    spr_grad_desc gd;
    cli_grad_inputs in = {0};
    spr_gauss_grads g = {0};
    spr_grad_explain x = {0};
    spr_backend *b = NULL;
    spr_error err = {0};
    int rc = 2;
    memset(&s, 0, sizeof s);
    cli_grad_claim(a);
    if (spr__scene_setup(a, &s, &rd, 0) || cli_grad_upstream(a, s.view.width, s.view.height, &gd, &in)) goto done;
    if (G >= s.cloud.n) { spr__error(a, "--gaussian %zu: %s has %zu Gaussians (0 … %zu)", G, s.model, s.cloud.n, s.cloud.n ? s.cloud.n - 1 : 0); goto done; }
    if (!(b = spr__backend(a, "cpu", s.threads, NULL))) goto done;
    if (spr_gauss_grad(b, &s.view, &s.cloud, &rd, &gd, &g, &err) || spr_gauss_grad_explain(b, &s.view, &s.cloud, &rd, &gd, G, &x, &err)) {
        fprintf(stderr, "splatref explain: %s\n", err.msg);
        goto done;
    }
    const int W = s.view.width, H = s.view.height;
    const spr_gauss_profile *pf = spr_gauss_profile_of(rd.algo, rd.gauss_profile);
    printf("explain --gaussian %zu --grad: %s, %zu Gaussians, gauss3d under %s, %dx%d, cpu backend: %zu pixels in %zu tiles gave Gaussian %zu a gradient\n",
           G, s.model, s.cloud.n, pf->name, W, H, x.n_terms, x.n_tiles, G);
    printf("explain: the backward's order (SPEC 10.10 item 4): tiles in tile order; in a tile its pixels row-major from the top row.  A tile's "
           "partial is its pixels' terms added in that order, in float; the array's value is the tiles' partials added in tile order\n");
    printf("explain: per pixel: power, alpha and T (the forward's, before the Gaussian), acc (the colour behind per unit of the T after it: r, g, b), "
           "dL/dalpha = T*<c - acc, dL/dC> - T_f/(1 - alpha)*(<bg, dL/dC> - dL/dA), dL/do = e^power*dL/dalpha, dL/dpower = o*e^power*dL/dalpha "
           "(both 0 where the profile's cap gate holds), then the terms it adds\n");
    for (size_t k = 0; k < x.n_tiles; k++) {
        const spr_grad_tile *t = &x.tiles[k];
        const int gx = (W + 15) / 16, i0 = (t->tile % gx) * 16, j0 = (t->tile / gx) * 16;
        printf("tile %d (list entry %u; x %d..%d, rows %d..%d from the top): %zu pixel%s\n", t->tile, t->entry, i0, i0 + 15 < W ? i0 + 15 : W - 1, j0,
               j0 + 15 < H ? j0 + 15 : H - 1, t->count, t->count == 1 ? "" : "s");
        for (size_t p = t->first; p < t->first + t->count; p++) {
            const spr_grad_term *m = &x.terms[p];
            printf("  pixel x %d, y %d (row %d from the top), blended %d of %d: power %.9g alpha %.9g T %.9g acc (%.9g, %.9g, %.9g) dL/dalpha %.9g "
                   "dL/do %.9g%s dL/dpower %.9g\n",
                   m->x, m->y, H - 1 - m->y, m->rank + 1, m->blended, m->power, m->alpha, m->T, m->acc[0], m->acc[1], m->acc[2], m->dl_dalpha, m->dl_do,
                   m->gated ? " (zeroed: the cap gate)" : "", m->dl_dpower);
            print_terms("    terms:", m->part);
        }
        printf("  partial of tile %d:", t->tile);
        print_terms("", t->part);
    }
    static const struct { const char *name; int off, n; } arr[] = {
        {"colors", SPR_GPART_COLOR, 3}, {"opacities", SPR_GPART_OPACITY, 1}, {"conics", SPR_GPART_CONIC, 3}, {"means2d", SPR_GPART_M, 2}, {"absgrad", SPR_GPART_ABS, 2}};
    const float *have[] = {g.colors + 3 * G, g.opacities + G, g.conics + 3 * G, g.means2d + 2 * G, g.absgrad + 2 * G};
    int same = 1;
    for (int i = 0; i < 5; i++) {
        const float *v = x.sum + arr[i].off;
        const int eq = !memcmp(v, have[i], (size_t)arr[i].n * sizeof *v);
        same &= eq;
        printf("sum %s =", arr[i].name);
        for (int k = 0; k < arr[i].n; k++) printf("%s %.9g", k ? "," : "", v[k]);
        printf("; array %s[%zu] =", arr[i].name, G);
        for (int k = 0; k < arr[i].n; k++) printf("%s %.9g", k ? "," : "", have[i][k]);
        if (eq) printf("; bit-identical\n");
        else {
            printf("; DIFFERS by");
            for (int k = 0; k < arr[i].n; k++) printf("%s %.9g", k ? "," : "", (double)have[i][k] - (double)v[k]);
            printf("\n");
        }
    }
    const int ceq = (double)x.sum[SPR_GPART_COUNT] == (double)g.counts[G];
    same &= ceq;
    printf("sum counts = %.9g; array counts[%zu] = %d; %s\n", x.sum[SPR_GPART_COUNT], G, (int)g.counts[G], ceq ? "equal" : "DIFFER");
    printf("explain: the chain from these sums (SPEC 10.3 backwards, and the SH's) gives means (%.9g, %.9g, %.9g), quats (%.9g, %.9g, %.9g, %.9g), "
           "scales (%.9g, %.9g, %.9g)\n", g.means[3 * G], g.means[3 * G + 1], g.means[3 * G + 2], g.quats[4 * G], g.quats[4 * G + 1], g.quats[4 * G + 2],
           g.quats[4 * G + 3], g.scales[3 * G], g.scales[3 * G + 1], g.scales[3 * G + 2]);
    if (!x.consistent) printf("explain: WARNING: a pixel's recomputed dL/do differs from the term the shared arithmetic added (the printed intermediates do not retrace it)\n");
    if (same) printf("explain: sums back to the array's value: yes (bit-identical)\n");
    else printf("explain: sums back to the array's value: NO (the differences above)\n");
    rc = same && x.consistent ? 0 : 1;
done:
    spr_grad_explain_free(&x);
    spr_gauss_grads_free(&g);
    cli_grad_inputs_free(&in);
    if (b) spr_backend_destroy(b);
    spr_scene_free(&s);
    return rc;
}

int cmd_explain(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "explain", explain_opts, "--pixel X,Y [--backend both|cpu|gl] [--json] [scene options | --scene S.json]  |  --gaussian G --grad --dl-dimage G.npy|--loss l1|l2 --target IMG [scene options]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    if (spr__flag(&a, "grad")) return explain_grad(&a);
    if (spr__get(&a, "gaussian")) { spr__error(&a, "--gaussian G goes with --grad (its gradient, pixel by pixel)"); return 2; }
    const char *pix = spr__get(&a, "pixel"), *which = spr__get(&a, "backend");
    const int json = spr__flag(&a, "json");
    int x, y;
    spr_gl_desc gd;
    spr_gl_defaults(&gd);
    char tail;
    if (!pix || sscanf(pix, "%d,%d%c", &x, &y, &tail) != 2) { spr__error(&a, "--pixel X,Y is required (two whole numbers)"); return 2; }
    if (!which) which = "both";
    if (strcmp(which, "both") && strcmp(which, "cpu") && strcmp(which, "gl")) { spr__error(&a, "--backend: '%s' is not both, cpu or gl", which); return 2; }
    if (strcmp(which, "cpu") && spr__gl_opts(&a, &gd) < 0) return 2;
    spr_scene s;
    spr_render_desc rd;
    cli_history_run runs[2];
    int nr = 0, rc = 2;
    memset(runs, 0, sizeof runs);
    const char *vs = spr__get(&a, "vs");
    if (spr__scene_setup(&a, &s, &rd, 0)) goto done;
    if (x < 0 || y < 0 || x >= s.view.width || y >= s.view.height) {
        spr__error(&a, "--pixel %d,%d lies outside the %dx%d image", x, y, s.view.width, s.view.height);
        goto done;
    }
    if (vs) {
        rc = explain_vs(&a, &s, &rd, vs, x, y);
        goto done;
    }
    if (strcmp(which, "gl")) {
        if (cli_run_history(&s, &rd, "cpu", &gd, x, y, &runs[nr])) goto done;
        nr++;
    }
    if (strcmp(which, "cpu")) {
        int r = cli_run_history(&s, &rd, "gl", &gd, x, y, &runs[nr]);
        if (r < 0 || (r > 0 && !strcmp(which, "gl"))) goto done;
        if (r == 0) nr++;
        else fprintf(stderr, "splatref explain: no GL device here: the CPU reference alone\n");
    }
    int dev = -1, dfrag = -1, differ = 0;
    char what[300] = "";
    if (nr == 2) differ = spr__history_difference(&runs[0].h, &runs[1].h, &dev, &dfrag, what, sizeof what);
    if (json) {
        cJSON *o = spr__explain_json(&s, &rd, x, y, runs, nr);
        char *text = cJSON_Print(o);
        cJSON_Delete(o);
        if (!text) { spr__error(&a, "out of memory"); goto done; }
        printf("%s\n", text);
        free(text);
    } else {
        printf("explain: pixel x %d, y %d (row %d from the top) of %s, %zu splats, %s, %dx%d; %s%s%s\n", x, y, s.view.height - 1 - y, s.model,
               s.cloud.n, spr_algo_name(rd.algo), s.view.width, s.view.height, runs[0].renderer, nr == 2 ? " beside " : "",
               nr == 2 ? runs[1].renderer : "");
        printf("explain: fragments in submission order (index: position in the draw, id: splat or rectangle), values as the backend computed them;\n"
               "explain: test before, outcome and the planes each passing fragment changed replay GL's fixed-function stages (SPEC 3.3, 3.4)\n");
        const spr_history *h = &runs[0].h;
        for (int i = 0; i < h->n; i++) {
            cli_explain_event(stdout, &h->ev[i], i, nr == 2 && i < runs[1].h.n ? &runs[1].h.ev[i] : NULL, differ ? dev : -1, dfrag, nr == 2 ? runs[1].name : "");
            if (differ && i == dev && nr == 2) { /* the other side of the first difference */
                printf("  %s's side of pass %d:\n", runs[1].name, h->ev[i].pass);
                cli_explain_event(stdout, &runs[1].h.ev[i], -2, NULL, -1, -1, "");
            }
        }
        if (h->overflow) printf("explain: more than %d records in one call: lists truncated\n", SPR_PROBE_MAX);
        if (nr == 2) {
            if (differ) {
                printf("explain: FIRST DIFFERENCE cpu vs gl at call %d (pass %d)", dev, dev < h->n ? h->ev[dev].pass : -1);
                if (dfrag >= 0) printf(", fragment %d", dfrag + 1);
                printf(": %s\n", what);
            }
            else printf("explain: cpu and gl histories identical: every fragment, every step, every plane after every call\n");
        }
    }
    rc = differ ? 1 : 0;
    for (int i = 0; i < nr; i++)
        for (int k = 0; k < runs[i].h.n; k++)
            if (!runs[i].h.ev[k].replay_matches) rc = 1;
done:
    for (int i = 0; i < 2; i++) spr_history_free(&runs[i].h);
    spr_scene_free(&s);
    return rc;
}
