/* algo_domain.c — the rendering methods of domain primitives (SPEC §7.7,
 * [R] §4.3–4.4), seven rows of the registry over one rectangle draw.
 *
 * Every method sums (α·c, α) of textured rectangles into an accumulation
 * target and ends with the `domainsum` composite (rgb + (1 − min(α,1))·bg);
 * they differ in which fragments reach the sum:
 *   blendall      one draw, no depth test
 *   noblend       one draw, depth test LESS with write, (c, 1) replaced
 *   twopass       "visibility" (t + ε_t, LESS, write) then "blend" (t, LEQUAL)
 *   darkback-*    back to front by centre distance, one draw per run of
 *                 equally facing rectangles: front faces add; back faces
 *                 replace with black (hard) or subtract α, then `clamp` (soft)
 *   overlap       front to back: each front face and its not yet drawn
 *                 neighbours added under LESS, then the face locked by a
 *                 depth write where α ≥ alpha_ref
 *   prefix        one list draw, then the `prefix` composite
 * Facing and order are decided on the host in double from the view: a
 * plane faces the eye everywhere or nowhere.
 */
#include "spr_algo.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct dom_order {
    size_t n;
    uint32_t *idx;   /* rectangles sorted by distance (see make_order) */
    uint8_t *front;  /* by rectangle: 1 when its normal faces the eye */
} dom_order;

static void order_free(dom_order *o)
{
    free(o->idx);
    free(o->front);
}

typedef struct keyed { double key; uint32_t i; } keyed;
static int by_key(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return x->i < y->i ? -1 : x->i > y->i; /* ties: index */
}

/* Facing and distance of every rectangle from the view (the eye for a
 * perspective view, the view direction for an orthographic one); idx
 * sorted nearest first, or farthest first when back_to_front. */
static spr_result make_order(spr__run *run, int back_to_front, dom_order *o)
{
    const spr_rects *rs = run->desc->rects;
    const double *V = run->b->view.V;
    const size_t n = rs->n;
    memset(o, 0, sizeof *o);
    o->n = n;
    o->idx = malloc((n ? n : 1) * sizeof *o->idx);
    o->front = malloc(n ? n : 1);
    keyed *key = malloc((n ? n : 1) * sizeof *key);
    if (!o->idx || !o->front || !key) {
        free(key);
        order_free(o);
        return spr__fail(run->err, SPR_E_NOMEM, "%s: out of memory ordering %zu rectangles", spr_algo_name(run->desc->algo), n);
    }
    double eye[3];
    for (int k = 0; k < 3; k++) eye[k] = -(V[k] * V[3] + V[4 + k] * V[7] + V[8 + k] * V[11]);
    for (size_t i = 0; i < n; i++) {
        const float *R = rs->f + i * SPR_RECT_FLOATS;
        double to_eye[3], d2 = 0.0, facing = 0.0, zeye = 0.0;
        for (int k = 0; k < 3; k++) {
            to_eye[k] = eye[k] - R[SPR_RECT_C + k];
            d2 += to_eye[k] * to_eye[k];
            zeye += V[8 + k] * R[SPR_RECT_C + k];
        }
        zeye += V[11];
        for (int k = 0; k < 3; k++) facing += (run->b->view.ortho ? V[8 + k] : to_eye[k]) * R[SPR_RECT_N + k];
        o->front[i] = facing > 0.0;
        const double dist = run->b->view.ortho ? -zeye : sqrt(d2);
        key[i] = (keyed){back_to_front ? -dist : dist, (uint32_t)i};
    }
    qsort(key, n, sizeof *key, by_key);
    for (size_t i = 0; i < n; i++) o->idx[i] = key[i].i;
    free(key);
    return SPR_OK;
}

/* A rectangle draw of the run's primitives with the usual state. */
static spr_rect_draw_desc rect_desc(const spr__run *run, spr_rect_output out, spr_blend blend, spr_depth_func func, unsigned mask)
{
    spr_rect_draw_desc d;
    memset(&d, 0, sizeof d);
    d.rects = run->desc->rects;
    d.output = out;
    d.sampling = run->desc->sampling;
    spr_pass_state_defaults(&d.state);
    spr_pass_state_blend(&d.state, blend);
    d.state.depth_value = SPR_DEPTH_PLAIN;
    d.state.depth_func = func;
    d.state.write_mask = mask;
    return d;
}

/* The accumulation target(s) and the image target. */
static spr_result dom_targets(spr__run *run, int *acc, int n_acc, int *out)
{
    spr_result r;
    for (int k = 0; k < n_acc; k++)
        if ((r = spr__run_target(run, SPR_PLANES_OPAQUE, &acc[k]))) return r;
    return spr__run_target(run, SPR_PLANES_IMAGE, out);
}

static spr_result dom_finish(spr__run *run, int acc, int out, int *final_target)
{
    spr_composite_desc c = spr__run_comp(run, SPR_COMP_DOMAINSUM, &acc, 1, out);
    spr_result r = spr__run_composite(run, "composite", &c);
    if (!r) *final_target = out;
    return r;
}

spr_result spr__algo_domain_blendall(spr__run *run, int *final_target)
{
    int acc, out;
    spr_result r;
    if ((r = dom_targets(run, &acc, 1, &out))) return r;
    spr_rect_draw_desc d = rect_desc(run, SPR_ROUT_WEIGHTED, SPR_BLEND_ADD, SPR_FUNC_ALWAYS, SPR_WRITE_COLOR | SPR_WRITE_COUNT);
    if ((r = spr__run_rects(run, "blend", -1, acc, &d))) return r;
    return dom_finish(run, acc, out, final_target);
}

spr_result spr__algo_domain_noblend(spr__run *run, int *final_target)
{
    int acc, out;
    spr_result r;
    if ((r = dom_targets(run, &acc, 1, &out))) return r;
    spr_rect_draw_desc d = rect_desc(run, SPR_ROUT_COLOR, SPR_BLEND_REPLACE, SPR_FUNC_LESS, SPR_WRITE_ALL);
    d.state.depth_write = 1;
    if ((r = spr__run_rects(run, "opaque", -1, acc, &d))) return r;
    return dom_finish(run, acc, out, final_target);
}

spr_result spr__algo_domain_twopass(spr__run *run, int *final_target)
{
    int acc, out;
    spr_result r;
    if ((r = dom_targets(run, &acc, 1, &out))) return r;
    spr_rect_draw_desc d = rect_desc(run, SPR_ROUT_WEIGHTED, SPR_BLEND_REPLACE, SPR_FUNC_LESS, SPR_WRITE_DEPTH | SPR_WRITE_ID);
    d.state.depth_value = SPR_DEPTH_EPS_OFFSET;
    d.state.eps_t = run->eps_t;
    d.state.depth_write = 1;
    if ((r = spr__run_rects(run, "visibility", -1, acc, &d))) return r;
    d = rect_desc(run, SPR_ROUT_WEIGHTED, SPR_BLEND_ADD, SPR_FUNC_LEQUAL, SPR_WRITE_COLOR | SPR_WRITE_COUNT);
    if ((r = spr__run_rects(run, "blend", -1, acc, &d))) return r;
    return dom_finish(run, acc, out, final_target);
}

/* Dark back faces ([R] §4.4.3), hard or soft. */
static spr_result darkback(spr__run *run, int soft, int *final_target)
{
    int acc[2], out;
    spr_result r;
    if ((r = dom_targets(run, acc, soft ? 2 : 1, &out))) return r;
    dom_order o;
    if ((r = make_order(run, 1, &o))) return r;
    int cur = 0;
    for (size_t a = 0; a < o.n && !r;) {
        const int front = o.front[o.idx[a]];
        size_t b = a;
        while (b < o.n && o.front[o.idx[b]] == front) b++;
        spr_rect_draw_desc d;
        if (front) d = rect_desc(run, SPR_ROUT_WEIGHTED, SPR_BLEND_ADD, SPR_FUNC_ALWAYS, SPR_WRITE_COLOR | SPR_WRITE_COUNT);
        else if (soft) d = rect_desc(run, SPR_ROUT_LUMINANCE, SPR_BLEND_SUB, SPR_FUNC_ALWAYS, SPR_WRITE_COLOR);
        else d = rect_desc(run, SPR_ROUT_BLACK, SPR_BLEND_REPLACE, SPR_FUNC_ALWAYS, SPR_WRITE_COLOR);
        d.indices = o.idx + a;
        d.count = b - a;
        if ((r = spr__run_rects(run, front ? "front" : "back", -1, acc[cur], &d))) break;
        if (!front && soft) { /* a run of subtractions, then one clamp: the same as clamping after each (α ≥ 0) */
            spr_composite_desc c = spr__run_comp(run, SPR_COMP_CLAMP, &acc[cur], 1, acc[1 - cur]);
            if ((r = spr__run_composite(run, "clamp", &c))) break;
            cur = 1 - cur;
        }
        a = b;
    }
    order_free(&o);
    return r ? r : dom_finish(run, acc[cur], out, final_target);
}

spr_result spr__algo_domain_darkback_hard(spr__run *run, int *final_target) { return darkback(run, 0, final_target); }
spr_result spr__algo_domain_darkback_soft(spr__run *run, int *final_target) { return darkback(run, 1, final_target); }

/* Overlapping domains ([R] §4.4.4, its pseudocode): front to back, for
 * each front-facing rectangle: it (unless drawn) and its not yet drawn
 * neighbours, nearest first, added under LESS against the locked depth;
 * then it is locked by a depth write where α ≥ alpha_ref. */
spr_result spr__algo_domain_overlap(spr__run *run, int *final_target)
{
    int acc, out;
    spr_result r;
    if ((r = dom_targets(run, &acc, 1, &out))) return r;
    dom_order o;
    if ((r = make_order(run, 0, &o))) return r;
    const spr_rects *rs = run->desc->rects;
    const size_t words = spr_rects_words(rs->n);
    uint8_t *drawn = calloc(o.n ? o.n : 1, 1);
    uint32_t *batch = malloc((o.n ? o.n : 1) * sizeof *batch);
    if (!drawn || !batch) r = spr__fail(run->err, SPR_E_NOMEM, "domain-overlap: out of memory");
    const float ref = run->desc->alpha_ref > 0.0f ? run->desc->alpha_ref : 0.1f;
    for (size_t a = 0; a < o.n && !r; a++) {
        const uint32_t i = o.idx[a];
        if (!o.front[i]) continue;
        size_t m = 0;
        if (!drawn[i]) batch[m++] = i, drawn[i] = 1;
        for (size_t b = 0; b < o.n; b++) {
            const uint32_t j = o.idx[b];
            if (!drawn[j] && spr_rects_neighbours(rs->nbr, words, i, j)) batch[m++] = j, drawn[j] = 1;
        }
        if (m) {
            spr_rect_draw_desc d = rect_desc(run, SPR_ROUT_WEIGHTED, SPR_BLEND_ADD, SPR_FUNC_LESS, SPR_WRITE_COLOR | SPR_WRITE_COUNT);
            d.indices = batch;
            d.count = m;
            if ((r = spr__run_rects(run, "blend", (int)i, acc, &d))) break;
        }
        spr_rect_draw_desc l = rect_desc(run, SPR_ROUT_WEIGHTED, SPR_BLEND_REPLACE, SPR_FUNC_LESS, SPR_WRITE_DEPTH | SPR_WRITE_ID);
        l.state.depth_write = 1;
        l.alpha_ref = ref;
        l.indices = &o.idx[a];
        l.count = 1;
        r = spr__run_rects(run, "lock", (int)i, acc, &l);
    }
    free(drawn);
    free(batch);
    order_free(&o);
    return r ? r : dom_finish(run, acc, out, final_target);
}

/* The exact method: every pixel's fragments listed, then sorted and summed
 * by the prefix op (the GL backend builds the lists in any order). */
spr_result spr__algo_domain_prefix(spr__run *run, int *final_target)
{
    int acc, out;
    spr_result r;
    if ((r = dom_targets(run, &acc, 1, &out))) return r;
    spr_rect_draw_desc d = rect_desc(run, SPR_ROUT_WEIGHTED, SPR_BLEND_REPLACE, SPR_FUNC_ALWAYS, 0);
    d.list = 1;
    if ((r = spr__run_rects(run, "lists", -1, acc, &d))) return r;
    spr_composite_desc c = spr__run_comp(run, SPR_COMP_PREFIX, &acc, 1, out);
    c.rects = run->desc->rects;
    if ((r = spr__run_composite(run, "prefix", &c))) return r;
    *final_target = out;
    return SPR_OK;
}
