/* explain.c — the history of one pixel on either backend, the first
 * difference between two histories, and `explain --json` (spr__inspect.h). */
#include "spr__inspect.h"
#include "spr_glbackend.h"
#include "spr_swrast.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const spr__depth_names[SPR_DEPTH__COUNT] = {"d_f", "d_f + eps_t", "z~ (low precision, [ZP] Eq. 10)", "z~ + rho/n (Voronoi, [ZP] Eq. 14)"};
const char *const spr__func_names[SPR_FUNC__COUNT] = {"LESS", "LEQUAL", "ALWAYS"};
const char *const spr__blend_names[SPR_BLEND__COUNT] = {"replace", "add", "over", "sub", "premultiplied over"};


typedef struct explain_ctx { spr_history *h; } explain_ctx;
static void label_hook(void *user, spr_backend *b, const spr_pass_info *info) { spr_history_pass(((explain_ctx *)user)->h, info); }

int spr__history_run_one(spr_scene *s, const spr_render_desc *rd0, const char *which, const spr_gl_desc *gl, int x, int y, spr__history_run *out,
                         spr_error *errp)
{
    spr_error err = {0};
    spr_backend *inner;
    memset(out, 0, sizeof *out);
    out->name = which;
    if (!strcmp(which, "gl")) {
        spr_gl_desc gd;
        if (gl) gd = *gl;
        else spr_gl_defaults(&gd);
        gd.probe = 1;
        inner = spr_gl_create(&gd, &err);
        if (inner) snprintf(out->renderer, sizeof out->renderer, "gl [%s]", spr_gl_renderer(inner));
    } else {
        inner = spr_swrast_create(s->threads, &err);
        snprintf(out->renderer, sizeof out->renderer, "cpu reference");
    }
    if (!inner) { *errp = err; return err.code == SPR_E_NO_DEVICE ? 1 : -1; }
    spr_backend *b = spr_history_create(inner, x, y, &out->h, &err);
    if (!b) { *errp = err; return -1; }
    spr_render_desc rd = *rd0;
    explain_ctx ec = {&out->h};
    rd.hook = label_hook;
    rd.hook_user = &ec;
    spr_render_result res = {0};
    int rc = spr_render(b, &s->view, &s->cloud, &rd, &res, &err) ? -1 : 0;
    if (rc) {
        errp->code = err.code;
        snprintf(errp->msg, sizeof errp->msg, "%s: %.400s", which, err.msg);
    }
    spr_render_result_free(&res);
    spr_backend_destroy(b);
    out->ok = rc == 0;
    return rc;
}

/* ---- the first difference between two histories ---- */
static int same_bits(const void *p, const void *q, size_t n) { return !memcmp(p, q, n); }

int spr__history_difference(const spr_history *c, const spr_history *g, int *ev, int *frag, char *what, size_t cap)
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

/* ---- JSON: explain --json ---- */
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
            cJSON_AddStringToObject(st, "test_value", spr__depth_names[e->state.depth_value]);
            cJSON_AddStringToObject(st, "depth_func", spr__func_names[e->state.depth_func]);
            cJSON_AddBoolToObject(st, "depth_write", e->state.depth_write);
            cJSON_AddStringToObject(st, "blend", spr__blend_names[e->state.blend]);
            cJSON_AddStringToObject(st, "blend_alpha", spr__blend_names[e->state.blend_alpha]);
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

cJSON *spr__explain_json(const spr_scene *s, const spr_render_desc *rd, int x, int y, const spr__history_run *runs, int nr)
{
    cJSON *o = cJSON_CreateObject();
    const int px[2] = {x, y};
    cJSON_AddItemToObject(o, "pixel", cJSON_CreateIntArray(px, 2));
    cJSON_AddStringToObject(o, "model", s->model);
    cJSON_AddStringToObject(o, "algo", spr_algo_name(rd->algo));
    cJSON_AddNumberToObject(o, "width", s->view.width);
    cJSON_AddNumberToObject(o, "height", s->view.height);
    for (int i = 0; i < nr; i++) {
        cJSON *b = cJSON_AddObjectToObject(o, runs[i].name);
        cJSON_AddStringToObject(b, "renderer", runs[i].renderer);
        cJSON_AddBoolToObject(b, "overflow", runs[i].h.overflow);
        cJSON_AddItemToObject(b, "passes", history_json(&runs[i].h));
    }
    if (nr == 2) {
        int dev, dfrag;
        char what[300] = "";
        const int differ = spr__history_difference(&runs[0].h, &runs[1].h, &dev, &dfrag, what, sizeof what);
        cJSON_AddBoolToObject(o, "identical", !differ);
        if (differ) {
            cJSON *d = cJSON_AddObjectToObject(o, "first_difference");
            cJSON_AddNumberToObject(d, "call", dev);
            cJSON_AddNumberToObject(d, "fragment", dfrag);
            cJSON_AddStringToObject(d, "what", what);
        }
    }
    return o;
}
