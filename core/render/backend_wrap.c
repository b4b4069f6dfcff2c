/* backend_wrap.c — the plumbing of backends that wrap another (the trace
 * backend, the history backend): every entry point forwards to the inner
 * backend through its validating wrapper, failures carry the inner
 * backend's message, and target handles stay equal on both sides because
 * every target call goes through here and both take the lowest free handle. */
#include "spr_backend.h"

#include <stdlib.h>

static spr__wrap *wr(spr_backend *b) { return (spr__wrap *)b; }

spr_result spr__wrap_pass_on(spr_backend *b, spr_result r)
{
    if (r) b->err = wr(b)->inner->err;
    return r;
}

static spr_result w_set_view(spr_backend *b, const spr_view *v) { return spr__wrap_pass_on(b, spr_backend_set_view(wr(b)->inner, v)); }

spr_result spr__wrap_target_create(spr_backend *b, unsigned mask, int *out)
{
    spr__wrap *w = wr(b);
    int theirs;
    spr_result r = spr__backend_add_target(b, mask, out, (void **)&w->slots, &w->cap, 1);
    if (r) return r;
    if ((r = spr_backend_target_create(w->inner, mask, &theirs)) || theirs != *out) {
        if (!r) spr_backend_target_destroy(w->inner, theirs);
        return r ? spr__wrap_pass_on(b, r) : spr__fail(&b->err, SPR_E_BACKEND, "%s: handles out of step (%d vs %d)", b->name, *out, theirs);
    }
    return SPR_OK;
}

static void w_target_destroy(spr_backend *b, int target) { spr_backend_target_destroy(wr(b)->inner, target); }
static spr_result w_clear(spr_backend *b, int target, const float c[4]) { return spr__wrap_pass_on(b, spr_backend_clear(wr(b)->inner, target, c)); }
static spr_result w_draw(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st)
{
    return spr__wrap_pass_on(b, spr_backend_draw(wr(b)->inner, target, d, st));
}
static spr_result w_draw_rects(spr_backend *b, int target, const spr_rect_draw_desc *d, spr_draw_stats *st)
{
    return spr__wrap_pass_on(b, spr_backend_draw_rects(wr(b)->inner, target, d, st));
}
static spr_result w_gauss_preprocess(spr_backend *b, const spr_gauss_desc *d, float *rec)
{
    return spr__wrap_pass_on(b, spr_backend_gauss_preprocess(wr(b)->inner, d, rec));
}
static spr_result w_gauss_raster(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st)
{
    return spr__wrap_pass_on(b, spr_backend_gauss_raster(wr(b)->inner, target, d, st));
}
static spr_result w_gauss_draw(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st)
{
    return spr__wrap_pass_on(b, spr_backend_gauss_draw(wr(b)->inner, target, d, st));
}
static spr_result w_gauss_backward(spr_backend *b, const spr_gauss_bwd_desc *d, float *sums, float *out)
{
    return spr__wrap_pass_on(b, spr_backend_gauss_backward(wr(b)->inner, d, sums, out));
}
static spr_result w_fits(spr_backend *b, const spr_fit_desc *d) { return spr__wrap_pass_on(b, spr_backend_fits(wr(b)->inner, d)); }
static spr_result w_composite(spr_backend *b, const spr_composite_desc *c) { return spr__wrap_pass_on(b, spr_backend_composite(wr(b)->inner, c)); }
static spr_result w_read(spr_backend *b, int target, spr_plane p, void *out)
{
    return spr__wrap_pass_on(b, spr_backend_read_plane(wr(b)->inner, target, p, out));
}

void spr__wrap_init(spr__wrap *w, spr_backend *inner, void (*destroy)(spr_backend *))
{
    w->inner = inner;
    spr_backend *b = &w->base;
    b->name = inner->name; /* the planes are the inner backend's */
    b->host_threads = inner->host_threads;
    b->set_view = w_set_view;
    b->target_create = spr__wrap_target_create;
    b->target_destroy = w_target_destroy;
    b->clear = w_clear;
    b->draw_splats = w_draw;
    b->draw_rects = w_draw_rects;
    b->composite = w_composite;
    b->gauss_preprocess = w_gauss_preprocess;
    b->gauss_raster = w_gauss_raster;
    b->gauss_draw = w_gauss_draw;
    b->gauss_backward = w_gauss_backward;
    b->fits = w_fits;
    b->read_plane = w_read;
    b->destroy = destroy;
}

void spr__wrap_release(spr__wrap *w)
{
    spr_backend_destroy(w->inner);
    free(w->slots);
}
