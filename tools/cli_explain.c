/* cli_explain.c — `splatref explain --pixel X,Y`: the history of one pixel
 * (SPEC §8), pass by pass, on the CPU reference and on the GL pipeline
 * itself (the probe variant of its programs), side by side with the first
 * difference marked.  --json writes the same as JSON for tools. */
#include "cli.h"
#include "spr__scene_opts.h"
#include "spr_glbackend.h"
#include "spr_history.h"
#include "spr_swrast.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const spr__opt explain_opts[] = {
    {"pixel", "X,Y", "the pixel, x from the left, y from the bottom (GL convention; check prints both)"},
    {"backend", "WHICH", "both (default: the CPU reference and GL side by side) | cpu | gl"},
    {"gl-device", "N", "GL backend: the N-th EGL device instead of the surfaceless platform"},
    {"json", NULL, "print the history as JSON (for tools)"},
    SPR__SCENE_OPTS,
    {NULL, NULL, NULL}};

static const char *const depth_names[SPR_DEPTH__COUNT] = {"d_f", "d_f + eps_t", "z~ (low precision, [ZP] Eq. 10)", "z~ + rho/n (Voronoi, [ZP] Eq. 14)"};
static const char *const func_names[SPR_FUNC__COUNT] = {"LESS", "LEQUAL", "ALWAYS"};
static const char *const blend_names[SPR_BLEND__COUNT] = {"replace", "add", "over", "sub", "premultiplied over"};


typedef struct explain_ctx { spr_history *h; } explain_ctx;
static void label_hook(void *user, spr_backend *b, const spr_pass_info *info) { spr_history_pass(((explain_ctx *)user)->h, info); }

int cli_run_history(spr_scene *s, const spr_render_desc *rd0, const char *which, int gl_device, int x, int y, cli_history_run *out)
{
    spr_error err = {0};
    spr_backend *inner;
    memset(out, 0, sizeof *out);
    out->name = which;
    if (!strcmp(which, "gl")) {
        spr_gl_desc gd;
        spr_gl_defaults(&gd);
        gd.device = gl_device;
        gd.probe = 1;
        inner = spr_gl_create(&gd, &err);
        if (inner) snprintf(out->renderer, sizeof out->renderer, "gl [%s]", spr_gl_renderer(inner));
    } else {
        inner = spr_swrast_create(s->threads, &err);
        snprintf(out->renderer, sizeof out->renderer, "cpu reference");
    }
    if (!inner) { fprintf(stderr, "splatref explain: %s\n", err.msg); return err.code == SPR_E_NO_DEVICE ? 1 : -1; }
    spr_backend *b = spr_history_create(inner, x, y, &out->h, &err);
    if (!b) { fprintf(stderr, "splatref explain: %s\n", err.msg); return -1; }
    spr_render_desc rd = *rd0;
    explain_ctx ec = {&out->h};
    rd.hook = label_hook;
    rd.hook_user = &ec;
    spr_render_result res = {0};
    int rc = spr_render(b, &s->view, &s->cloud, &rd, &res, &err) ? -1 : 0;
    if (rc) fprintf(stderr, "splatref explain: %s: %s\n", which, err.msg);
    spr_render_result_free(&res);
    spr_backend_destroy(b);
    out->ok = rc == 0;
    return rc;
}

/* ---- the first difference between two histories ---- */
static int same_bits(const void *p, const void *q, size_t n) { return !memcmp(p, q, n); }

/* Sets *ev, *frag (−1: not a fragment), a description; 0 when identical. */
static int first_difference(const spr_history *c, const spr_history *g, int *ev, int *frag, char *what, size_t cap)
{
    *ev = *frag = -1;
    if (c->n != g->n) { snprintf(what, cap, "%d calls on the cpu, %d on gl", c->n, g->n); *ev = c->n < g->n ? c->n : g->n; return 1; }
    for (int i = 0; i < c->n; i++) {
        const spr_hist_event *x = &c->ev[i], *y = &g->ev[i];
        *ev = i;
        if (x->n_frags != y->n_frags) { snprintf(what, cap, "%d fragments on the cpu, %d on gl", x->n_frags, y->n_frags); return 1; }
        for (int f = 0; f < x->n_frags; f++) {
            const spr_probe_frag *p = &x->frags[f].f, *q = &y->frags[f].f;
            *frag = f;
            static const char *const field[] = {"submission index", "id", "t", "rho", "z", "src[0]", "src[1]", "src[2]", "src[3]", "opacity"};
            const uint32_t *pp = (const uint32_t *)(const void *)p, *qq = (const uint32_t *)(const void *)q;
            for (int k = 0; k < 10; k++)
                if (pp[k] != qq[k]) {
                    float fa, fb;
                    memcpy(&fa, &pp[k], 4), memcpy(&fb, &qq[k], 4);
                    if (k < 2) snprintf(what, cap, "%s: cpu %u, gl %u", field[k], pp[k], qq[k]);
                    else snprintf(what, cap, "%s: cpu %.9g (0x%08x), gl %.9g (0x%08x)", field[k], fa, pp[k], fb, qq[k]);
                    return 1;
                }
        }
        *frag = -1;
        if (x->n_notes != y->n_notes || !same_bits(x->notes, y->notes, (size_t)x->n_notes * sizeof *x->notes)) {
            snprintf(what, cap, "the composite's steps");
            return 1;
        }
        for (int p = 0; p < SPR_PLANE__COUNT; p++)
            for (int ch = 0; ch < spr_plane_channels((spr_plane)p) && (x->planes & SPR_PLANE_BIT(p)); ch++)
                if (x->after[p][ch] != y->after[p][ch]) {
                    snprintf(what, cap, "plane %s channel %d after the call: cpu %.9g, gl %.9g", spr_plane_name((spr_plane)p), ch,
                             spr_history_value((spr_plane)p, x->after[p][ch]), spr_history_value((spr_plane)p, y->after[p][ch]));
                    return 1;
                }
    }
    return 0;
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
            fprintf(f, ": test value %s, depth %s, depth write %s, blend rgb %s alpha %s, writes ", depth_names[s->depth_value], func_names[s->depth_func],
                   s->depth_write ? "on" : "off", blend_names[s->blend], blend_names[s->blend_alpha]);
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

/* ---- JSON ---- */
static cJSON *planes_json(unsigned planes, const uint32_t v[SPR_PLANE__COUNT][4])
{
    cJSON *o = cJSON_CreateObject();
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        if (!(planes & SPR_PLANE_BIT(p))) continue;
        const int ch = spr_plane_channels((spr_plane)p);
        if (ch == 1) cJSON_AddNumberToObject(o, spr_plane_name((spr_plane)p), spr_history_value((spr_plane)p, v[p][0]));
        else {
            double d[4];
            for (int c = 0; c < ch; c++) d[c] = spr_history_value((spr_plane)p, v[p][c]);
            cJSON_AddItemToObject(o, spr_plane_name((spr_plane)p), cJSON_CreateDoubleArray(d, ch));
        }
    }
    return o;
}

static cJSON *history_json(const spr_history *h)
{
    cJSON *arr = cJSON_CreateArray();
    static const char *const kinds[] = {"draw_splats", "draw_rects", "composite", "gauss_raster", "gauss_draw"};
    static const char *const tags[] = {"", "eps_nearest", "eps_input", "prefix_node", "gauss_tile", "gauss_blend", "gauss_skip_power",
                                       "gauss_skip_faint", "gauss_stop", "gauss_skip_parallel", "gauss_skip_behind", "gauss_end"};
    _Static_assert(sizeof tags / sizeof tags[0] == SPR_NOTE_GAUSS_END + 1, "a name for every note tag");
    for (int i = 0; i < h->n; i++) {
        const spr_hist_event *e = &h->ev[i];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "pass", e->pass);
        cJSON_AddStringToObject(o, "name", e->pass_name);
        cJSON_AddNumberToObject(o, "group", e->group);
        cJSON_AddStringToObject(o, "kind", kinds[e->kind]);
        cJSON_AddNumberToObject(o, "target", e->target);
        if (e->kind == SPR_HIST_GAUSS_RASTER) {
            cJSON_AddNumberToObject(o, "submitted", (double)e->submitted);
        } else if (e->kind == SPR_HIST_COMPOSITE) {
            cJSON_AddStringToObject(o, "op", spr_composite_info_of(e->op)->name);
            cJSON_AddNumberToObject(o, "eps_t", e->eps_t);
            cJSON *in = cJSON_AddArrayToObject(o, "inputs");
            for (int k = 0; k < e->n_inputs; k++) {
                cJSON *x = planes_json(e->in_planes[k], e->in_vals[k]);
                cJSON_AddNumberToObject(x, "target", e->inputs[k]);
                cJSON_AddItemToArray(in, x);
            }
        } else {
            cJSON *st = cJSON_AddObjectToObject(o, "state");
            cJSON_AddStringToObject(st, "test_value", depth_names[e->state.depth_value]);
            cJSON_AddStringToObject(st, "depth_func", func_names[e->state.depth_func]);
            cJSON_AddBoolToObject(st, "depth_write", e->state.depth_write);
            cJSON_AddStringToObject(st, "blend", blend_names[e->state.blend]);
            cJSON_AddStringToObject(st, "blend_alpha", blend_names[e->state.blend_alpha]);
            cJSON_AddNumberToObject(st, "eps_t", e->state.eps_t);
            cJSON_AddBoolToObject(o, "list", e->list);
            cJSON_AddNumberToObject(o, "submitted", (double)e->submitted);
            cJSON_AddBoolToObject(o, "replay_matches", e->replay_matches);
        }
        cJSON_AddItemToObject(o, "before", planes_json(e->planes, e->before));
        cJSON_AddItemToObject(o, "after", planes_json(e->planes, e->after));
        cJSON *fr = cJSON_AddArrayToObject(o, "fragments");
        for (int f = 0; f < e->n_frags; f++) {
            const spr_hist_frag *x = &e->frags[f];
            cJSON *j = cJSON_CreateObject();
            cJSON_AddNumberToObject(j, "index", x->f.seq);
            cJSON_AddNumberToObject(j, "id", x->f.prim);
            cJSON_AddNumberToObject(j, "group", e->group);
            cJSON_AddNumberToObject(j, "t", x->f.t);
            cJSON_AddNumberToObject(j, "rho", x->f.rho);
            cJSON_AddNumberToObject(j, "z", x->f.z);
            double src[4] = {x->f.src[0], x->f.src[1], x->f.src[2], x->f.src[3]};
            cJSON_AddItemToObject(j, "src", cJSON_CreateDoubleArray(src, 4));
            cJSON_AddNumberToObject(j, "weight", x->f.src[3]);
            cJSON_AddNumberToObject(j, "opacity", x->f.opacity);
            cJSON_AddNumberToObject(j, "test_before", x->z_before);
            cJSON_AddStringToObject(j, "outcome", x->passed < 0 ? "listed" : x->passed ? "pass" : "fail");
            cJSON_AddItemToObject(j, "after", planes_json(e->planes, x->after));
            cJSON_AddItemToArray(fr, j);
        }
        cJSON *nt = cJSON_AddArrayToObject(o, "steps");
        for (int n = 0; n < e->n_notes; n++) {
            const spr_probe_note *x = &e->notes[n];
            cJSON *j = cJSON_CreateObject();
            cJSON_AddStringToObject(j, "step", x->tag > 0 && x->tag <= SPR_NOTE_GAUSS_END ? tags[x->tag] : "note");
            cJSON_AddNumberToObject(j, "k", x->k);
            double v[4] = {x->v[0], x->v[1], x->v[2], x->v[3]};
            cJSON_AddItemToObject(j, "v", cJSON_CreateDoubleArray(v, 4));
            cJSON_AddItemToArray(nt, j);
        }
        cJSON_AddItemToArray(arr, o);
    }
    return arr;
}

int cmd_explain(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "explain", explain_opts, "--pixel X,Y [--backend both|cpu|gl] [--json] [scene options | --scene S.json]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    const char *pix = spr__get(&a, "pixel"), *which = spr__get(&a, "backend");
    const int json = spr__flag(&a, "json");
    int x, y, gl_device = -1;
    char tail;
    if (!pix || sscanf(pix, "%d,%d%c", &x, &y, &tail) != 2) { spr__error(&a, "--pixel X,Y is required (two whole numbers)"); return 2; }
    if (!which) which = "both";
    if (strcmp(which, "both") && strcmp(which, "cpu") && strcmp(which, "gl")) { spr__error(&a, "--backend: '%s' is not both, cpu or gl", which); return 2; }
    if (strcmp(which, "cpu") && spr__get_int(&a, "gl-device", &gl_device, 0, 64) < 0) return 2;
    spr_scene s;
    spr_render_desc rd;
    cli_history_run runs[2];
    int nr = 0, rc = 2;
    memset(runs, 0, sizeof runs);
    if (spr__scene_setup(&a, &s, &rd, 0)) goto done;
    if (x < 0 || y < 0 || x >= s.view.width || y >= s.view.height) {
        spr__error(&a, "--pixel %d,%d lies outside the %dx%d image", x, y, s.view.width, s.view.height);
        goto done;
    }
    if (strcmp(which, "gl")) {
        if (cli_run_history(&s, &rd, "cpu", gl_device, x, y, &runs[nr])) goto done;
        nr++;
    }
    if (strcmp(which, "cpu")) {
        int r = cli_run_history(&s, &rd, "gl", gl_device, x, y, &runs[nr]);
        if (r < 0 || (r > 0 && !strcmp(which, "gl"))) goto done;
        if (r == 0) nr++;
        else fprintf(stderr, "splatref explain: no GL device here: the CPU reference alone\n");
    }
    int dev = -1, dfrag = -1, differ = 0;
    char what[300] = "";
    if (nr == 2) differ = first_difference(&runs[0].h, &runs[1].h, &dev, &dfrag, what, sizeof what);
    if (json) {
        cJSON *o = cJSON_CreateObject();
        const int px[2] = {x, y};
        cJSON_AddItemToObject(o, "pixel", cJSON_CreateIntArray(px, 2));
        cJSON_AddStringToObject(o, "model", s.model);
        cJSON_AddStringToObject(o, "algo", spr_algo_name(rd.algo));
        cJSON_AddNumberToObject(o, "width", s.view.width);
        cJSON_AddNumberToObject(o, "height", s.view.height);
        for (int i = 0; i < nr; i++) {
            cJSON *b = cJSON_AddObjectToObject(o, runs[i].name);
            cJSON_AddStringToObject(b, "renderer", runs[i].renderer);
            cJSON_AddBoolToObject(b, "overflow", runs[i].h.overflow);
            cJSON_AddItemToObject(b, "passes", history_json(&runs[i].h));
        }
        if (nr == 2) {
            cJSON_AddBoolToObject(o, "identical", !differ);
            if (differ) {
                cJSON *d = cJSON_AddObjectToObject(o, "first_difference");
                cJSON_AddNumberToObject(d, "call", dev);
                cJSON_AddNumberToObject(d, "fragment", dfrag);
                cJSON_AddStringToObject(d, "what", what);
            }
        }
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
