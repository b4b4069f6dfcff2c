/* algo.c — the algorithm runner: shared parameters, pass bookkeeping, hooks. */
#include "spr_util.h"
#include "spr_algo.h"

#include <math.h>
#include <stdio.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static spr_result record_ex(spr__run *run, const char *name, int group, const spr_pass_state *state, int target,
                            const spr_draw_stats *st, double ms, const float *records, size_t n_records)
{
    spr_render_result *o = run->out;
    if (o->n_passes == run->pass_cap) {
        int cap = run->pass_cap ? 2 * run->pass_cap : 8;
        spr_pass_record *np = realloc(o->passes, (size_t)cap * sizeof *np);
        if (!np) return spr__fail(run->err, SPR_E_NOMEM, "render: out of memory");
        o->passes = np;
        run->pass_cap = cap;
    }
    spr_pass_record *rec = &o->passes[o->n_passes];
    snprintf(rec->name, sizeof rec->name, "%s", name);
    rec->group = group;
    rec->stats = *st;
    rec->ms = ms;
    if (run->desc->hook) {
        spr_pass_info info = {o->n_passes, name, group, state, target, *st, ms, records, n_records};
        run->desc->hook(run->desc->hook_user, run->b, &info);
    }
    if (run->desc->progress.fn) {
        char phase[96];
        if (group >= 0) snprintf(phase, sizeof phase, "frame: pass %d done (%s k%d)", o->n_passes, name, group);
        else snprintf(phase, sizeof phase, "frame: pass %d done (%s)", o->n_passes, name);
        spr_progress_report(&run->desc->progress, phase, 0, 1);
    }
    o->n_passes++;
    return SPR_OK;
}

static spr_result record(spr__run *run, const char *name, int group, const spr_pass_state *state, int target,
                         const spr_draw_stats *st, double ms)
{
    return record_ex(run, name, group, state, target, st, ms, NULL, 0);
}

static spr_result backend_failed(spr__run *run, spr_result r)
{
    return spr__fail(run->err, r, "%s backend: %s", run->b->name, run->b->err.msg);
}

/* The part of draw d within chunk [first, first + m) of a streamed cloud as
 * a draw of that chunk (c): its splats in their order, ids and submission
 * positions placed in the whole; *at: the next position in d->indices
 * (the draw's indices must follow the file).  0: nothing of d in the chunk. */
static int chunk_slice(spr__run *run, const spr_draw_desc *d, size_t first, size_t m, size_t *at, uint32_t *local, spr_draw_desc *c,
                       spr_result *r)
{
    *c = *d;
    c->cloud = &run->chunk;
    c->id_base = (uint32_t)first;
    *r = SPR_OK;
    if (!d->indices) {
        c->seq_base = (uint32_t)first;
        return 1;
    }
    size_t end = *at;
    for (; end < d->count && d->indices[end] < first + m; end++) {
        if (d->indices[end] < first || (end > *at && d->indices[end] <= d->indices[end - 1])) {
            *r = spr__fail(run->err, SPR_E_ARG, "%s: --stream draws splats in file order; this draw is not", spr_algo_name(run->desc->algo));
            return 0;
        }
        local[end - *at] = d->indices[end] - (uint32_t)first;
    }
    c->indices = local;
    c->count = end - *at;
    c->seq_base = (uint32_t)*at;
    *at = end;
    return c->count > 0;
}

/* n draws of a streamed cloud, each into its own target: the file is read
 * once, chunk by chunk, and each chunk drawn by every draw that has splats
 * in it, so every pixel of every target sees the same fragments in the same
 * order as the whole draws (a target is written by its draw alone).  The
 * passes are recorded after the last chunk, in draw order. */
static spr_result stream_draws(spr__run *run, const char *name, const int *group, const int *target, const spr_draw_desc *d, int n)
{
    const spr_cloud_source *src = run->desc->source;
    spr_draw_stats *st = calloc((size_t)n, sizeof *st);
    size_t *at = calloc((size_t)n, sizeof *at);
    double *ms = calloc((size_t)n, sizeof *ms);
    spr_result r = st && at && ms ? SPR_OK : spr__fail(run->err, SPR_E_NOMEM, "%s: out of memory", spr_algo_name(run->desc->algo));
    for (size_t first = 0; first < src->n && !r; first += src->chunk) {
        const size_t m = src->n - first < src->chunk ? src->n - first : src->chunk;
        int read = 0;
        for (int k = 0; k < n && !r; k++) {
            spr_draw_desc c;
            if (!chunk_slice(run, &d[k], first, m, &at[k], run->local, &c, &r)) continue;
            double t0 = spr_now_ms();
            if (!read && (r = src->read(src->user, first, m, &run->chunk, run->err))) break;
            read = 1;
            spr_draw_stats cs;
            if ((r = spr_backend_draw(run->b, target[k], &c, &cs))) { r = backend_failed(run, r); break; }
            st[k].splats += cs.splats;
            st[k].generated += cs.generated;
            st[k].passed += cs.passed;
            ms[k] += spr_now_ms() - t0;
        }
        spr_progress_report(&run->desc->progress, "frame: drawing", first + m, src->n);
    }
    for (int k = 0; k < n && !r; k++) {
        if (d[k].indices && at[k] != d[k].count)
            r = spr__fail(run->err, SPR_E_ARG, "%s: --stream: a draw names splats beyond the cloud", spr_algo_name(run->desc->algo));
        else
            r = record(run, name, group[k], &d[k].state, target[k], &st[k], ms[k]);
    }
    free(st);
    free(at);
    free(ms);
    return r;
}

spr_result spr__run_draws(spr__run *run, const char *name, const int *group, const int *target, const spr_draw_desc *d, int n)
{
    if (run->desc->source) return stream_draws(run, name, group, target, d, n);
    spr_result r = SPR_OK;
    for (int k = 0; k < n && !r; k++) r = spr__run_draw(run, name, group[k], target[k], &d[k]);
    return r;
}

spr_result spr__run_draw(spr__run *run, const char *name, int group, int target, const spr_draw_desc *d)
{
    spr_draw_stats st;
    double t0 = spr_now_ms();
    if (run->desc->source) return stream_draws(run, name, &group, &target, d, 1);
    spr_result r = spr_backend_draw(run->b, target, d, &st);
    if (r) return backend_failed(run, r);
    return record(run, name, group, &d->state, target, &st, spr_now_ms() - t0);
}

spr_result spr__run_composite(spr__run *run, const char *name, const spr_composite_desc *c)
{
    spr_draw_stats st = {0, 0, 0};
    double t0 = spr_now_ms();
    spr_result r = spr_backend_composite(run->b, c);
    if (r) return backend_failed(run, r);
    return record(run, name, -1, NULL, c->output, &st, spr_now_ms() - t0);
}

spr_result spr__run_rects(spr__run *run, const char *name, int group, int target, const spr_rect_draw_desc *d)
{
    spr_draw_stats st;
    double t0 = spr_now_ms();
    spr_result r = spr_backend_draw_rects(run->b, target, d, &st);
    if (r) return backend_failed(run, r);
    return record(run, name, group, &d->state, target, &st, spr_now_ms() - t0);
}

spr_result spr__run_gauss_preprocess(spr__run *run, const spr_gauss_desc *d, float *rec)
{
    spr_draw_stats st = {d->n, 0, 0};
    double t0 = spr_now_ms();
    spr_result r = spr_backend_gauss_preprocess(run->b, d, rec);
    if (r) return backend_failed(run, r);
    for (size_t i = 0; i < d->n; i++) st.generated += rec[i * SPR_GREC_FLOATS + SPR_GREC_CULL] == SPR_GCULL_NONE;
    return record_ex(run, "preprocess", -1, NULL, -1, &st, spr_now_ms() - t0, rec, d->n);
}

spr_result spr__run_host_pass(spr__run *run, const char *name, const spr_draw_stats *st, double ms)
{
    return record(run, name, -1, NULL, -1, st, ms);
}

spr_result spr__run_gauss_raster(spr__run *run, const char *name, int target, const spr_gauss_raster_desc *d)
{
    spr_draw_stats st;
    double t0 = spr_now_ms();
    spr_result r = spr_backend_gauss_raster(run->b, target, d, &st);
    if (r) return backend_failed(run, r);
    return record(run, name, -1, NULL, target, &st, spr_now_ms() - t0);
}

spr_result spr__run_gauss_draw(spr__run *run, const char *name, int target, const spr_gauss_draw_desc *d)
{
    spr_draw_stats st;
    double t0 = spr_now_ms();
    spr_result r = spr_backend_gauss_draw(run->b, target, d, &st);
    if (r) return backend_failed(run, r);
    return record(run, name, -1, &d->state, target, &st, spr_now_ms() - t0);
}

float spr__group_radius_scale(const spr_groups *g, int k) { return g && g->radius_scale ? g->radius_scale[k] : 0.0f; }

spr_composite_desc spr__run_comp(const spr__run *run, spr_composite_op op, const int *inputs, int n, int output)
{
    const float *bg = run->desc->background;
    spr_composite_desc c = {op, inputs, n, output, run->eps_t, {bg[0], bg[1], bg[2]}, NULL, NULL, NULL};
    if (run->use_prm) {
        c.params = run->prm;
        c.env = run->desc->shade.env;
    }
    return c;
}

unsigned spr__run_normal_planes(const spr__run *run)
{
    return run->use_prm ? SPR_PLANE_BIT(SPR_PLANE_NORMAL) : 0u;
}

void spr_shading_defaults(spr_shading *s)
{
    memset(s, 0, sizeof *s);
    s->model = SPR_SHADE_NONE;
    s->light_eye[0] = -0.4;
    s->light_eye[1] = 0.5;
    s->light_eye[2] = 1.0;
    s->ka = 0.2;
    s->kd = 0.8;
    s->ks = 0.4;
    s->exponent = 32;
    s->eta[0] = 1.0 / 1.49;
    s->eta[1] = 1.0 / 1.50;
    s->eta[2] = 1.0 / 1.52;
    s->multilayer = 1;
}

/* The parameter array of SPR_PARAM_LIST from the view and desc->shade,
 * every value rounded to float once here (SPEC §4.3, §6.3). */
static spr_result make_params(spr__run *run, const spr_view *v)
{
    const spr_render_desc *desc = run->desc;
    const spr_shading *sh = &desc->shade;
    const unsigned uses = spr_algo_info_of(desc->algo)->uses;
    const int shade = (uses & SPR_USES_SHADE) && sh->model == SPR_SHADE_PHONG;
    const int env = (uses & SPR_USES_ENV) && sh->env != NULL;
    memset(run->prm, 0, sizeof run->prm);
    run->use_prm = shade || env;
    if (!run->use_prm) return SPR_OK;
    float *q = run->prm;
    for (int i = 0; i < 16; i++) q[SPR_PRM_M + i] = v->M[i];
    q[SPR_PRM_SX] = v->ndc_sx;
    q[SPR_PRM_SY] = v->ndc_sy;
    q[SPR_PRM_SHADE] = shade ? 1.0f : 0.0f;
    /* the eye-space light into world space: Vᵀ·L (V's 3×3 part is a rotation) */
    const double *L = sh->light_eye;
    double l2 = L[0] * L[0] + L[1] * L[1] + L[2] * L[2];
    if (shade && !(l2 > 0.0)) return spr__fail(run->err, SPR_E_ARG, "render: the light direction is zero");
    double w[3], wl = 0.0;
    for (int c = 0; c < 3; c++) {
        w[c] = v->V[c] * L[0] + v->V[4 + c] * L[1] + v->V[8 + c] * L[2];
        wl += w[c] * w[c];
    }
    for (int c = 0; c < 3 && wl > 0.0; c++) q[SPR_PRM_LIGHT + c] = (float)(w[c] / sqrt(wl));
    q[SPR_PRM_KA] = (float)sh->ka;
    q[SPR_PRM_KD] = (float)sh->kd;
    q[SPR_PRM_KS] = (float)sh->ks;
    q[SPR_PRM_EXP] = (float)(sh->exponent >= 1 ? sh->exponent : 1);
    if (env) {
        q[SPR_PRM_ENV] = 1.0f;
        q[SPR_PRM_ENV_SIZE] = (float)sh->env->size;
        for (int c = 0; c < 3; c++) q[SPR_PRM_ETA + c] = (float)sh->eta[c];
        q[SPR_PRM_MULTI] = sh->multilayer ? 1.0f : 0.0f;
        /* material opacity for l = round(α_total/α): --alpha, else the mean of the cloud's */
        double a = desc->alpha > 0.0f ? desc->alpha : 0.0;
        if (!(a > 0.0)) {
            for (size_t i = 0; i < run->cloud->n; i++) a += run->cloud->alpha[i];
            a = run->cloud->n ? a / (double)run->cloud->n : 1.0;
        }
        q[SPR_PRM_ALPHA] = (float)(a > 0.0 ? a : 1.0);
    }
    return SPR_OK;
}

spr_result spr__run_finish(spr__run *run, spr_composite_op op, const int *I, int K, int *final_target)
{
    spr_composite_desc c = spr__run_comp(run, op, I, K, I[K]);
    spr_result r = spr__run_composite(run, "composite", &c);
    if (r) return r;
    *final_target = I[K];
    return SPR_OK;
}

spr_result spr__run_target(spr__run *run, unsigned planes, int *target)
{
    spr_result r = spr_backend_target_create(run->b, planes, target);
    if (r) return spr__fail(run->err, r, "%s: %s", spr_algo_name(run->desc->algo), run->b->err.msg);
    return SPR_OK;
}

spr_result spr_stream_check(spr_algo algo, size_t n, spr_error *err)
{
    const spr_algo_info *ai = spr_algo_info_of(algo);
    if (ai->uses & SPR_USES_GAUSS)
        return spr__fail(err, SPR_E_ARG, "render: %s sorts every Gaussian of the frame, --stream cannot draw it: leave out --stream", ai->name);
    if (ai->uses & (SPR_USES_ORDER | SPR_USES_RECTS)) {
        char size[96] = "";
        const double mb = (double)spr_cloud_bytes(n) / 1e6;
        if (n) snprintf(size, sizeof size, " (the cloud alone takes %.0f MB for %zu splats)", mb > 1.0 ? mb : 1.0, n);
        return spr__fail(err, SPR_E_ARG, "render: %s needs the whole cloud in memory (%s), --stream cannot draw it: leave out --stream%s",
                         ai->name, (ai->uses & SPR_USES_ORDER) ? "a back-to-front order of every splat" : "domain primitives built over every point",
                         size);
    }
    return SPR_OK;
}

static spr_result render_frame(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc,
                                    spr_render_result *out, spr_error *err);

spr_result spr_render_fits(spr_backend *b, const spr_cloud *cloud, spr_algo algo, spr_error *err)
{
    const spr_algo_info *ai = spr_algo_info_of(algo);
    const spr_fit_desc fit = {cloud->n, ai && (ai->uses & SPR_USES_GAUSS)};
    const spr_result r = spr_backend_fits(b, &fit);
    return r ? spr__fail(err, r, "%s backend: %s", b->name, b->err.msg) : SPR_OK;
}

spr_result spr_render(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc,
                      spr_render_result *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    const spr_algo_info *ai = spr_algo_info_of(desc->algo);
    if (!ai) return spr__fail(err, SPR_E_ARG, "render: unknown algorithm %d", (int)desc->algo);
    if ((ai->uses & SPR_USES_RECTS) && !desc->rects)
        return spr__fail(err, SPR_E_ARG, "render: %s draws domain primitives: none given", ai->name);
    if (desc->groups && desc->groups->n_splats != cloud->n)
        return spr__fail(err, SPR_E_ARG, "render: groups are for %zu splats, the model has %zu", desc->groups->n_splats, cloud->n);
    const spr_cloud_source *src = desc->source;
    if (src && src->n != cloud->n) return spr__fail(err, SPR_E_ARG, "render: the stream has %zu splats, the cloud %zu", src->n, cloud->n);
    spr_result r;
    if (src && (r = spr_stream_check(desc->algo, cloud->n, err))) return r;
    if ((r = spr_render_fits(b, cloud, desc->algo, err))) return r;
    /* the frame's host work (view-dependent colours, orders, tile lists) on
     * the backend's host thread count: OpenMP's default for regions that do
     * not name one, restored on the way out */
    const int omp_default = omp_get_max_threads();
    if (b->host_threads > 0) omp_set_num_threads(b->host_threads);
    r = render_frame(b, view, cloud, desc, out, err);
    omp_set_num_threads(omp_default);
    return r;
}

static spr_result render_frame(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc,
                                    spr_render_result *out, spr_error *err)
{
    const spr_algo_info *ai = spr_algo_info_of(desc->algo);
    const spr_cloud_source *src = desc->source;
    spr_result r;
    spr_cloud viewed;
    float *sh_color = NULL;
    if (cloud->sh && cloud->sh_k > 1 && !(ai->uses & SPR_USES_GAUSS)) { /* view-dependent colours (--sh-degree): this view's, once per frame on the host, drawn by every backend */
        if (!(sh_color = malloc((cloud->n ? cloud->n : 1) * 3 * sizeof *sh_color)))
            return spr__fail(err, SPR_E_NOMEM, "render: out of memory for %zu view-dependent colours", cloud->n);
        double eye[3], fwd[3] = {-view->V[8], -view->V[9], -view->V[10]}; /* the camera looks down −z of eye space */
        spr_view_matrix_eye(view->V, eye);
        spr_cloud_sh_colors(cloud, eye, view->ortho ? fwd : NULL, sh_color);
        viewed = *cloud;
        viewed.color = sh_color;
        cloud = &viewed;
    }
    r = spr_backend_set_view(b, view);
    if (r) {
        free(sh_color);
        return backend_failed(&(spr__run){.b = b, .err = err}, r);
    }
    spr_bounds bd;
    if (src) bd = src->bounds;
    else spr_cloud_bounds(cloud, &bd);
    double eps = desc->eps > 0.0 ? desc->eps : spr_bounds_default_eps(&bd);
    spr__run run = {b, cloud, desc, out, err, spr_view_eps_t(view, eps), {0, 0, 0, 0}, 0, {0}, 0, {0}, NULL};
    if (src && (spr_cloud_alloc(&run.chunk, src->chunk) || !(run.local = malloc(src->chunk * sizeof *run.local)))) {
        spr_cloud_free(&run.chunk);
        free(sh_color);
        return spr__fail(err, SPR_E_NOMEM, "render: out of memory for a chunk of %zu splats", src->chunk);
    }
    if ((r = make_params(&run, view))) goto done;
    spr_lowres_make(view, &bd, run.eps_t, desc->lowres_n, &run.lowres);
    out->width = view->width;
    out->height = view->height;
    out->eps_t = run.eps_t;
    out->lowres = run.lowres;
    out->K = (ai->uses & SPR_USES_GROUPS) && desc->groups ? desc->groups->K : 1; /* the groups the algorithm draws */
    int final_target = -1;
    r = ai->run(&run, &final_target);
done:
    if (!r) {
        out->rgba = malloc((size_t)view->width * view->height * 4 * sizeof(float));
        if (!out->rgba) r = spr__fail(err, SPR_E_NOMEM, "render: out of memory for the image");
        else if ((r = spr_backend_read_plane(b, final_target, SPR_PLANE_COLOR, out->rgba))) backend_failed(&run, r);
    }
    for (int t = 0; t < b->n_targets; t++) spr_backend_target_destroy(b, t);
    spr_progress_report(&desc->progress, "frame", 1, 1); /* done: the terminal line is cleared */
    spr_cloud_free(&run.chunk);
    free(run.local);
    free(sh_color);
    if (r) spr_render_result_free(out);
    return r;
}

void spr_render_result_free(spr_render_result *r)
{
    free(r->rgba);
    free(r->passes);
    memset(r, 0, sizeof *r);
}
