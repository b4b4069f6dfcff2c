/* backend.c — argument validation in front of every backend (STYLE 4). */
#include "spr_backend.h"

#include <stdlib.h>
#include <math.h>
#include <string.h>

static const spr_plane_info plane_table[SPR_PLANE__COUNT] = {
#define SPR__PLANE_ROW(e, name, ch, type, clear) {name, ch, type, clear},
    SPR_PLANE_LIST(SPR__PLANE_ROW)
#undef SPR__PLANE_ROW
};

static const spr_composite_info composite_table[SPR_COMP__COUNT] = {
#define SPR__COMP_ROW(e, fn, max_in, reads, writes, summary) {#fn, max_in, reads, writes, summary},
    SPR_COMPOSITE_LIST(SPR__COMP_ROW)
#undef SPR__COMP_ROW
};

const spr_plane_info *spr_plane_info_of(spr_plane p) { return (unsigned)p < SPR_PLANE__COUNT ? &plane_table[p] : NULL; }
int spr_plane_channels(spr_plane p) { return (unsigned)p < SPR_PLANE__COUNT ? plane_table[p].channels : 0; }
const char *spr_plane_name(spr_plane p) { return (unsigned)p < SPR_PLANE__COUNT ? plane_table[p].name : "?"; }
const spr_composite_info *spr_composite_info_of(spr_composite_op op)
{
    return (unsigned)op < SPR_COMP__COUNT ? &composite_table[op] : NULL;
}

void spr_pass_state_defaults(spr_pass_state *s)
{
    memset(s, 0, sizeof *s);
    s->blend = s->blend_alpha = SPR_BLEND_REPLACE;
    s->write_mask = SPR_WRITE_ALL;
    s->lowres.n = 1.0f;
    s->lowres.inv_n = 1.0f;
    s->lowres.d_max = 1.0f;
}

void spr_pass_state_blend(spr_pass_state *s, spr_blend b) { s->blend = s->blend_alpha = b; }

static int live(const spr_backend *b, int t)
{
    return t >= 0 && t < b->n_targets && b->target_planes[t] != 0;
}

static spr_result bad(spr_backend *b, const char *fmt, int v)
{
    return spr__fail(&b->err, SPR_E_ARG, fmt, v);
}

unsigned spr_backend_target_planes(const spr_backend *b, int t) { return live(b, t) ? b->target_planes[t] : 0u; }

static int has(const spr_backend *b, int t, spr_plane p) { return (b->target_planes[t] & SPR_PLANE_BIT(p)) != 0; }

spr_result spr__backend_add_target(spr_backend *b, unsigned planes, int *out_target, void **slots, int *cap,
                                   size_t slot_size)
{
    int t = 0;
    while (t < b->n_targets && b->target_planes[t]) t++;
    if (t == b->n_targets) {
        unsigned *np = realloc(b->target_planes, ((size_t)b->n_targets + 1) * sizeof *np);
        if (!np) return spr__fail(&b->err, SPR_E_NOMEM, "%s: out of memory for a target", b->name);
        b->target_planes = np;
        b->target_planes[b->n_targets++] = 0;
    }
    if (t >= *cap) {
        int ncap = *cap ? 2 * *cap : 8;
        char *ns = realloc(*slots, (size_t)ncap * slot_size);
        if (!ns) return spr__fail(&b->err, SPR_E_NOMEM, "%s: out of memory for a target", b->name);
        memset(ns + (size_t)*cap * slot_size, 0, (size_t)(ncap - *cap) * slot_size);
        *slots = ns;
        *cap = ncap;
    }
    b->target_planes[t] = planes;
    *out_target = t;
    return SPR_OK;
}

spr_result spr_backend_set_view(spr_backend *b, const spr_view *v)
{
    if (v->width < 1 || v->height < 1 || v->width > SPR_MAX_IMAGE_SIDE || v->height > SPR_MAX_IMAGE_SIDE)
        return bad(b, "view: width %d outside the supported range", v->width);
    for (int t = 0; t < b->n_targets; t++)
        if (b->target_planes[t]) return bad(b, "view: cannot change the view while target %d exists", t);
    b->view = *v;
    return b->set_view(b, v);
}

spr_result spr_backend_target_create(spr_backend *b, unsigned planes, int *out_target)
{
    if (b->view.width < 1) return bad(b, "target: no view set (%d)", 0);
    if (!planes || (planes & ~SPR_PLANES_ALL)) return bad(b, "target: plane mask 0x%x names no plane or an unknown one", (int)planes);
    *out_target = -1;
    spr_result r = b->target_create(b, planes, out_target);
    if (r && *out_target >= 0 && *out_target < b->n_targets) { /* the slot taken is free again */
        b->target_planes[*out_target] = 0;
        *out_target = -1;
    }
    return r;
}

void spr_backend_target_destroy(spr_backend *b, int target)
{
    if (live(b, target)) {
        b->target_destroy(b, target);
        b->target_planes[target] = 0;
    }
}

spr_result spr_backend_clear(spr_backend *b, int target, const float color[4])
{
    if (!live(b, target)) return bad(b, "clear: no target %d", target);
    return b->clear(b, target, color);
}

/* The blends that weigh by the source's alpha (`over`, plain or premultiplied). */
static int blends_by_alpha(spr_blend m) { return m == SPR_BLEND_OVER || m == SPR_BLEND_PREMUL; }

spr_result spr_backend_draw(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st)
{
    if (!live(b, target)) return bad(b, "draw: no target %d", target);
    if (!d->cloud) return bad(b, "draw: no cloud (%d)", 0);
    const spr_pass_state *s = &d->state;
    if ((unsigned)s->kernel >= SPR_KERNEL__COUNT) return bad(b, "draw: kernel %d unknown", (int)s->kernel);
    if ((unsigned)s->depth_value >= SPR_DEPTH__COUNT) return bad(b, "draw: depth value %d unknown", (int)s->depth_value);
    if ((unsigned)s->depth_func >= SPR_FUNC__COUNT) return bad(b, "draw: depth func %d unknown", (int)s->depth_func);
    if ((unsigned)s->blend >= SPR_BLEND__COUNT) return bad(b, "draw: blend %d unknown", (int)s->blend);
    if ((unsigned)s->blend_alpha >= SPR_BLEND__COUNT) return bad(b, "draw: alpha blend %d unknown", (int)s->blend_alpha);
    if (!has(b, target, SPR_PLANE_TEST)) return bad(b, "draw: target %d has no test plane", target);
    if ((s->write_mask & SPR_WRITE_OPACITY) && blends_by_alpha(s->blend_alpha))
        return bad(b, "draw: the opacity plane is replaced or added, not blended `over` (%d)", 0);
    if ((s->write_mask & SPR_WRITE_NORMAL) && (blends_by_alpha(s->blend) || s->output != SPR_OUT_WEIGHTED))
        return bad(b, "draw: the normal plane takes weighted output, replaced or added (%d)", 0);
    for (int p = 0; p < SPR_PLANE__COUNT; p++)
        if ((s->write_mask & SPR_PLANE_BIT(p)) && p != SPR_PLANE_TEST && !has(b, target, (spr_plane)p))
            return spr__fail(&b->err, SPR_E_ARG, "draw: writes plane %s, which target %d does not have", spr_plane_name((spr_plane)p), target);
    if (d->depth_mask) {
        if (!live(b, d->mask_target)) return bad(b, "draw: no mask target %d", d->mask_target);
        if (d->mask_target == target) return bad(b, "draw: target %d cannot mask itself", target);
        if (!has(b, d->mask_target, SPR_PLANE_DEPTH)) return bad(b, "draw: mask target %d has no depth plane", d->mask_target);
    }
    if ((unsigned)s->output >= SPR_OUT__COUNT) return bad(b, "draw: output %d unknown", (int)s->output);
    if ((s->depth_value == SPR_DEPTH_LOWRES || s->depth_value == SPR_DEPTH_VORONOI) &&
        !(s->lowres.d_max > s->lowres.d_min && s->lowres.n >= 1.0f))
        return bad(b, "draw: low-precision depth needs d_max > d_min and n >= 1 (%d)", 0);
    size_t count = d->indices ? d->count : d->cloud->n;
    if (d->indices)
        for (size_t i = 0; i < count; i++)
            if (d->indices[i] >= d->cloud->n) return bad(b, "draw: index %d beyond the cloud", (int)d->indices[i]);
    spr_draw_stats dummy;
    memset(st ? st : &dummy, 0, sizeof dummy);
    return b->draw_splats(b, target, d, st ? st : &dummy);
}

spr_result spr_backend_draw_rects(spr_backend *b, int target, const spr_rect_draw_desc *d, spr_draw_stats *st)
{
    if (!live(b, target)) return bad(b, "rects: no target %d", target);
    if (!b->draw_rects) return spr__fail(&b->err, SPR_E_BACKEND, "rects: backend %s draws no rectangles", b->name);
    const spr_rects *r = d->rects;
    if (!r || (r->n && (!r->f || !r->i || !r->texels || !r->nbr))) return bad(b, "rects: no rectangles (%d)", 0);
    const spr_pass_state *s = &d->state;
    if ((unsigned)d->output >= SPR_ROUT__COUNT) return bad(b, "rects: output %d unknown", (int)d->output);
    if ((unsigned)d->sampling >= SPR_SAMPLE__COUNT) return bad(b, "rects: sampling %d unknown", (int)d->sampling);
    if (!(d->alpha_ref >= 0.0f && d->alpha_ref <= 1.0f)) return bad(b, "rects: alpha reference outside [0, 1] (%d)", 0);
    if (s->depth_value != SPR_DEPTH_PLAIN && s->depth_value != SPR_DEPTH_EPS_OFFSET)
        return bad(b, "rects: test value %d is not plain or eps-offset", (int)s->depth_value);
    if ((unsigned)s->depth_func >= SPR_FUNC__COUNT) return bad(b, "rects: depth func %d unknown", (int)s->depth_func);
    if ((unsigned)s->blend >= SPR_BLEND__COUNT || (unsigned)s->blend_alpha >= SPR_BLEND__COUNT || blends_by_alpha(s->blend) ||
        blends_by_alpha(s->blend_alpha))
        return bad(b, "rects: blends are replace, add or sub (%d)", 0);
    if (s->write_mask & ~(unsigned)(SPR_WRITE_COLOR | SPR_WRITE_DEPTH | SPR_WRITE_ID | SPR_WRITE_COUNT))
        return bad(b, "rects: write mask 0x%x: colour, depth, id and count only", (int)s->write_mask);
    if (!has(b, target, SPR_PLANE_TEST)) return bad(b, "rects: target %d has no test plane", target);
    for (int p = 0; p < SPR_PLANE__COUNT; p++)
        if (!d->list && (s->write_mask & SPR_PLANE_BIT(p)) && !has(b, target, (spr_plane)p))
            return spr__fail(&b->err, SPR_E_ARG, "rects: writes plane %s, which target %d does not have", spr_plane_name((spr_plane)p), target);
    const size_t count = d->indices ? d->count : r->n;
    for (size_t i = 0; i < count; i++) { /* the drawn rectangles: in the set, their texels too */
        const size_t k = d->indices ? d->indices[i] : i;
        if (k >= r->n) return bad(b, "rects: index %d beyond the set", (int)k);
        const uint32_t *I = r->i + k * SPR_RECTI_COUNT;
        if (I[SPR_RECTI_TW] < 1 || I[SPR_RECTI_TH] < 1 ||
            (uint64_t)I[SPR_RECTI_OFF] + (uint64_t)I[SPR_RECTI_TW] * I[SPR_RECTI_TH] > (uint64_t)r->n_texels)
            return bad(b, "rects: rectangle %d's texture lies outside the texels", (int)k);
    }
    if (r->n_texels >= (size_t)1 << 31) return bad(b, "rects: %d-bit texel count too large", 31);
    spr_draw_stats dummy;
    memset(st ? st : &dummy, 0, sizeof dummy);
    return b->draw_rects(b, target, d, st ? st : &dummy);
}

static uint64_t rects_serial;

spr_result spr_rects_alloc(spr_rects *r, size_t n, size_t n_texels, spr_error *err)
{
    memset(r, 0, sizeof *r);
    const size_t words = spr_rects_words(n);
    r->n = n;
    r->n_texels = n_texels;
    r->f = calloc(n ? n * SPR_RECT_FLOATS : 1, sizeof(float));
    r->i = calloc(n ? n * SPR_RECTI_COUNT : 1, sizeof(uint32_t));
    r->texels = calloc(n_texels ? n_texels * 4 : 1, sizeof(float));
    r->nbr = calloc(n ? n * words : 1, sizeof(uint32_t));
#pragma omp atomic capture
    r->serial = ++rects_serial;
    if (!r->f || !r->i || !r->texels || !r->nbr) {
        spr_rects_free(r);
        return spr__fail(err, SPR_E_NOMEM, "rectangles: out of memory for %zu rectangles and %zu texels", n, n_texels);
    }
    return SPR_OK;
}

void spr_rects_free(spr_rects *r)
{
    free(r->f);
    free(r->i);
    free(r->texels);
    free(r->nbr);
    memset(r, 0, sizeof *r);
}

spr_result spr_rects_atlas(const spr_rects *r, int max_w, float **img, int *w, int *h, int32_t *org, spr_error *err)
{
    int W = 1, H = 0, x = 0, rowh = 0;
    for (size_t k = 0; k < r->n; k++) { /* shelves: blocks left to right, a new row when one is full */
        const int bw = (int)r->i[k * SPR_RECTI_COUNT + SPR_RECTI_TW] + 2, bh = (int)r->i[k * SPR_RECTI_COUNT + SPR_RECTI_TH] + 2;
        if (x > 0 && x + bw > max_w) H += rowh, x = 0, rowh = 0;
        org[2 * k] = x;
        org[2 * k + 1] = H;
        x += bw;
        if (x > W) W = x;
        if (bh > rowh) rowh = bh;
    }
    H += rowh;
    if (H < 1) H = 1;
    if (!(*img = calloc((size_t)W * H * 4, sizeof **img))) return spr__fail(err, SPR_E_NOMEM, "rectangles: out of memory for a %dx%d atlas", W, H);
    for (size_t k = 0; k < r->n; k++) {
        const uint32_t *I = r->i + k * SPR_RECTI_COUNT;
        const int tw = (int)I[SPR_RECTI_TW], th = (int)I[SPR_RECTI_TH];
        for (int y = -1; y <= th; y++)
            for (int xx = -1; xx <= tw; xx++) {
                const int sx = xx < 0 ? 0 : xx >= tw ? tw - 1 : xx, sy = y < 0 ? 0 : y >= th ? th - 1 : y;
                memcpy(*img + 4 * ((size_t)(org[2 * k + 1] + 1 + y) * W + (size_t)(org[2 * k] + 1 + xx)),
                       r->texels + 4 * ((size_t)I[SPR_RECTI_OFF] + (size_t)sy * tw + sx), 4 * sizeof(float));
            }
    }
    *w = W;
    *h = H;
    return SPR_OK;
}

unsigned spr_composite_extra_reads(spr_composite_op op, const float *params, int input)
{
    if (!params || (params[SPR_PRM_SHADE] == 0.0f && params[SPR_PRM_ENV] == 0.0f)) return 0;
    switch (op) {
    case SPR_COMP_NORMALIZE:
    case SPR_COMP_DEFERRED:
    case SPR_COMP_NEAREST: return SPR_PLANE_BIT(SPR_PLANE_NORMAL);
    case SPR_COMP_TRANSPARENT2: return input == 0 ? SPR_PLANE_BIT(SPR_PLANE_NORMAL) : 0;
    default: return 0;
    }
}

spr_result spr_backend_composite(spr_backend *b, const spr_composite_desc *c)
{
    if ((unsigned)c->op >= SPR_COMP__COUNT) return bad(b, "composite: op %d unknown", (int)c->op);
    if (c->n_inputs < 1 || c->n_inputs > SPR_MAX_COMPOSITE_INPUTS)
        return bad(b, "composite: %d inputs", c->n_inputs);
    const spr_composite_info *ci = spr_composite_info_of(c->op);
    if (c->n_inputs > ci->max_inputs)
        return spr__fail(&b->err, SPR_E_ARG, "composite: %s takes at most %d input(s), got %d", ci->name, ci->max_inputs, c->n_inputs);
    if (c->params) {
        const float *q = c->params;
        if (!(q[SPR_PRM_SHADE] == 0.0f || q[SPR_PRM_SHADE] == 1.0f) || !(q[SPR_PRM_ENV] == 0.0f || q[SPR_PRM_ENV] == 1.0f))
            return bad(b, "composite: shading parameters out of range (%d)", 0);
        if (!(q[SPR_PRM_EXP] >= 1.0f && q[SPR_PRM_EXP] <= 1024.0f) || q[SPR_PRM_EXP] != floorf(q[SPR_PRM_EXP]))
            return bad(b, "composite: specular exponent must be an integer in 1..1024 (%d)", 0);
        if (q[SPR_PRM_ENV] != 0.0f) {
            if (!c->env || !c->env->texels || c->env->size < 1 || (float)c->env->size != q[SPR_PRM_ENV_SIZE])
                return bad(b, "composite: environment effects need a cube map of the given size (%d)", 0);
            if (!(q[SPR_PRM_ALPHA] > 0.0f && q[SPR_PRM_ALPHA] <= 1.0f))
                return bad(b, "composite: material opacity must lie in (0, 1] (%d)", 0);
        }
    }
    for (int i = 0; i < c->n_inputs; i++) {
        if (!live(b, c->inputs[i])) return bad(b, "composite: no input target %d", c->inputs[i]);
        if (c->inputs[i] == c->output) return bad(b, "composite: target %d is both input and output", c->output);
        unsigned reads = ci->reads | spr_composite_extra_reads(c->op, c->params, i);
        if ((b->target_planes[c->inputs[i]] & reads) != reads)
            return spr__fail(&b->err, SPR_E_ARG, "composite: %s reads planes input target %d lacks", ci->name, c->inputs[i]);
    }
    if (c->op == SPR_COMP_PREFIX && (!c->rects || !c->rects->nbr))
        return bad(b, "composite: prefix needs the rectangles the lists came from (%d)", 0);
    if (!live(b, c->output)) return bad(b, "composite: no output target %d", c->output);
    if ((b->target_planes[c->output] & ci->writes) != ci->writes)
        return spr__fail(&b->err, SPR_E_ARG, "composite: %s writes planes output target %d lacks", ci->name, c->output);
    return b->composite(b, c);
}

/* A Gaussian frame's parameters fit the view (SPEC §10). */
static spr_result gauss_prm_check(spr_backend *b, const char *what, const float *g)
{
    const int W = b->view.width, H = b->view.height;
    if (g[SPR_GPRM_W] != (float)W || g[SPR_GPRM_H] != (float)H)
        return spr__fail(&b->err, SPR_E_ARG, "%s: parameters for %gx%g, the view is %dx%d", what, g[SPR_GPRM_W], g[SPR_GPRM_H], W, H);
    if (g[SPR_GPRM_GX] != (float)((W + 15) / 16) || g[SPR_GPRM_GY] != (float)((H + 15) / 16))
        return spr__fail(&b->err, SPR_E_ARG, "%s: a tile grid of %gx%g is not ceil(W/16) x ceil(H/16)", what, g[SPR_GPRM_GX], g[SPR_GPRM_GY]);
    if (g[SPR_GPRM_MODE] != SPR_GMODE_3D && g[SPR_GPRM_MODE] != SPR_GMODE_2D) return spr__fail(&b->err, SPR_E_ARG, "%s: mode %g unknown", what, g[SPR_GPRM_MODE]);
    for (int i = 0; i < SPR_GPRM_COUNT; i++)
        if (!isfinite(g[i])) return spr__fail(&b->err, SPR_E_ARG, "%s: parameter %d is not finite", what, i);
    if (!(g[SPR_GPRM_FX] > 0.0f) || !(g[SPR_GPRM_FY] > 0.0f)) return spr__fail(&b->err, SPR_E_ARG, "%s: focal lengths must be positive", what);
    return SPR_OK;
}

spr_result spr_backend_gauss_preprocess(spr_backend *b, const spr_gauss_desc *d, float *rec)
{
    if (!b->gauss_preprocess) return spr__fail(&b->err, SPR_E_BACKEND, "gauss: backend %s has no Gaussian rasterizer", b->name);
    if (b->view.width < 1) return bad(b, "gauss: no view set (%d)", 0);
    if (d->n && (!d->mu || !d->q || !d->s || !d->opacity || !d->color || !rec)) return bad(b, "gauss: preprocessing without its arrays (%d)", 0);
    spr_result r = gauss_prm_check(b, "gauss preprocess", d->prm);
    return r ? r : b->gauss_preprocess(b, d, rec);
}

spr_result spr_backend_gauss_raster(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st)
{
    if (!b->gauss_raster) return spr__fail(&b->err, SPR_E_BACKEND, "gauss: backend %s has no Gaussian rasterizer", b->name);
    if (!live(b, target)) return bad(b, "gauss raster: no target %d", target);
    if (!has(b, target, SPR_PLANE_COLOR)) return bad(b, "gauss raster: target %d has no colour plane", target);
    spr_result r = gauss_prm_check(b, "gauss raster", d->prm);
    if (r) return r;
    const size_t tiles = (size_t)d->prm[SPR_GPRM_GX] * (size_t)d->prm[SPR_GPRM_GY];
    if (!d->range || (d->range[tiles] && (!d->list || !d->rec)) || d->range[0] != 0) return bad(b, "gauss raster: no tile lists (%d)", 0);
    for (size_t t = 0; t < tiles; t++)
        if (d->range[t + 1] < d->range[t]) return bad(b, "gauss raster: tile %d's range runs backwards", (int)t);
    for (uint32_t e = 0; e < d->range[tiles]; e++)
        if (d->list[e] >= d->n) return bad(b, "gauss raster: list entry names Gaussian %d beyond the records", (int)d->list[e]);
    spr_draw_stats dummy;
    memset(st ? st : &dummy, 0, sizeof dummy);
    return b->gauss_raster(b, target, d, st ? st : &dummy);
}

spr_result spr_backend_gauss_draw(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st)
{
    if (!b->gauss_draw) return spr__fail(&b->err, SPR_E_BACKEND, "gauss: backend %s has no Gaussian rasterizer", b->name);
    if (!live(b, target)) return bad(b, "gauss draw: no target %d", target);
    const spr_pass_state *s = &d->state;
    if ((unsigned)s->blend >= SPR_BLEND__COUNT || (unsigned)s->blend_alpha >= SPR_BLEND__COUNT) return bad(b, "gauss draw: blend %d unknown", (int)s->blend);
    if ((s->write_mask & ~SPR_WRITE_COLOR) || !has(b, target, SPR_PLANE_COLOR)) return bad(b, "gauss draw: writes the colour plane alone (%d)", 0);
    spr_result r = gauss_prm_check(b, "gauss draw", d->prm);
    if (r) return r;
    if (d->count && (!d->order || !d->rec)) return bad(b, "gauss draw: no order (%d)", 0);
    for (size_t i = 0; i < d->count; i++)
        if (d->order[i] >= d->n) return bad(b, "gauss draw: order names Gaussian %d beyond the records", (int)d->order[i]);
    spr_draw_stats dummy;
    memset(st ? st : &dummy, 0, sizeof dummy);
    return b->gauss_draw(b, target, d, st ? st : &dummy);
}

int spr_gauss_bwd_batch_end(const uint32_t *range, int nt, int t0, size_t cap)
{
    int t1 = t0 + 1;
    while (t1 < nt && range[t1 + 1] - range[t0] <= cap) t1++;
    return t1;
}

size_t spr_gauss_bwd_batch_most(const uint32_t *range, int nt, size_t cap)
{
    size_t most = 0;
    for (int t0 = 0, t1; t0 < nt; t0 = t1) {
        t1 = spr_gauss_bwd_batch_end(range, nt, t0, cap);
        if (range[t1] - range[t0] > most) most = range[t1] - range[t0];
    }
    return most;
}

spr_result spr_gauss_bwd_over(spr_error *err, const char *who, int gx, int tile, int p)
{
    const int i = (tile % gx) * 16 + p % 16, j = (tile / gx) * 16 + p / 16;
    return spr__fail(err, SPR_E_TOO_LARGE,
                     "%s: gauss backward: pixel (%d, %d) from the top left blends more than %d Gaussians, more than the backward holds "
                     "(a profile that skips alpha below 1/255 and stops below T = 1e-4 blends at most 2,345)",
                     who, i, j, SPR_GBWD_HOLD);
}

spr_result spr_backend_gauss_backward(spr_backend *b, const spr_gauss_bwd_desc *d, float *sums, float *out)
{
    if (!b->gauss_backward) return spr__fail(&b->err, SPR_E_BACKEND, "gauss: backend %s has no backward pass", b->name);
    spr_result r = gauss_prm_check(b, "gauss backward", d->prm);
    if (r) return r;
    if (d->prm[SPR_GPRM_MODE] != SPR_GMODE_3D) return bad(b, "gauss backward: gauss3d only (mode %d)", (int)d->prm[SPR_GPRM_MODE]);
    const size_t tiles = (size_t)d->prm[SPR_GPRM_GX] * (size_t)d->prm[SPR_GPRM_GY], entries = d->range ? d->range[tiles] : 0;
    if (!d->range || d->range[0] != 0 || (entries && (!d->list || !d->rec)) || !d->up || !d->csr_start || (entries && !d->csr))
        return bad(b, "gauss backward: no tile lists or upstream gradient (%d)", 0);
    if (d->n && (!d->mu || !d->q || !d->s || !sums || !out)) return bad(b, "gauss backward: without its arrays (%d)", 0);
    for (size_t t = 0; t < tiles; t++)
        if (d->range[t + 1] < d->range[t]) return bad(b, "gauss backward: tile %d's range runs backwards", (int)t);
    for (uint32_t e = 0; e < entries; e++)
        if (d->list[e] >= d->n) return bad(b, "gauss backward: list entry names Gaussian %d beyond the records", (int)d->list[e]);
    if (d->csr_start[0] != 0 || d->csr_start[d->n] != entries) return bad(b, "gauss backward: the entries of the Gaussians are not the list's (%d)", 0);
    for (size_t G = 0; G < d->n; G++)
        for (uint32_t k = d->csr_start[G]; k < d->csr_start[G + 1]; k++)
            if (k < d->csr_start[G] || d->csr[k] >= entries || d->list[d->csr[k]] != G || (k > d->csr_start[G] && d->csr[k] <= d->csr[k - 1]))
                return bad(b, "gauss backward: Gaussian %d's entries are not its own, ascending", (int)G);
    return b->gauss_backward(b, d, sums, out);
}

spr_result spr_backend_fits(spr_backend *b, const spr_fit_desc *d)
{
    return b->fits ? b->fits(b, d) : SPR_OK;
}

spr_result spr_backend_read_plane(spr_backend *b, int target, spr_plane p, void *out)
{
    if (!live(b, target)) return bad(b, "read: no target %d", target);
    if ((unsigned)p >= SPR_PLANE__COUNT) return bad(b, "read: plane %d unknown", (int)p);
    if (!has(b, target, p)) return spr__fail(&b->err, SPR_E_ARG, "read: target %d has no %s plane", target, spr_plane_name(p));
    return b->read_plane(b, target, p, out);
}

spr_result spr_backend_read_plane_f(spr_backend *b, int target, spr_plane p, float *out)
{
    spr_result r = spr_backend_read_plane(b, target, p, out);
    const spr_plane_type type = r ? SPR_PLANE_F32 : spr_plane_info_of(p)->type;
    if (spr_plane_type_uint(type)) {
        const size_t n = (size_t)b->view.width * b->view.height;
        for (size_t i = 0; i < n; i++) {
            uint32_t u;
            memcpy(&u, &out[i], 4);
            out[i] = u == UINT32_MAX ? -1.0f : (float)u; /* exact below 2^24 */
        }
    }
    return r;
}

void spr_backend_destroy(spr_backend *b)
{
    if (!b) return;
    for (int t = 0; t < b->n_targets; t++)
        if (b->target_planes[t]) b->target_destroy(b, t);
    free(b->target_planes);
    b->target_planes = NULL;
    b->n_targets = 0;
    b->destroy(b);
}
