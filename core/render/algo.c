/* algo.c — the algorithm runner: shared parameters, pass bookkeeping, hooks. */
#include "spr_util.h"
#include "spr_algo.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static spr_result record(spr__run *run, const char *name, int group, const spr_pass_state *state, int target,
                         const spr_draw_stats *st, double ms)
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
        spr_pass_info info = {o->n_passes, name, group, state, target, *st, ms};
        run->desc->hook(run->desc->hook_user, run->b, &info);
    }
    o->n_passes++;
    return SPR_OK;
}

static spr_result backend_failed(spr__run *run, spr_result r)
{
    return spr__fail(run->err, r, "%s backend: %s", run->b->name, run->b->err.msg);
}

spr_result spr__run_draw(spr__run *run, const char *name, int group, int target, const spr_draw_desc *d)
{
    spr_draw_stats st;
    double t0 = spr_now_ms();
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

void spr__group_radii(const spr__run *run, const spr_groups *g, int k, const uint32_t *members, size_t m, float *radius)
{
    for (size_t a = 0; a < m; a++) radius[members[a]] = g->radius_scale[k] * run->cloud->radius[members[a]];
}

spr_result spr__run_finish(spr__run *run, spr_composite_op op, const int *I, int K, int *final_target)
{
    const float *bg = run->desc->background;
    spr_composite_desc c = {op, I, K, I[K], run->eps_t, {bg[0], bg[1], bg[2]}};
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

spr_result spr_render(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc,
                      spr_render_result *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    const spr_algo_info *ai = spr_algo_info_of(desc->algo);
    if (!ai) return spr__fail(err, SPR_E_ARG, "render: unknown algorithm %d", (int)desc->algo);
    if (desc->groups && desc->groups->n_splats != cloud->n)
        return spr__fail(err, SPR_E_ARG, "render: groups are for %zu splats, the model has %zu", desc->groups->n_splats, cloud->n);
    spr_result r = spr_backend_set_view(b, view);
    if (r) return backend_failed(&(spr__run){.b = b, .err = err}, r);
    spr_bounds bd;
    spr_cloud_bounds(cloud, &bd);
    double eps = desc->eps > 0.0 ? desc->eps : spr_cloud_default_eps(cloud);
    spr__run run = {b, cloud, desc, out, err, spr_view_eps_t(view, eps), {0, 0, 0, 0}, 0};
    spr_lowres_make(view, &bd, run.eps_t, desc->lowres_n, &run.lowres);
    out->width = view->width;
    out->height = view->height;
    out->eps_t = run.eps_t;
    out->lowres = run.lowres;
    out->K = (ai->uses & SPR_USES_GROUPS) && desc->groups ? desc->groups->K : 1; /* the groups the algorithm draws */
    int final_target = -1;
    r = ai->run(&run, &final_target);
    if (!r) {
        out->rgba = malloc((size_t)view->width * view->height * 4 * sizeof(float));
        if (!out->rgba) r = spr__fail(err, SPR_E_NOMEM, "render: out of memory for the image");
        else if ((r = spr_backend_read_plane(b, final_target, SPR_PLANE_COLOR, out->rgba))) backend_failed(&run, r);
    }
    for (int t = 0; t < b->n_targets; t++) spr_backend_target_destroy(b, t);
    if (r) spr_render_result_free(out);
    return r;
}

void spr_render_result_free(spr_render_result *r)
{
    free(r->rgba);
    free(r->passes);
    memset(r, 0, sizeof *r);
}
