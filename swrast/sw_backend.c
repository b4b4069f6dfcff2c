/* sw_backend.c — CPU backend context: view, ray cache, targets, clear, read. */
#include "spr_swrast.h"
#include "sw_internal.h"
#include "spr_fragment.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

static void free_target(sw_target *t)
{
    free(t->color);
    free(t->depth);
    free(t->test);
    free(t->id);
    free(t->count);
    memset(t, 0, sizeof *t);
}

static spr_result sw_set_view(spr_backend *b, const spr_view *v)
{
    sw_context *c = sw_ctx(b);
    size_t np = (size_t)v->width * (size_t)v->height;
    float *ray = realloc(c->ray, np * 6 * sizeof(float));
    if (!ray) return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for a %dx%d view", v->width, v->height);
    c->ray = ray;
    int W = v->width, H = v->height;
#pragma omp parallel for num_threads(c->threads) schedule(static)
    for (int y = 0; y < H; y++) {
        unsigned fp = sw_fp_enter();
        for (int x = 0; x < W; x++) {
            float *r = ray + 6 * ((size_t)y * W + x);
            spr_pixel_ray(v, x, y, r, r + 3);
        }
        sw_fp_leave(fp);
    }
    return SPR_OK;
}

static spr_result sw_target_create(spr_backend *b, int *out)
{
    sw_context *c = sw_ctx(b);
    int t;
    spr_result r = spr__backend_add_target(b, &t, (void **)&c->targets, &c->cap, sizeof *c->targets);
    if (r) return r;
    size_t np = (size_t)b->view.width * (size_t)b->view.height;
    sw_target *tg = &c->targets[t];
    if (tg->color && tg->pixels == np) { /* memory kept from a destroyed target of this size */
        static const float zero[4] = {0, 0, 0, 0};
        *out = t;
        return b->clear(b, t, zero);
    }
    free_target(tg);
    tg->pixels = np;
    tg->color = malloc(np * 4 * sizeof(float));
    tg->depth = malloc(np * sizeof(float));
    tg->test = malloc(np * sizeof(float));
    tg->id = malloc(np * sizeof(uint32_t));
    tg->count = malloc(np * sizeof(uint32_t));
    if (!tg->color || !tg->depth || !tg->test || !tg->id || !tg->count) {
        free_target(tg);
        b->target_live[t] = 0;
        return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for a target");
    }
    *out = t;
    static const float zero[4] = {0, 0, 0, 0};
    return b->clear(b, t, zero);
}

/* Buffers stay allocated for the next target of the same size: algorithms
 * create and destroy their targets every frame, and fresh pages would be
 * faulted in serially on every render. */
static void sw_target_destroy(spr_backend *b, int t) { (void)b; (void)t; }

static spr_result sw_clear(spr_backend *b, int t, const float color[4])
{
    sw_context *c = sw_ctx(b);
    sw_target *tg = &c->targets[t];
    const long np = (long)b->view.width * b->view.height;
#pragma omp parallel for num_threads(c->threads) schedule(static)
    for (long i = 0; i < np; i++) {
        memcpy(tg->color + 4 * i, color, 4 * sizeof(float));
        tg->depth[i] = 1.0f;
        tg->test[i] = 1.0f;
        tg->id[i] = UINT32_MAX;
        tg->count[i] = 0;
    }
    return SPR_OK;
}

static spr_result sw_read_plane(spr_backend *b, int t, spr_plane p, void *out)
{
    sw_target *tg = &sw_ctx(b)->targets[t];
    size_t np = (size_t)b->view.width * (size_t)b->view.height;
    switch (p) {
    case SPR_PLANE_COLOR: memcpy(out, tg->color, np * 4 * sizeof(float)); break;
    case SPR_PLANE_DEPTH: memcpy(out, tg->depth, np * sizeof(float)); break;
    case SPR_PLANE_TEST: memcpy(out, tg->test, np * sizeof(float)); break;
    case SPR_PLANE_ID: memcpy(out, tg->id, np * sizeof(uint32_t)); break;
    case SPR_PLANE_COUNT: memcpy(out, tg->count, np * sizeof(uint32_t)); break;
    default: return spr__fail(&b->err, SPR_E_ARG, "cpu: unknown plane");
    }
    return SPR_OK;
}

static void sw_destroy(spr_backend *b)
{
    sw_context *c = sw_ctx(b);
    free(c->ray);
    for (int t = 0; t < c->cap; t++) free_target(&c->targets[t]);
    free(c->targets);
    free(c);
}

spr_backend *spr_swrast_create(int threads, spr_error *err)
{
    if (threads < 0 || threads > 1024) {
        spr__fail(err, SPR_E_ARG, "cpu: thread count %d outside 0..1024", threads);
        return NULL;
    }
    sw_context *c = calloc(1, sizeof *c);
    if (!c) {
        spr__fail(err, SPR_E_NOMEM, "cpu: out of memory");
        return NULL;
    }
    c->threads = threads ? threads : omp_get_num_procs();
    spr_backend *b = &c->base;
    b->name = "cpu";
    b->set_view = sw_set_view;
    b->target_create = sw_target_create;
    b->target_destroy = sw_target_destroy;
    b->clear = sw_clear;
    b->draw_splats = sw__draw_splats;
    b->composite = sw__composite;
    b->read_plane = sw_read_plane;
    b->destroy = sw_destroy;
    return b;
}
