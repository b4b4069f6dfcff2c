/* sw_backend.c — CPU backend context: view, ray cache, targets, clear, read. */
#include "spr_swrast.h"
#include "sw_internal.h"
#include "spr_util.h"
#include "spr_fragment.h"

#include <omp.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <stdlib.h>
#include <string.h>

static void free_target(sw_target *t)
{
    for (int p = 0; p < SPR_PLANE__COUNT; p++) free(t->plane[p]);
    free(t->tpend);
    sw__lists_free(&t->lists);
    memset(t, 0, sizeof *t);
}

static spr_result sw_set_view(spr_backend *b, const spr_view *v)
{
    sw_context *c = sw_ctx(b);
    size_t np = (size_t)v->width * (size_t)v->height;
    float *ray = realloc(c->ray, np * 6 * sizeof(float));
    if (!ray) return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for a %dx%d view", v->width, v->height);
    c->ray = ray;
    const int wp = (v->width + 7) / 8 * 8 + 8;
    if (!c->ray_soa || wp != c->ray_wp || v->height != c->ray_h) { /* the padding stays zero: den = 0, never covered */
        c->ray_ok = 0;
        free(c->ray_soa);
        c->ray_wp = wp, c->ray_h = v->height;
        if (!(c->ray_soa = calloc((size_t)wp * (size_t)v->height * 6, sizeof(float)))) {
            c->ray_wp = 0;
            return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for a %dx%d view", v->width, v->height);
        }
    }
    /* what the rays are made of (spr_pixel_ray): the same bits as the last
     * view's keep them (a frame set again in the same view: bench, step) */
    float key[18];
    memcpy(key, v->M, sizeof v->M);
    key[16] = v->ndc_sx, key[17] = v->ndc_sy;
    const int same = c->ray_ok && !memcmp(key, c->ray_key, sizeof key) && np == c->ray_np;
    memcpy(c->ray_key, key, sizeof key);
    c->ray_np = np;
    c->ray_ok = same; /* else computed by the first draw that needs them: the Gaussian algorithms do not */
    c->bins.valid = 0;
    return SPR_OK;
}

void sw__rays(sw_context *c)
{
    if (c->ray_ok) return;
    const spr_view *v = &c->base.view;
    const int W = v->width, H = v->height;
    float *ray = c->ray;
#pragma omp parallel for num_threads(c->threads) schedule(static)
    for (int y = 0; y < H; y++) {
        unsigned fp = sw_fp_enter();
        for (int x = 0; x < W; x++) {
            float *r = ray + 6 * ((size_t)y * W + x);
            spr_pixel_ray(v, x, y, r, r + 3);
            for (int k = 0; k < 6; k++) c->ray_soa[((size_t)k * H + y) * c->ray_wp + x] = r[k];
        }
        sw_fp_leave(fp);
    }
    c->ray_ok = 1;
}

/* A clear of every plane (colour to `color`, the others to the clear value
 * of the plane table) recorded, every tile pending; the fragment lists
 * emptied at once. */
static void pend_all(sw_target *tg, const float color[4])
{
    sw__lists_free(&tg->lists);
    for (int p = 0; p < SPR_PLANE__COUNT; p++)
        if (tg->planes & SPR_PLANE_BIT(p))
            for (int k = 0; k < spr_plane_channels((spr_plane)p); k++) tg->pval[p][k] = sw__clear_word((spr_plane)p, color, k);
    memset(tg->tpend, 1, tg->ntiles);
    tg->pending = 1;
    static const float zero[4] = {0, 0, 0, 0};
    tg->zero_clear = !memcmp(color, zero, sizeof zero); /* bit for bit: −0 is another clear */
}

static spr_result sw_target_create(spr_backend *b, unsigned planes, int *out)
{
    sw_context *c = sw_ctx(b);
    spr_result r = spr__backend_add_target(b, planes, out, (void **)&c->targets, &c->cap, sizeof *c->targets);
    if (r) return r;
    const int t = *out;
    size_t np = (size_t)b->view.width * (size_t)b->view.height;
    sw_target *tg = &c->targets[t];
    if (tg->pixels != np) free_target(tg); /* else: memory kept from a destroyed target of this size */
    tg->pixels = np;
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        if (!(planes & SPR_PLANE_BIT(p)) || tg->plane[p]) continue;
        if (!(tg->plane[p] = spr__big_alloc(np * (size_t)spr_plane_channels((spr_plane)p) * 4))) {
            free_target(tg);
            return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for a target");
        }
    }
    const size_t ntiles = sw__tiles(&b->view);
    if (tg->ntiles != ntiles) {
        free(tg->tpend);
        tg->ntiles = 0;
        if (!(tg->tpend = malloc(ntiles))) {
            free_target(tg);
            return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for a target");
        }
        tg->ntiles = ntiles;
    }
    tg->planes = planes;
    static const float zero[4] = {0, 0, 0, 0};
    pend_all(tg, zero); /* the zero clear, done tile by tile at the first use unless a clear comes first */
    return SPR_OK;
}

/* Buffers stay allocated for the next target of the same size: algorithms
 * create and destroy their targets every frame, and fresh pages would be
 * faulted in serially on every render. */
static void sw_target_destroy(spr_backend *b, int t) { (void)b; (void)t; }

/* n copies of the ch-channel pixel v (4-byte words) from dst on, in
 * parallel, with non-temporal stores where SSE2 has them: a cleared plane
 * (4 to 16 MB a plane at 1024²) does not fit in the caches, and the stores
 * skip reading each line before writing it. */
#ifndef SW_FILL_STORE
#define SW_FILL_STORE _mm_stream_si128
#endif
static void fill_plane(uint32_t *dst, long np, int ch, const uint32_t v[4], int threads)
{
    const long words = np * ch;
#pragma omp parallel num_threads(threads)
    {
        const int nt = omp_get_num_threads(), id = omp_get_thread_num();
        long w0 = words / nt * id, w1 = id == nt - 1 ? words : words / nt * (id + 1);
        w0 -= w0 % (4 * ch), w1 -= id == nt - 1 ? 0 : w1 % (4 * ch); /* chunks of whole 4-pixel groups: the pattern repeats every 4·ch words */
        long i = w0;
#if defined(__SSE2__)
        for (; i < w1 && ((uintptr_t)(dst + i) & 15u); i++) dst[i] = v[i % ch];
        /* the 16-byte pattern at word i: ch is 1 or 4, so it is the same at every aligned word */
        __m128i pat = ch == 4 ? _mm_setr_epi32((int)v[i % 4], (int)v[(i + 1) % 4], (int)v[(i + 2) % 4], (int)v[(i + 3) % 4])
                              : _mm_set1_epi32((int)v[0]);
        if (ch == 1 || ch == 4) {
            for (; i + 4 <= w1; i += 4) SW_FILL_STORE((__m128i *)(dst + i), pat);
            _mm_sfence();
        }
#endif
        for (; i < w1; i++) dst[i] = v[i % ch];
    }
}

void sw__tile_fill(const sw_context *c, sw_target *tg, int tile)
{
    if (!tg->pending || !tg->tpend[tile]) return;
    const int W = c->base.view.width, H = c->base.view.height, tiles_x = (W + SW_TILE - 1) / SW_TILE;
    const int x0 = tile % tiles_x * SW_TILE, y0 = tile / tiles_x * SW_TILE;
    const int x1 = x0 + SW_TILE < W ? x0 + SW_TILE : W, y1 = y0 + SW_TILE < H ? y0 + SW_TILE : H;
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        if (!(tg->planes & SPR_PLANE_BIT(p))) continue;
        const int ch = spr_plane_channels((spr_plane)p);
        const uint32_t *v = tg->pval[p];
        for (int y = y0; y < y1; y++) {
            uint32_t *q = (uint32_t *)tg->plane[p] + ((size_t)y * W + x0) * (size_t)ch;
            if (ch == 1)
                for (int x = 0; x < x1 - x0; x++) q[x] = v[0];
            else
                for (int x = 0; x < x1 - x0; x++)
                    for (int k = 0; k < ch; k++) q[ch * x + k] = v[k];
        }
    }
    tg->tpend[tile] = 0;
}

sw_target *sw__target(sw_context *c, int t)
{
    sw_target *tg = &c->targets[t];
    if (!tg->pending) return tg;
    size_t left = 0;
    for (size_t k = 0; k < tg->ntiles; k++) left += tg->tpend[k];
    if (left == tg->ntiles) { /* all of it: plane by plane, streaming */
        const long np = (long)c->base.view.width * c->base.view.height;
        for (int p = 0; p < SPR_PLANE__COUNT; p++)
            if (tg->planes & SPR_PLANE_BIT(p)) fill_plane(tg->plane[p], np, spr_plane_channels((spr_plane)p), tg->pval[p], c->threads);
        memset(tg->tpend, 0, tg->ntiles);
    } else if (left) {
#pragma omp parallel for num_threads(c->threads) schedule(dynamic, 4)
        for (long k = 0; k < (long)tg->ntiles; k++) sw__tile_fill(c, tg, (int)k);
    }
    tg->pending = 0;
    return tg;
}

static spr_result sw_clear(spr_backend *b, int t, const float color[4])
{
    pend_all(&sw_ctx(b)->targets[t], color);
    return SPR_OK;
}

static spr_result sw_read_plane(spr_backend *b, int t, spr_plane p, void *out)
{
    sw_context *c = sw_ctx(b);
    const sw_target *tg = sw__target(c, t);
    const size_t bytes = (size_t)b->view.width * (size_t)b->view.height * (size_t)spr_plane_channels(p) * 4, chunk = (size_t)1 << 20;
    const long chunks = (long)((bytes + chunk - 1) / chunk);
    /* in parallel: out is often fresh memory, and its page faults are most of the copy */
#pragma omp parallel for num_threads(c->threads) schedule(static)
    for (long k = 0; k < chunks; k++) {
        const size_t o = (size_t)k * chunk;
        memcpy((char *)out + o, (const char *)tg->plane[p] + o, bytes - o < chunk ? bytes - o : chunk);
    }
    return SPR_OK;
}

static void sw_destroy(spr_backend *b)
{
    sw_context *c = sw_ctx(b);
    free(c->ray);
    free(c->ray_soa);
    for (int k = 0; k < SW_SCRATCH__COUNT; k++) free(c->scratch[k].p);
    for (int p = 0; p < SPR_PLANE__COUNT; p++) free(c->zband[p]);
    free(c->bins.indices);
    for (int t = 0; t < c->cap; t++) free_target(&c->targets[t]);
    free(c->targets);
    free(c);
}

void spr_swrast_scalar(spr_backend *b, int on) { sw_ctx(b)->scalar = on != 0; }

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
    b->host_threads = c->threads;
    b->set_view = sw_set_view;
    b->target_create = sw_target_create;
    b->target_destroy = sw_target_destroy;
    b->clear = sw_clear;
    b->draw_splats = sw__draw_splats;
    b->composite = sw__composite;
    b->draw_rects = sw__draw_rects;
    b->gauss_preprocess = sw__gauss_preprocess;
    b->gauss_raster = sw__gauss_raster;
    b->gauss_draw = sw__gauss_draw;
    b->gauss_backward = sw__gauss_backward;
    b->read_plane = sw_read_plane;
    b->destroy = sw_destroy;
    return b;
}
