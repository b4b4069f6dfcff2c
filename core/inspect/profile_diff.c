/* profile_diff.c — `explain --gauss-profile A --vs B`: why two renderer
 * profiles (SPEC §10.9) give one pixel different values, Gaussian by
 * Gaussian, each difference named by the rule that makes it.
 *
 * Both profiles render on the CPU reference with the pixel recorded (its
 * history: the tile loop's notes, or the ellipses' fragments), and every
 * Gaussian that reaches the pixel under either is looked at twice:
 *   - locally, with the shared arithmetic on the host (the same functions
 *     the backends run): culled and why, outside its tiles or cut, skipped
 *     (power > 0, α below the floor), or offering α and a colour;
 *   - in the pixel's loop (the histories): blended, never reached (the loop
 *     had stopped), and its rank among the Gaussians both profiles blend.
 * Where the local outcomes differ, the rule is found by counterfactual: A
 * with one rule taken from B (then two) — the first hybrid whose outcome for
 * this Gaussian is B's, bit for bit, names it.  Where only the loop differs,
 * the stop rule (6) or the order (7, 8) is named.
 */
#include "spr__inspect.h"
#include "spr_arith_c.h"
#include "spr_profile_diff.h"
#include "spr_swrast.h"
#include "spr_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const spr__gauss_rule_names[10] = {"skeleton", "1 cull", "2 tangent clamp", "3 dilation and compensation", "4 extent",
                                               "5 alpha cap and floor", "6 stop", "7 order", "8 blend", "9 colour"};

/* A with rule r (1 … 9) taken from B. */
static void take_rule(spr_gauss_profile *h, const spr_gauss_profile *b, int r)
{
    switch (r) {
    case 1: h->cull = b->cull; break;
    case 2: h->tan_clamp = b->tan_clamp; break;
    case 3: h->dilation = b->dilation; break;
    case 4: h->extent = b->extent, h->skeleton = b->skeleton; break; /* how far a Gaussian reaches: its tiles, or the cut */
    case 5: h->alpha = b->alpha; break;
    case 6: h->stop = b->stop; break;
    case 7: h->order = b->order; break;
    case 8: h->blend = b->blend; break;
    case 9: h->colour = b->colour; break;
    default: break;
    }
}

enum { L_CULLED = 0, L_OUTSIDE, L_POWER, L_FAINT, L_OFFERS };
typedef struct local { int status; float why, alpha, power, color[3], opacity; } local;

typedef struct ctx {
    const spr_scene *s;
    const spr_render_desc *rd;
    const float *q, *sc;
    int i, j; /* pixel-index coordinates */
} ctx;

/* Gaussian G's outcome at the pixel under profile pf (colour rule applied to G alone, as spr_cloud_gauss_colors_as). */
static local outcome(const ctx *c, const spr_gauss_profile *pf, uint32_t G)
{
    local L = {0};
    const spr_cloud *cl = &c->s->cloud;
    const spr_view *v = &c->s->view;
    float g[SPR_GPRM_COUNT], rec[SPR_GREC_FLOATS];
    spr__gauss_frame(v, 0, c->rd, pf, g);
    /* the colour rule for this one Gaussian: a one-splat view of the cloud */
    const spr_cloud one = spr_cloud_view(cl, G, 1);
    double eye[3];
    spr_pinhole_eye(&v->cv, eye);
    float col[3];
    spr_cloud_gauss_colors_as(&one, eye, pf->colour.sh_max, pf->colour.dc8, pf->colour.post8, pf->colour.clamp_hi, col);
    float sg[3] = {c->sc[3 * (size_t)G], c->sc[3 * (size_t)G + 1], c->sc[3 * (size_t)G + 2]}, mu[3], o;
    spr_gauss_profile_store(pf, cl, G, eye, sg, mu, &o);
    spr_gauss_preprocess3d(g, mu, c->q + 4 * (size_t)G, sg, o, col, rec);
    L.opacity = rec[SPR_GREC_OPACITY];
    memcpy(L.color, col, sizeof col);
    if (rec[SPR_GREC_CULL] != SPR_GCULL_NONE) {
        L.status = L_CULLED, L.why = rec[SPR_GREC_CULL];
        return L;
    }
    const float fi = (float)c->i, fj = (float)c->j;
    if (pf->skeleton != SPR_ALGO_GAUSS_BLEND) {
        const int tx = c->i / 16, ty = c->j / 16;
        if (tx < rec[SPR_GREC_RECT] || tx >= rec[SPR_GREC_RECT + 2] || ty < rec[SPR_GREC_RECT + 1] || ty >= rec[SPR_GREC_RECT + 3] ||
            (pf->extent.kind == SPR_GEXT_BOX &&
             (fi < rec[SPR_GREC_BOX] || fi > rec[SPR_GREC_BOX + 2] || fj < rec[SPR_GREC_BOX + 1] || fj > rec[SPR_GREC_BOX + 3]))) {
            L.status = L_OUTSIDE;
            return L;
        }
        L.power = spr_gauss_power(rec[SPR_GREC_M], rec[SPR_GREC_M + 1], rec[SPR_GREC_CONIC], rec[SPR_GREC_CONIC + 1], rec[SPR_GREC_CONIC + 2], fi, fj);
        if (L.power > 0.0f) {
            L.status = L_POWER;
            return L;
        }
        L.alpha = spr_gauss_alpha(g, L.opacity, L.power);
        L.status = L.alpha < g[SPR_GPRM_ALPHA_MIN] ? L_FAINT : L_OFFERS;
        return L;
    }
    if (fi < rec[SPR_GREC_BOX] || fi > rec[SPR_GREC_BOX + 2] || fj < rec[SPR_GREC_BOX + 1] || fj > rec[SPR_GREC_BOX + 3]) {
        L.status = L_OUTSIDE;
        return L;
    }
    float src[4], power, alpha;
    const int hit = spr_gauss_blend_frag(g, rec[SPR_GREC_M], rec[SPR_GREC_M + 1], rec[SPR_GREC_CONIC], rec[SPR_GREC_CONIC + 1],
                                         rec[SPR_GREC_CONIC + 2], rec[SPR_GREC_OPACITY], col, fi, fj, src, &power, &alpha);
    L.power = power, L.alpha = alpha;
    L.status = hit ? L_OFFERS : power > 0.0f ? L_POWER : power < -g[SPR_GPRM_CUT] ? L_OUTSIDE : L_FAINT;
    return L;
}

static int same_local(const local *a, const local *b)
{
    if (a->status != b->status) return 0;
    if (a->status == L_CULLED) return a->why == b->why;
    if (a->status != L_OFFERS) return 1;
    return !memcmp(&a->alpha, &b->alpha, sizeof a->alpha) && !memcmp(a->color, b->color, sizeof a->color);
}

static void describe_local(const local *L, const spr_gauss_profile *pf, char *out, size_t cap)
{
    static const char *const why[] = {"", "near plane", "degenerate footprint", "outside the clip box", "smaller than the minimum size"};
    switch (L->status) {
    case L_CULLED: snprintf(out, cap, "culled: %s", why[(int)L->why < 5 ? (int)L->why : 0]); break;
    case L_OUTSIDE: snprintf(out, cap, pf->skeleton == SPR_ALGO_GAUSS_BLEND ? "cut: outside its ellipse" : "outside: its tiles miss this pixel"); break;
    case L_POWER: snprintf(out, cap, "skipped: power %.6g > 0", L->power); break;
    case L_FAINT: snprintf(out, cap, "skipped: alpha %.6g below the floor", L->alpha); break;
    default: snprintf(out, cap, "alpha %.6g, colour (%.4g, %.4g, %.4g)", L->alpha, L->color[0], L->color[1], L->color[2]);
    }
}

/* Per profile, from its history: each Gaussian's fate in the pixel's loop (1 blended, 2 skipped, 3 stopped here), its
 * rank among the blended ones front to back, and whether the loop stopped. */
typedef struct fate { uint32_t id; int what, rank; float alpha; } fate;
typedef struct loop { fate *f; int n, cap, stopped; float color[4]; } loop;

static int loop_add(loop *l, uint32_t id, int what, float alpha)
{
    if (l->n == l->cap) {
        int cap = l->cap ? 2 * l->cap : 64;
        fate *f = realloc(l->f, (size_t)cap * sizeof *f);
        if (!f) return -1;
        l->f = f, l->cap = cap;
    }
    l->f[l->n++] = (fate){id, what, -1, alpha};
    return 0;
}

static int read_loop(const spr_history *h, loop *l)
{
    memset(l, 0, sizeof *l);
    for (int e = 0; e < h->n; e++) {
        const spr_hist_event *ev = &h->ev[e];
        if (ev->planes & SPR_PLANE_BIT(SPR_PLANE_COLOR)) memcpy(l->color, ev->after[SPR_PLANE_COLOR], sizeof l->color);
        if (ev->kind == SPR_HIST_GAUSS_RASTER)
            for (int k = 0; k < ev->n_notes; k++) {
                const spr_probe_note *n = &ev->notes[k];
                int what = n->tag == SPR_NOTE_GAUSS_BLEND ? 1 : n->tag == SPR_NOTE_GAUSS_STOP ? 3 : n->tag == SPR_NOTE_GAUSS_TILE || n->tag == SPR_NOTE_GAUSS_END ? 0 : 2;
                if (n->tag == SPR_NOTE_GAUSS_STOP) l->stopped = 1;
                if (what && loop_add(l, (uint32_t)n->k, what, n->v[1])) return -1;
            }
        if (ev->kind == SPR_HIST_GAUSS_DRAW) /* farthest first: ranked below front to back */
            for (int k = ev->n_frags - 1; k >= 0; k--)
                if (loop_add(l, ev->frags[k].f.prim, 1, ev->frags[k].f.rho)) return -1;
    }
    int r = 0;
    for (int k = 0; k < l->n; k++)
        if (l->f[k].what == 1) l->f[k].rank = r++;
    return 0;
}

static const fate *find(const loop *l, uint32_t id)
{
    for (int k = 0; k < l->n; k++)
        if (l->f[k].id == id) return &l->f[k];
    return NULL;
}

static int pdiff_add(spr__pdiff *d, const spr__pdiff_row *row)
{
    if (d->n == d->cap) {
        int cap = d->cap ? 2 * d->cap : 32;
        spr__pdiff_row *r = realloc(d->rows, (size_t)cap * sizeof *r);
        if (!r) return -1;
        d->rows = r, d->cap = cap;
    }
    d->rows[d->n++] = *row;
    return 0;
}

/* The rule(s) that turn A's local outcome for G into B's: one rule, else a pair; 0 when none does. */
static int name_rules(const ctx *c, const spr_gauss_profile *A, const spr_gauss_profile *B, uint32_t G, const local *LB, char *out, size_t cap)
{
    static const int local_rules[] = {1, 2, 3, 4, 5, 9};
    for (int a = 0; a < 6; a++) {
        spr_gauss_profile h = *A;
        take_rule(&h, B, local_rules[a]);
        local L = outcome(c, &h, G);
        if (same_local(&L, LB)) return snprintf(out, cap, "%s", spr__gauss_rule_names[local_rules[a]]), 1;
    }
    for (int a = 0; a < 6; a++)
        for (int b = a + 1; b < 6; b++) {
            spr_gauss_profile h = *A;
            take_rule(&h, B, local_rules[a]);
            take_rule(&h, B, local_rules[b]);
            local L = outcome(c, &h, G);
            if (same_local(&L, LB))
                return snprintf(out, cap, "%s + %s (together)", spr__gauss_rule_names[local_rules[a]], spr__gauss_rule_names[local_rules[b]]), 2;
        }
    snprintf(out, cap, "three or more rules together");
    return 0;
}

int spr__profile_diff(spr_scene *s, const spr_render_desc *rd, int pa, int pb, int x, int y, spr__pdiff *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    const spr_gauss_profile *A = spr_gauss_profile_at(pa), *B = spr_gauss_profile_at(pb);
    if (!A || !B) return spr__fail(err, SPR_E_ARG, "explain --vs: no such profile"), -1;
    if (rd->algo == SPR_ALGO_GAUSS2D) return spr__fail(err, SPR_E_ARG, "explain --vs: gauss2d is not compared (gauss3d and gauss-blend are)"), -1;
    out->a = A, out->b = B;
    spr_render_desc ra = *rd, rb = *rd;
    ra.algo = A->skeleton, ra.gauss_profile = pa + 1;
    rb.algo = B->skeleton, rb.gauss_profile = pb + 1;
    spr__history_run ha, hb;
    if (spr__history_run_one(s, &ra, "cpu", NULL, x, y, &ha, err)) return -1;
    if (spr__history_run_one(s, &rb, "cpu", NULL, x, y, &hb, err)) {
        spr_history_free(&ha.h);
        return -1;
    }
    loop la, lb;
    int rc = -1;
    const size_t n = s->cloud.n;
    float *q = malloc(n * 4 * sizeof *q), *sc = malloc(n * 3 * sizeof *sc);
    memset(&la, 0, sizeof la), memset(&lb, 0, sizeof lb);
    if (!q || !sc || read_loop(&ha.h, &la) || read_loop(&hb.h, &lb)) {
        spr__fail(err, SPR_E_NOMEM, "explain --vs: out of memory");
        goto done;
    }
    spr__gauss_of_cloud(&s->cloud, q, sc);
    ctx c = {s, rd, q, sc, x, s->view.height - 1 - y};
    memcpy(out->color_a, la.color, sizeof out->color_a);
    memcpy(out->color_b, lb.color, sizeof out->color_b);
    /* every Gaussian either loop visited, once, in A's order then B's */
    for (int side = 0; side < 2; side++) {
        const loop *l = side ? &lb : &la;
        for (int k = 0; k < l->n; k++) {
            const uint32_t G = l->f[k].id;
            if (side && find(&la, G)) continue;
            const fate *fa = find(&la, G), *fb = find(&lb, G);
            local LA = outcome(&c, A, G), LB = outcome(&c, B, G);
            spr__pdiff_row row = {G, "", "", ""};
            describe_local(&LA, A, row.a, sizeof row.a);
            describe_local(&LB, B, row.b, sizeof row.b);
            if (!same_local(&LA, &LB)) {
                if (LA.status != L_OFFERS && LB.status != L_OFFERS) { /* dropped by both, only for different reasons */
                    out->quiet++;
                    continue;
                }
                name_rules(&c, A, B, G, &LB, row.rule, sizeof row.rule);
            } else if (LA.status == L_OFFERS && (!fa || fa->what != 1) != (!fb || fb->what != 1)) {
                const int a_out = !fa || fa->what != 1; /* A did not blend it: its loop had stopped */
                snprintf(row.a + strlen(row.a), sizeof row.a - strlen(row.a), a_out ? "; not blended: the loop stopped" : "; blended");
                snprintf(row.b + strlen(row.b), sizeof row.b - strlen(row.b), a_out ? "; blended" : "; not blended: the loop stopped");
                const int stop_rule = A->stop.t_min != B->stop.t_min || A->stop.le != B->stop.le;
                snprintf(row.rule, sizeof row.rule, stop_rule ? "%s" : "%s (the same threshold reached earlier: the Gaussians in front differ)",
                         spr__gauss_rule_names[6]);
            } else if (fa && fb && fa->what == 1 && fb->what == 1) {
                /* blended by both: reordered when the Gaussians in front of it are not the same ones */
                int moved = 0;
                for (int m = 0; m < la.n && !moved; m++) {
                    if (la.f[m].what != 1 || la.f[m].id == G) continue;
                    const fate *o = find(&lb, la.f[m].id);
                    if (o && o->what == 1 && (la.f[m].rank < fa->rank) != (o->rank < fb->rank)) moved = 1;
                }
                if (!moved) continue;
                snprintf(row.a + strlen(row.a), sizeof row.a - strlen(row.a), "; rank %d front to back", fa->rank + 1);
                snprintf(row.b + strlen(row.b), sizeof row.b - strlen(row.b), "; rank %d front to back", fb->rank + 1);
                snprintf(row.rule, sizeof row.rule, "%s%s", spr__gauss_rule_names[7],
                         A->skeleton != B->skeleton ? " (per-tile depth vs one global order)" : "");
            } else continue;
            if (pdiff_add(out, &row)) {
                spr__fail(err, SPR_E_NOMEM, "explain --vs: out of memory");
                goto done;
            }
        }
    }
    rc = 0;
done:
    free(q), free(sc), free(la.f), free(lb.f);
    spr_history_free(&ha.h), spr_history_free(&hb.h);
    if (rc) spr__pdiff_free(out);
    return rc;
}

void spr__pdiff_free(spr__pdiff *d)
{
    free(d->rows);
    d->rows = NULL;
    d->n = d->cap = 0;
}
