/* backend_trace.c — the trace backend of spr_trace.h: each entry point
 * forwards to the inner backend (backend_wrap.c) and writes one line. */
#include "spr_algo.h"
#include "spr_trace.h"

#include <stdlib.h>
#include <string.h>

typedef struct trace_backend {
    spr__wrap w; /* first: a trace_backend is a wrapping spr_backend */
    FILE *out;
} trace_backend;

static trace_backend *tr(spr_backend *b) { return (trace_backend *)b; }
#define pass_on spr__wrap_pass_on

static void planes(FILE *f, unsigned mask)
{
    int first = 1;
    for (int p = 0; p < SPR_PLANE__COUNT; p++)
        if (mask & SPR_PLANE_BIT(p)) { fprintf(f, "%s%s", first ? "" : ",", spr_plane_name((spr_plane)p)); first = 0; }
    if (first) fprintf(f, "-");
}

static spr_result t_set_view(spr_backend *b, const spr_view *v)
{
    fprintf(tr(b)->out, "set_view %dx%d%s near %.9g far %.9g\n", v->width, v->height, v->ortho ? " ortho" : "", v->near_plane, v->far_plane);
    return pass_on(b, spr_backend_set_view(tr(b)->w.inner, v));
}

static spr_result t_target_create(spr_backend *b, unsigned mask, int *out)
{
    trace_backend *t = tr(b);
    spr_result r = spr__wrap_target_create(b, mask, out);
    if (r) return r;
    fprintf(t->out, "target_create t%d planes ", *out);
    planes(t->out, mask);
    fprintf(t->out, "\n");
    return SPR_OK;
}

static void t_target_destroy(spr_backend *b, int target)
{
    fprintf(tr(b)->out, "target_destroy t%d\n", target);
    spr_backend_target_destroy(tr(b)->w.inner, target);
}

static spr_result t_clear(spr_backend *b, int target, const float c[4])
{
    fprintf(tr(b)->out, "clear t%d color (%.9g, %.9g, %.9g, %.9g), other planes to the plane table's values\n", target, c[0], c[1],
            c[2], c[3]);
    return pass_on(b, spr_backend_clear(tr(b)->w.inner, target, c));
}

static const char *const depth_names[SPR_DEPTH__COUNT] = {"d_f", "d_f+eps_t", "z_lowres", "voronoi"};
static const char *const func_names[SPR_FUNC__COUNT] = {"LESS", "LEQUAL", "ALWAYS"};
static const char *const blend_names[SPR_BLEND__COUNT] = {"replace", "add", "over", "sub", "premultiplied over"};

/* The depth test, write and blends of a pass state, then the planes written. */
static void print_state(FILE *f, const spr_pass_state *s)
{
    fprintf(f, "test %s %s, depth write %s, blend rgb %s alpha %s, writes ", func_names[s->depth_func], depth_names[s->depth_value],
            s->depth_write ? "on" : "off", blend_names[s->blend], blend_names[s->blend_alpha]);
    planes(f, s->write_mask);
    fprintf(f, ", eps_t %.9g", s->eps_t);
}

static void print_result(trace_backend *t, spr_result r, const spr_draw_stats *st)
{
    if (!r) fprintf(t->out, " -> %llu fragments, %llu passed\n", (unsigned long long)st->generated, (unsigned long long)st->passed);
    else fprintf(t->out, " -> failed: %s\n", t->w.base.err.msg);
}

static spr_result t_draw(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st)
{
    static const char *const outk[] = {"(w*c, w)", "(c, alpha)"};
    const spr_pass_state *s = &d->state;
    spr_result r = pass_on(b, spr_backend_draw(tr(b)->w.inner, target, d, st));
    FILE *f = tr(b)->out;
    fprintf(f, "draw t%d: %zu splats", target, d->indices ? d->count : d->cloud->n);
    if (d->radius_scale > 0.0f) fprintf(f, " (radii x%.9g)", d->radius_scale);
    fprintf(f, ", kernel %s, output %s, ", spr_kernel_name(s->kernel), outk[s->output]);
    print_state(f, s);
    fprintf(f, ", lowres d_min %.9g d_max %.9g n %.9g%s", s->lowres.d_min, s->lowres.d_max, s->lowres.n,
            s->cull_backfaces ? ", back faces culled" : "");
    if (d->alpha > 0.0f) fprintf(f, ", every opacity %.9g", d->alpha);
    if (d->depth_mask) fprintf(f, ", masked by t%d", d->mask_target);
    print_result(tr(b), r, st);
    return r;
}

static spr_result t_draw_rects(spr_backend *b, int target, const spr_rect_draw_desc *d, spr_draw_stats *st)
{
    static const char *const outk[SPR_ROUT__COUNT] = {"(alpha*c, alpha)", "(c, 1)", "(0, 0, 0, 1)", "(alpha, alpha, alpha, 0)"};
    static const char *const smp[SPR_SAMPLE__COUNT] = {"nearest", "linear", "hardware"};
    spr_result r = pass_on(b, spr_backend_draw_rects(tr(b)->w.inner, target, d, st));
    FILE *f = tr(b)->out;
    fprintf(f, "draw_rects t%d: %zu rectangles, sampling %s, alpha >= %.9g, ", target, d->indices ? d->count : d->rects->n, smp[d->sampling],
            d->alpha_ref);
    if (d->list) fprintf(f, "into the fragment lists");
    else fprintf(f, "output %s, ", outk[d->output]), print_state(f, &d->state);
    print_result(tr(b), r, st);
    return r;
}

static spr_result t_composite(spr_backend *b, const spr_composite_desc *c)
{
    FILE *f = tr(b)->out;
    fprintf(f, "composite %s of", spr_composite_info_of(c->op)->name);
    for (int k = 0; k < c->n_inputs; k++) fprintf(f, " t%d", c->inputs[k]);
    fprintf(f, " -> t%d, eps_t %.9g, background (%.9g, %.9g, %.9g)\n", c->output, c->eps_t, c->background[0], c->background[1],
            c->background[2]);
    return pass_on(b, spr_backend_composite(tr(b)->w.inner, c));
}

static spr_result t_gauss_preprocess(spr_backend *b, const spr_gauss_desc *d, float *rec)
{
    spr_result r = pass_on(b, spr_backend_gauss_preprocess(tr(b)->w.inner, d, rec));
    size_t kept = 0;
    for (size_t i = 0; !r && i < d->n; i++) kept += rec[i * SPR_GREC_FLOATS + SPR_GREC_CULL] == SPR_GCULL_NONE;
    fprintf(tr(b)->out, "gauss_preprocess %zu Gaussians, %s, %gx%g, fx %.9g fy %.9g, near %.9g", d->n,
            d->prm[SPR_GPRM_MODE] == SPR_GMODE_2D ? "2D surfels" : "3D", d->prm[SPR_GPRM_W], d->prm[SPR_GPRM_H], d->prm[SPR_GPRM_FX],
            d->prm[SPR_GPRM_FY], d->prm[SPR_GPRM_NEAR]);
    if (!r) fprintf(tr(b)->out, " -> %zu kept\n", kept);
    else fprintf(tr(b)->out, " -> failed: %s\n", b->err.msg);
    return r;
}

static spr_result t_gauss_raster(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st)
{
    spr_result r = pass_on(b, spr_backend_gauss_raster(tr(b)->w.inner, target, d, st));
    const size_t tiles = (size_t)d->prm[SPR_GPRM_GX] * (size_t)d->prm[SPR_GPRM_GY];
    fprintf(tr(b)->out, "gauss_raster t%d: %zu tiles, %u list entries, alpha cap %.9g, stop below T %.9g%s, background (%.9g, %.9g, %.9g)", target,
            tiles, d->range[tiles], d->prm[SPR_GPRM_CAP], d->prm[SPR_GPRM_T_MIN], d->prm[SPR_GPRM_STOP_LE] != 0.0f ? " (and at it)" : "",
            d->background[0], d->background[1], d->background[2]);
    print_result(tr(b), r, st);
    return r;
}

static spr_result t_gauss_draw(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st)
{
    spr_result r = pass_on(b, spr_backend_gauss_draw(tr(b)->w.inner, target, d, st));
    fprintf(tr(b)->out, "gauss_draw t%d: %zu ellipses farthest first, ", target, d->count);
    print_state(tr(b)->out, &d->state);
    print_result(tr(b), r, st);
    return r;
}

static spr_result t_read(spr_backend *b, int target, spr_plane p, void *out)
{
    fprintf(tr(b)->out, "read t%d %s\n", target, spr_plane_name(p));
    return pass_on(b, spr_backend_read_plane(tr(b)->w.inner, target, p, out));
}

static void t_destroy(spr_backend *b)
{
    spr__wrap_release(&tr(b)->w);
    free(b);
}

spr_backend *spr_trace_create(spr_backend *inner, FILE *out, spr_error *err)
{
    trace_backend *t = calloc(1, sizeof *t);
    if (!t) {
        spr__fail(err, SPR_E_NOMEM, "trace: out of memory");
        return NULL;
    }
    spr__wrap_init(&t->w, inner, t_destroy);
    t->out = out;
    spr_backend *b = &t->w.base;
    b->set_view = t_set_view;
    b->target_create = t_target_create;
    b->target_destroy = t_target_destroy;
    b->clear = t_clear;
    b->draw_splats = t_draw;
    b->draw_rects = t_draw_rects;
    b->composite = t_composite;
    b->gauss_preprocess = t_gauss_preprocess;
    b->gauss_raster = t_gauss_raster;
    b->gauss_draw = t_gauss_draw;
    b->read_plane = t_read;
    return b;
}
