/* history.c — pixel history (spr_history.h): a backend wrapper that arms
 * the inner backend's probe around every draw and composite, reads the
 * pixel's planes before and after, and replays the fixed-function stages
 * on the recorded fragments. */
#include "spr_history.h"
#include "spr_arith_c.h"
#include "spr_fixed.h"

#include <stdlib.h>
#include <string.h>

typedef struct hist_backend {
    spr__wrap w;      /* first: a hist_backend is a wrapping spr_backend (backend_wrap.c) */
    spr_history *h;
    spr_probe *probe;
    float *buf;       /* one plane of the view */
    size_t buf_cap;
} hist_backend;

static hist_backend *hb(spr_backend *b) { return (hist_backend *)b; }
#define pass_on spr__wrap_pass_on

double spr_history_value(spr_plane p, uint32_t bits)
{
    const spr_plane_type t = spr_plane_info_of(p)->type;
    if (spr_plane_type_uint(t)) return bits == UINT32_MAX ? -1.0 : (double)bits;
    float f;
    memcpy(&f, &bits, 4);
    return f;
}

/* The pixel's values of every plane of `planes` in target t (value bits). */
static spr_result read_pixel(spr_backend *b, int t, unsigned planes, uint32_t out[SPR_PLANE__COUNT][4])
{
    hist_backend *w = hb(b);
    const spr_view *v = &w->w.inner->view;
    const size_t need = (size_t)v->width * v->height * 4;
    if (need > w->buf_cap) {
        float *nb = realloc(w->buf, need * sizeof *nb);
        if (!nb) return spr__fail(&b->err, SPR_E_NOMEM, "history: out of memory");
        w->buf = nb, w->buf_cap = need;
    }
    memset(out, 0, sizeof(uint32_t) * SPR_PLANE__COUNT * 4);
    const size_t pix = (size_t)w->h->y * v->width + (size_t)w->h->x;
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        if (!(planes & SPR_PLANE_BIT(p))) continue;
        spr_result r = spr_backend_read_plane(w->w.inner, t, (spr_plane)p, w->buf);
        if (r) return pass_on(b, r);
        const int ch = spr_plane_channels((spr_plane)p);
        memcpy(out[p], (const uint32_t *)(const void *)w->buf + pix * (size_t)ch, (size_t)ch * 4);
    }
    return SPR_OK;
}

static spr_hist_event *new_event(spr_backend *b, spr_hist_kind kind, int target)
{
    spr_history *h = hb(b)->h;
    if (h->n == h->cap) {
        int cap = h->cap ? 2 * h->cap : 16;
        spr_hist_event *ne = realloc(h->ev, (size_t)cap * sizeof *ne);
        if (!ne) return NULL;
        h->ev = ne, h->cap = cap;
    }
    spr_hist_event *e = &h->ev[h->n++];
    memset(e, 0, sizeof *e);
    e->kind = kind;
    e->pass = -1;
    e->group = -1;
    e->target = target;
    e->planes = spr_backend_target_planes(hb(b)->w.inner, target);
    e->replay_matches = 1;
    return e;
}

static int by_seq(const void *a, const void *b)
{
    const spr_probe_frag *x = a, *y = b;
    return x->seq < y->seq ? -1 : x->seq > y->seq;
}

/* The probe's records into e: fragments in submission order, notes. */
static spr_result take_probe(spr_backend *b, spr_hist_event *e)
{
    spr_probe *p = hb(b)->probe;
    if (p->overflow) hb(b)->h->overflow = 1;
    qsort(p->frag, (size_t)p->n_frags, sizeof p->frag[0], by_seq); /* seqs are distinct: the order is total */
    e->frags = calloc((size_t)(p->n_frags ? p->n_frags : 1), sizeof *e->frags);
    e->notes = malloc((size_t)(p->n_notes ? p->n_notes : 1) * sizeof *e->notes);
    if (!e->frags || !e->notes) return spr__fail(&b->err, SPR_E_NOMEM, "history: out of memory");
    for (int i = 0; i < p->n_frags; i++) e->frags[i].f = p->frag[i];
    memcpy(e->notes, p->note, (size_t)p->n_notes * sizeof *e->notes);
    e->n_frags = p->n_frags;
    e->n_notes = p->n_notes;
    p->n_frags = p->n_notes = 0;
    p->overflow = 0;
    return SPR_OK;
}

/* One pixel's planes as values (the history keeps their bits). */
typedef struct pixel_values {
    float color[4], depth, test, opacity, normal[4];
    uint32_t id, count;
} pixel_values;

static void bits_to_values(const uint32_t bits[SPR_PLANE__COUNT][4], pixel_values *pv)
{
    memcpy(pv->color, bits[SPR_PLANE_COLOR], sizeof pv->color);
    memcpy(&pv->depth, bits[SPR_PLANE_DEPTH], 4);
    memcpy(&pv->test, bits[SPR_PLANE_TEST], 4);
    memcpy(&pv->opacity, bits[SPR_PLANE_OPACITY], 4);
    memcpy(pv->normal, bits[SPR_PLANE_NORMAL], sizeof pv->normal);
    pv->id = bits[SPR_PLANE_ID][0];
    pv->count = bits[SPR_PLANE_COUNT][0];
}

static void values_to_bits(const pixel_values *pv, uint32_t bits[SPR_PLANE__COUNT][4])
{
    memcpy(bits[SPR_PLANE_COLOR], pv->color, sizeof pv->color);
    memcpy(bits[SPR_PLANE_DEPTH], &pv->depth, 4);
    memcpy(bits[SPR_PLANE_TEST], &pv->test, 4);
    memcpy(bits[SPR_PLANE_OPACITY], &pv->opacity, 4);
    memcpy(bits[SPR_PLANE_NORMAL], pv->normal, sizeof pv->normal);
    bits[SPR_PLANE_ID][0] = pv->id;
    bits[SPR_PLANE_COUNT][0] = pv->count;
}

/* Replay a draw's depth stage and plane writes on its fragments from
 * `before` with the reference's own stages (spr_fixed.h, what swrast runs
 * per pixel), then compare with `after`.  normals: the splats' normals
 * (splat draws that write the normal plane). */
static void replay(spr_hist_event *e, const float *normals)
{
    uint32_t cur[SPR_PLANE__COUNT][4];
    memcpy(cur, e->before, sizeof cur);
    pixel_values pv;
    bits_to_values(cur, &pv);
    const unsigned has = e->planes;
#define PL(p, field) (has & SPR_PLANE_BIT(SPR_PLANE_##p) ? (field) : NULL)
    const spr_fixed_planes pl = {PL(COLOR, pv.color), PL(DEPTH, &pv.depth), PL(TEST, &pv.test), PL(OPACITY, &pv.opacity),
                                 PL(NORMAL, pv.normal), PL(ID, &pv.id), PL(COUNT, &pv.count)};
#undef PL
    const spr_pass_state *s = &e->state;
    for (int i = 0; i < e->n_frags; i++) {
        spr_hist_frag *hf = &e->frags[i];
        const spr_probe_frag *f = &hf->f;
        hf->z_before = pv.test;
        if (e->list) {
            hf->passed = -1;
        } else if ((hf->passed = spr_fixed_depth(s, &pl, 0, f->z))) {
            float nw[4];
            const int splat = e->kind == SPR_HIST_SPLATS;
            if (splat && normals) spr_fragment_normal(f->src, normals + 3 * (size_t)f->prim, nw);
            spr_fixed_writes(s, &pl, 0, f->t, f->src, f->prim, splat ? &f->opacity : NULL, splat && normals ? nw : NULL);
        }
        values_to_bits(&pv, cur);
        memcpy(hf->after, cur, sizeof cur);
    }
    for (int p = 0; p < SPR_PLANE__COUNT && e->replay_matches && !e->list; p++) {
        if (!(e->planes & SPR_PLANE_BIT(p))) continue;
        for (int ch = 0; ch < spr_plane_channels((spr_plane)p); ch++)
            if (cur[p][ch] != e->after[p][ch]) {
                e->replay_matches = 0;
                snprintf(e->replay_note, sizeof e->replay_note, "plane %s channel %d: replay %.9g, backend %.9g", spr_plane_name((spr_plane)p), ch,
                         spr_history_value((spr_plane)p, cur[p][ch]), spr_history_value((spr_plane)p, e->after[p][ch]));
                break;
            }
    }
}

/* Around a call: the pixel's planes before, the probe armed; then
 * disarmed, the planes after and the probe's records. */
static spr_result call_begin(spr_backend *b, spr_hist_event *e)
{
    spr_result r = read_pixel(b, e->target, e->planes, e->before);
    if (!r) hb(b)->w.inner->probe = hb(b)->probe;
    return r;
}
static spr_result call_end(spr_backend *b, spr_hist_event *e, spr_result r)
{
    hb(b)->w.inner->probe = NULL;
    if (r || (r = read_pixel(b, e->target, e->planes, e->after))) return r;
    return take_probe(b, e);
}

static spr_result h_draw(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st)
{
    spr_hist_event *e = new_event(b, SPR_HIST_SPLATS, target);
    if (!e) return spr__fail(&b->err, SPR_E_NOMEM, "history: out of memory");
    e->state = d->state;
    e->submitted = d->indices ? d->count : d->cloud->n;
    e->depth_mask = d->depth_mask, e->mask_target = d->mask_target;
    spr_result r = call_begin(b, e);
    if (r || (r = call_end(b, e, pass_on(b, spr_backend_draw(hb(b)->w.inner, target, d, st))))) return r;
    replay(e, d->cloud->nrm);
    return SPR_OK;
}

static spr_result h_draw_rects(spr_backend *b, int target, const spr_rect_draw_desc *d, spr_draw_stats *st)
{
    spr_hist_event *e = new_event(b, SPR_HIST_RECTS, target);
    if (!e) return spr__fail(&b->err, SPR_E_NOMEM, "history: out of memory");
    e->state = d->state;
    e->submitted = d->indices ? d->count : d->rects->n;
    e->list = d->list;
    e->rect_output = (int)d->output;
    spr_result r = call_begin(b, e);
    if (r || (r = call_end(b, e, pass_on(b, spr_backend_draw_rects(hb(b)->w.inner, target, d, st))))) return r;
    replay(e, NULL);
    return SPR_OK;
}

static spr_result h_composite(spr_backend *b, const spr_composite_desc *c)
{
    hist_backend *w = hb(b);
    spr_hist_event *e = new_event(b, SPR_HIST_COMPOSITE, c->output);
    if (!e) return spr__fail(&b->err, SPR_E_NOMEM, "history: out of memory");
    e->op = c->op;
    e->n_inputs = c->n_inputs;
    e->eps_t = c->eps_t;
    spr_result r;
    for (int k = 0; k < c->n_inputs; k++) {
        e->inputs[k] = c->inputs[k];
        e->in_planes[k] = spr_backend_target_planes(w->w.inner, c->inputs[k]);
        if ((r = read_pixel(b, c->inputs[k], e->in_planes[k], e->in_vals[k]))) return r;
    }
    if ((r = call_begin(b, e))) return r;
    return call_end(b, e, pass_on(b, spr_backend_composite(w->w.inner, c)));
}

static spr_result h_gauss_raster(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st)
{
    spr_hist_event *e = new_event(b, SPR_HIST_GAUSS_RASTER, target);
    if (!e) return spr__fail(&b->err, SPR_E_NOMEM, "history: out of memory");
    memcpy(e->gprm, d->prm, sizeof e->gprm);
    e->submitted = d->n;
    spr_result r = call_begin(b, e);
    if (r) return r;
    return call_end(b, e, pass_on(b, spr_backend_gauss_raster(hb(b)->w.inner, target, d, st)));
}

static spr_result h_gauss_draw(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st)
{
    spr_hist_event *e = new_event(b, SPR_HIST_GAUSS_DRAW, target);
    if (!e) return spr__fail(&b->err, SPR_E_NOMEM, "history: out of memory");
    e->state = d->state;
    memcpy(e->gprm, d->prm, sizeof e->gprm);
    e->submitted = d->count;
    spr_result r = call_begin(b, e);
    if (r || (r = call_end(b, e, pass_on(b, spr_backend_gauss_draw(hb(b)->w.inner, target, d, st))))) return r;
    replay(e, NULL);
    return SPR_OK;
}

static void h_destroy(spr_backend *b)
{
    hist_backend *w = hb(b);
    spr__wrap_release(&w->w);
    free(w->probe);
    free(w->buf);
    free(w);
}

spr_backend *spr_history_create(spr_backend *inner, int x, int y, spr_history *h, spr_error *err)
{
    hist_backend *w = calloc(1, sizeof *w);
    spr_probe *p = w ? calloc(1, sizeof *p) : NULL;
    if (!w || !p) {
        free(w);
        spr_backend_destroy(inner);
        spr__fail(err, SPR_E_NOMEM, "history: out of memory");
        return NULL;
    }
    p->x = x, p->y = y;
    h->x = x, h->y = y;
    spr__wrap_init(&w->w, inner, h_destroy);
    w->h = h;
    w->probe = p;
    spr_backend *b = &w->w.base;
    b->draw_splats = h_draw;
    b->draw_rects = h_draw_rects;
    b->composite = h_composite;
    b->gauss_raster = h_gauss_raster;
    b->gauss_draw = h_gauss_draw;
    return b;
}

void spr_history_pass(spr_history *h, const spr_pass_info *info)
{
    for (; h->labelled < h->n; h->labelled++) {
        spr_hist_event *e = &h->ev[h->labelled];
        e->pass = info->index;
        e->group = info->group;
        snprintf(e->pass_name, sizeof e->pass_name, "%s", info->name);
    }
}

void spr_history_free(spr_history *h)
{
    for (int i = 0; i < h->n; i++) {
        free(h->ev[i].frags);
        free(h->ev[i].notes);
    }
    free(h->ev);
    memset(h, 0, sizeof *h);
}
