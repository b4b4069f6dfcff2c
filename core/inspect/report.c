/* report.c — what `check` and `parity` report, shared by the command line
 * and the foreign-language interface (spr__inspect.h): the reference plane
 * an image is checked against, the tier's bounds, report.json of check and
 * of parity. */
#include "spr__inspect.h"
#include "spr_image.h"
#include "spr_swrast.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int spr__check_tier(spr__args *a, const char *t, double u, int lsb, int pos, int bits, spr_check_desc *d)
{
    int64_t ulp = u >= 0.0 ? (int64_t)u : -1;
    if (t && strcmp(t, "A") && strcmp(t, "B") && strcmp(t, "C")) { spr__error(a, "--tier: '%s' is not A, B or C", t); return -1; }
    const int bounds = ulp >= 0 || lsb >= 0 || pos;
    d->tier = t ? (spr_tier)(t[0] - 'A') : bounds ? SPR_TIER_B : SPR_TIER_A;
    if (d->tier == SPR_TIER_A && bounds) { spr__error(a, "Tier A is bit-exact: --ulp, --lsb and --position-tolerance need --tier B"); return -1; }
    if (ulp >= 0 && bits != 32) { spr__error(a, "--ulp applies to float (PFM) images; this one has %d-bit values: use --lsb", bits); return -1; }
    if (d->tier == SPR_TIER_B && ulp < 0 && lsb < 0) lsb = 1; /* PARITY.md: ≤ 1 LSB expected */
    d->bits = bits, d->ulp = ulp, d->lsb = lsb, d->position = pos;
    return 0;
}

int spr__check_channels(spr__args *a, const char *name, float **test, int *tch, int rch, int w, int h)
{
    if (*tch == rch) return 0;
    if (rch == 1 && *tch == 3) {
        const size_t np = (size_t)w * h;
        for (size_t p = 0; p < np; p++)
            if ((*test)[3 * p] != (*test)[3 * p + 1] || (*test)[3 * p] != (*test)[3 * p + 2]) goto mismatch;
        for (size_t p = 0; p < np; p++) (*test)[p] = (*test)[3 * p];
        *tch = 1;
        return 0;
    }
mismatch:
    spr__error(a, "%s has %d channel%s, the reference has %d%s", name, *tch, *tch > 1 ? "s" : "", rch,
               *tch == 4 ? " (write RGB without alpha)" : "");
    return -1;
}

/* The plane the image holds, grabbed after the pass that has it. */
typedef struct plane_grab {
    spr_plane plane;
    int channel;      /* −1: all of the plane's channels (colour: rgb); 3: the weight */
    int want_pass;    /* −1: the last pass that has the plane */
    float *buf;       /* W·H·channels of the plane */
    int got_pass;
    char pass_name[48];
    int failed;
    spr_error err;
} plane_grab;

static void grab_hook(void *user, spr_backend *b, const spr_pass_info *info)
{
    plane_grab *g = user;
    if (g->failed || (g->want_pass >= 0 && info->index != g->want_pass)) return;
    if (!(spr_backend_target_planes(b, info->target) & SPR_PLANE_BIT(g->plane))) return;
    if (spr_backend_read_plane_f(b, info->target, g->plane, g->buf)) { g->failed = 1; g->err = b->err; return; }
    g->got_pass = info->index;
    if (info->group >= 0) snprintf(g->pass_name, sizeof g->pass_name, "%s k%d", info->name, info->group);
    else snprintf(g->pass_name, sizeof g->pass_name, "%s", info->name);
}

int spr__check_reference(spr__args *a, spr_scene *s, const spr_render_desc *rd0, const char *pname, int pass, float **ref_out, int *ch_out,
                         char *what, size_t what_cap)
{
    plane_grab g = {SPR_PLANE_COLOR, -1, pass, NULL, -1, "", 0, {0}};
    *ref_out = NULL;
    if (pname && strcmp(pname, "color") && strcmp(pname, "colour")) {
        int p = 0;
        while (p < SPR_PLANE__COUNT && strcmp(spr_plane_name((spr_plane)p), pname)) p++;
        if (!strcmp(pname, "weight")) p = SPR_PLANE_COLOR, g.channel = 3;
        else if (p == SPR_PLANE__COUNT || p == SPR_PLANE_NORMAL) {
            spr__error(a, "--plane: '%s' is not color, weight, depth, test, id, count, opacity, transmittance, contrib, invdepth or surfdepth", pname);
            return -1;
        }
        g.plane = (spr_plane)p;
    }
    const int final = g.plane == SPR_PLANE_COLOR && g.channel < 0 && g.want_pass < 0;
    const size_t np = (size_t)s->view.width * s->view.height;
    const int pch = spr_plane_channels(g.plane);
    spr_render_desc rd = *rd0;
    spr_render_result res = {0};
    spr_backend *b = NULL;
    spr_error err = {0};
    int rc = -1;
    if (!(g.buf = malloc(np * (size_t)pch * sizeof(float)))) { spr__error(a, "out of memory"); return -1; }
    if (!final) rd.hook = grab_hook, rd.hook_user = &g;
    if (!(b = spr_swrast_create(s->threads, &err)) || spr_render(b, &s->view, &s->cloud, &rd, &res, &err)) {
        spr__error(a, "%s", err.msg);
        goto done;
    }
    if (g.failed) { spr__error(a, "%s", g.err.msg); goto done; }
    int rch = 3;
    float *ref = g.buf;
    if (final) {
        for (size_t p = 0; p < np; p++)
            for (int c = 0; c < 3; c++) ref[3 * p + c] = res.rgba[4 * p + c];
    } else if (g.got_pass < 0) {
        if (g.want_pass >= 0) spr__error(a, "--pass %d: no such pass has a %s plane (render --dump lists them)", g.want_pass, spr_plane_name(g.plane));
        else spr__error(a, "no pass of %s has a %s plane", spr_algo_name(rd.algo), spr_plane_name(g.plane));
        goto done;
    } else if (g.plane == SPR_PLANE_COLOR) { /* rgb, or the weight alone */
        rch = g.channel == 3 ? 1 : 3;
        for (size_t p = 0; p < np; p++)
            for (int c = 0; c < rch; c++) ref[rch * p + c] = ref[4 * p + (g.channel == 3 ? 3 : c)];
    } else {
        rch = pch; /* ids and counts as floats, none = −1 (as --dump) */
    }
    if (final) snprintf(what, what_cap, "final colour");
    else snprintf(what, what_cap, "%s%s after pass %d (%s)", g.channel == 3 ? "weight" : spr_plane_name(g.plane),
                  g.channel == 3 ? " (colour channel 4)" : "", g.got_pass, g.pass_name);
    *ref_out = g.buf, g.buf = NULL;
    *ch_out = rch;
    rc = 0;
done:
    free(g.buf);
    spr_render_result_free(&res);
    spr_backend_destroy(b);
    return rc;
}

void spr__check_bounds_text(const spr_check_desc *d, char *bounds, size_t cap)
{
    snprintf(bounds, cap, "bit-exact");
    if (d->tier == SPR_TIER_B) {
        size_t at = 0;
        bounds[0] = '\0';
        if (d->ulp >= 0) at += (size_t)snprintf(bounds + at, cap - at, "ulp <= %lld", (long long)d->ulp);
        if (d->lsb >= 0 && at < cap) at += (size_t)snprintf(bounds + at, cap - at, "%slsb <= %d", at ? ", " : "", d->lsb);
        if (d->position && at < cap) snprintf(bounds + at, cap - at, "%sposition +-1 pixel", at ? ", " : "");
    }
    if (d->tier == SPR_TIER_C) snprintf(bounds, cap, "diagnostics only");
}

cJSON *spr__check_json(const char *ref_label, const char *image, const char *what, int w, int h, int ch, const spr_check_desc *d,
                       const spr_check_result *r, const char *explain)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "reference", ref_label);
    cJSON_AddStringToObject(o, "image", image);
    cJSON_AddStringToObject(o, "plane", what);
    cJSON_AddNumberToObject(o, "width", w);
    cJSON_AddNumberToObject(o, "height", h);
    cJSON_AddNumberToObject(o, "channels", ch);
    cJSON_AddNumberToObject(o, "bits", d->bits);
    cJSON_AddStringToObject(o, "tier", spr_tier_name(d->tier));
    if (d->ulp >= 0) cJSON_AddNumberToObject(o, "ulp_bound", (double)d->ulp);
    if (d->lsb >= 0) cJSON_AddNumberToObject(o, "lsb_bound", d->lsb);
    cJSON_AddNumberToObject(o, "position_tolerance", d->position);
    cJSON_AddNumberToObject(o, "pixels", (double)r->pixels);
    cJSON_AddNumberToObject(o, "differing_pixels", (double)r->differing);
    cJSON_AddNumberToObject(o, "failing_pixels", (double)r->failing);
    cJSON_AddNumberToObject(o, "position_rescued_pixels", (double)r->rescued);
    if (d->bits == 32) cJSON_AddNumberToObject(o, "max_ulp", (double)r->max_ulp);
    cJSON_AddNumberToObject(o, "max_lsb", r->max_lsb);
    cJSON_AddNumberToObject(o, "max_abs", isfinite(r->max_abs) ? r->max_abs : -1.0);
    cJSON_AddNumberToObject(o, "mean_abs", r->mean_abs);
    cJSON_AddNumberToObject(o, "zp_eps", r->zp_eps);
    if (r->first_x >= 0) {
        cJSON *f = cJSON_AddObjectToObject(o, r->failing ? "first_failing" : "first_differing");
        cJSON_AddNumberToObject(f, "x", r->first_x);
        cJSON_AddNumberToObject(f, "y", r->first_y);
        cJSON_AddNumberToObject(f, "row_from_top", h - 1 - r->first_y);
        cJSON_AddNumberToObject(f, "channel", r->first_channel);
        cJSON_AddNumberToObject(f, "reference", r->first_ref);
        cJSON_AddNumberToObject(f, "image", r->first_test);
        if (explain && explain[0]) cJSON_AddStringToObject(f, "explain", explain);
    }
    cJSON_AddStringToObject(o, "verdict", d->tier == SPR_TIER_C ? "diagnostic" : r->pass ? "pass" : "fail");
    return o;
}

const char *spr__cpu_flags(void)
{
    static char buf[128];
    __builtin_cpu_init();
    snprintf(buf, sizeof buf, "fma=%d avx=%d avx2=%d avx512f=%d", __builtin_cpu_supports("fma") != 0,
             __builtin_cpu_supports("avx") != 0, __builtin_cpu_supports("avx2") != 0, __builtin_cpu_supports("avx512f") != 0);
    return buf;
}

cJSON *spr__parity_json(const spr__parity_set *r)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "reference", "cpu");
    cJSON_AddStringToObject(o, "test", "gl");
    cJSON_AddStringToObject(o, "gl_renderer", r->renderer);
    cJSON_AddStringToObject(o, "cpu_flags", spr__cpu_flags());
    cJSON_AddStringToObject(o, "model", r->s->model);
    cJSON_AddNumberToObject(o, "splats", (double)r->s->cloud.n);
    cJSON_AddNumberToObject(o, "width", r->s->view.width);
    cJSON_AddNumberToObject(o, "height", r->s->view.height);
    cJSON *algos = cJSON_AddArrayToObject(o, "algorithms");
    for (int a = 0; a < r->n; a++) {
        const spr_parity_report *p = r->rep[a];
        cJSON *e = cJSON_CreateObject();
        cJSON_AddStringToObject(e, "algo", r->algo[a]);
        cJSON_AddBoolToObject(e, "bit_exact", spr_parity_exact(p));
        cJSON_AddNumberToObject(e, "planes", p->n_planes);
        cJSON_AddNumberToObject(e, "exact_planes", p->exact_planes);
        cJSON_AddNumberToObject(e, "max_ulp", (double)p->max_ulp);
        cJSON_AddNumberToObject(e, "passes_ref", p->passes_ref);
        cJSON_AddNumberToObject(e, "passes_test", p->passes_test);
        cJSON_AddNumberToObject(e, "stats_mismatches", p->stats_mismatches);
        cJSON_AddStringToObject(e, "first_stats_mismatch", p->first_stats_mismatch);
        cJSON *planes = cJSON_AddArrayToObject(e, "plane_results");
        for (int i = 0; i < p->n_planes; i++) {
            const spr_plane_diff *d = &p->planes[i];
            cJSON *q = cJSON_CreateObject();
            cJSON_AddNumberToObject(q, "pass", d->pass);
            cJSON_AddStringToObject(q, "pass_name", d->pass_name);
            cJSON_AddNumberToObject(q, "group", d->group);
            cJSON_AddStringToObject(q, "plane", spr_parity_plane_name(d->plane));
            cJSON_AddNumberToObject(q, "differing_pixels", (double)d->differing_pixels);
            cJSON_AddNumberToObject(q, "max_ulp", (double)d->max_ulp);
            cJSON_AddNumberToObject(q, "max_abs", d->max_abs); /* cJSON writes null for NaN and infinity */
            if (d->differing_pixels) {
                cJSON *f = cJSON_AddObjectToObject(q, "first");
                cJSON_AddNumberToObject(f, "x", d->first_x);
                cJSON_AddNumberToObject(f, "y", d->first_y);
                cJSON_AddNumberToObject(f, "channel", d->first_channel);
                cJSON_AddNumberToObject(f, "cpu", d->first_ref);
                cJSON_AddNumberToObject(f, "gl", d->first_test);
                if (r->dir && d->heatmap[0]) {
                    char hm[1300];
                    snprintf(hm, sizeof hm, "%s/%s", r->dir, d->heatmap); /* where it ends up, not the temporary directory */
                    cJSON_AddStringToObject(q, "heatmap", hm);
                }
            }
            cJSON_AddItemToArray(planes, q);
        }
        cJSON_AddItemToArray(algos, e);
    }
    return o;
}
