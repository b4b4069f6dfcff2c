/* sw_raster.c — splat draws: bounds, binning to tiles, per-tile fragments.
 *
 *   1. rect[i]  = conservative pixel rectangle of the i-th submitted splat
 *   2. bins     = for each 32×32 tile, the submitted positions i touching it,
 *                 ascending (chunks of the submission are binned in parallel
 *                 and concatenated in chunk order)
 *   3. per tile = for i in bin order, for each pixel of rect ∩ tile:
 *                 ray–disk test → depth mask → test value → depth test →
 *                 kernel → blend/write  (spr_arith.h, then sw_fixed.h)
 * Tiles are disjoint, so the result does not depend on which thread runs
 * which tile; statistics are integer sums.
 */
#include "sw_internal.h"
#include "spr_fragment.h"
#include "sw_fixed.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

typedef struct sw_draw_job {
    const spr_draw_desc *d;
    const int32_t *rect; /* 4 per submitted splat, x0 = −1: empty */
    const uint32_t *bin_start, *bin;
    int tiles_x;
} sw_draw_job;

static inline uint32_t splat_at(const spr_draw_desc *d, size_t i)
{
    return d->indices ? d->indices[i] : (uint32_t)i;
}

static void raster_tile(sw_context *c, sw_target *tg, const sw_draw_job *job, int tile, uint64_t *gen_out,
                        uint64_t *pass_out)
{
    const spr_draw_desc *d = job->d;
    const spr_pass_state *s = &d->state;
    const spr_cloud *cl = d->cloud;
    const int W = c->base.view.width;
    const int tx0 = (tile % job->tiles_x) * SW_TILE, ty0 = (tile / job->tiles_x) * SW_TILE;
    const unsigned mask = s->write_mask;
    float *test = SW_F(tg, TEST);
    float *opacity = SW_F(tg, OPACITY), *normal = SW_F(tg, NORMAL);
    const float *z_near = d->depth_mask ? SW_F(&c->targets[d->mask_target], DEPTH) : NULL;
    uint64_t gen = 0, passed = 0;
    spr_probe *probe = c->base.probe;
    for (uint32_t e = job->bin_start[tile]; e < job->bin_start[tile + 1]; e++) {
        size_t i = job->bin[e];
        uint32_t sid = splat_at(d, i);
        const int32_t *rc = job->rect + 4 * i;
        int x0 = rc[0] > tx0 ? rc[0] : tx0, y0 = rc[1] > ty0 ? rc[1] : ty0;
        int x1 = rc[2] < tx0 + SW_TILE - 1 ? rc[2] : tx0 + SW_TILE - 1;
        int y1 = rc[3] < ty0 + SW_TILE - 1 ? rc[3] : ty0 + SW_TILE - 1;
        const float *p = cl->pos + 3 * (size_t)sid, *n = cl->nrm + 3 * (size_t)sid;
        const float *col = cl->color + 3 * (size_t)sid;
        const float r = d->radius_override ? d->radius_override[sid] : cl->radius[sid];
        for (int y = y0; y <= y1; y++) {
            for (int x = x0; x <= x1; x++) {
                size_t pix = (size_t)y * W + x;
                const float *ray = c->ray + 6 * pix;
                float t, rho2, rho;
                if (!spr_splat_covers(ray, ray + 3, p, n, r, s->cull_backfaces, z_near != NULL, z_near ? z_near[pix] : 0.0f,
                                      s->eps_t, &t, &rho2, &rho))
                    continue;
                gen++;
                const float z = spr_test_value(s, t, rho);
                if (probe && x == probe->x && y == probe->y) { /* pixel history: the fragment before its depth test */
                    const float alpha = d->alpha > 0.0f ? d->alpha : cl->alpha[sid];
                    spr_probe_frag f = {(uint32_t)i, sid, t, rho, z, {0.0f, 0.0f, 0.0f, 0.0f}, 0.0f};
                    spr_fragment_color((int)s->output, (int)s->kernel, rho2, rho, col, alpha, f.src);
                    f.opacity = spr_fragment_opacity((int)s->output, f.src, alpha);
                    spr_probe_add_frag(probe, &f);
                }
                if (!sw_depth_stage(s, test, pix, z)) continue;
                passed++;
                float src[4] = {0.0f, 0.0f, 0.0f, 0.0f};
                if (mask & (SPR_WRITE_COLOR | SPR_WRITE_OPACITY | SPR_WRITE_NORMAL)) {
                    const float alpha = d->alpha > 0.0f ? d->alpha : cl->alpha[sid];
                    spr_fragment_color((int)s->output, (int)s->kernel, rho2, rho, col, alpha, src);
                    if (mask & SPR_WRITE_OPACITY) /* replace or add (core refuses over) */
                        opacity[pix] = spr_blend1(s->blend_alpha, spr_fragment_opacity((int)s->output, src, alpha), opacity[pix], 1.0f);
                    if (mask & SPR_WRITE_NORMAL) { /* (w·n, w) under the rgb blend: replace or add (core refuses over) */
                        float nw[4];
                        spr_fragment_normal(src, n, nw);
                        for (int ch = 0; ch < 4; ch++) normal[4 * pix + ch] = spr_blend1(s->blend, nw[ch], normal[4 * pix + ch], 1.0f);
                    }
                }
                sw_plane_writes(s, tg, pix, t, src, sid);
            }
        }
    }
    *gen_out = gen;
    *pass_out = passed;
}

spr_result sw__draw_splats(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st)
{
    sw_context *c = sw_ctx(b);
    sw_target *tg = &c->targets[target];
    const spr_view *v = &b->view;
    const size_t n = d->indices ? d->count : d->cloud->n;
    const int tiles_x = (v->width + SW_TILE - 1) / SW_TILE, tiles_y = (v->height + SW_TILE - 1) / SW_TILE;
    const int ntiles = tiles_x * tiles_y;
    const int nchunks = c->threads * 4;
    st->splats = n;
    if (n == 0) return SPR_OK;

    int32_t *rect = malloc(n * 4 * sizeof(int32_t));
    uint32_t *counts = calloc((size_t)nchunks * ntiles, sizeof(uint32_t));
    uint32_t *bin_start = malloc(((size_t)ntiles + 1) * sizeof(uint32_t));
    uint64_t *tile_stats = calloc((size_t)ntiles * 2, sizeof(uint64_t));
    uint32_t *bin = NULL;
    spr_result res = SPR_OK;
    if (!rect || !counts || !bin_start || !tile_stats) {
        res = spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory binning %zu splats", n);
        goto done;
    }
    const size_t chunk = (n + nchunks - 1) / nchunks;

    /* 1–2a: rectangles and per-chunk tile counts. */
#pragma omp parallel for num_threads(c->threads) schedule(static, 1)
    for (int ch = 0; ch < nchunks; ch++) {
        uint32_t *cnt = counts + (size_t)ch * ntiles;
        size_t lo = (size_t)ch * chunk, hi = lo + chunk < n ? lo + chunk : n;
        for (size_t i = lo; i < hi; i++) {
            uint32_t sid = splat_at(d, i);
            float r = d->radius_override ? d->radius_override[sid] : d->cloud->radius[sid];
            int32_t *rc = rect + 4 * i;
            int x0, y0, x1, y1;
            if (!spr_splat_pixel_rect(v, d->cloud->pos + 3 * (size_t)sid, d->cloud->nrm + 3 * (size_t)sid, r,
                                      &x0, &y0, &x1, &y1)) {
                rc[0] = -1;
                continue;
            }
            rc[0] = x0; rc[1] = y0; rc[2] = x1; rc[3] = y1;
            for (int ty = y0 / SW_TILE; ty <= y1 / SW_TILE; ty++)
                for (int tx = x0 / SW_TILE; tx <= x1 / SW_TILE; tx++) cnt[ty * tiles_x + tx]++;
        }
    }
    /* 2b: prefix sums in (tile, chunk) order turn counts into write offsets. */
    uint64_t total = 0;
    for (int t = 0; t < ntiles; t++) {
        bin_start[t] = (uint32_t)total;
        for (int ch = 0; ch < nchunks; ch++) {
            uint32_t k = counts[(size_t)ch * ntiles + t];
            counts[(size_t)ch * ntiles + t] = (uint32_t)total;
            total += k;
        }
        if (total > UINT32_MAX) {
            res = spr__fail(&b->err, SPR_E_TOO_LARGE, "cpu: more than 2^32 tile entries in one draw");
            goto done;
        }
    }
    bin_start[ntiles] = (uint32_t)total;
    bin = malloc((total ? total : 1) * sizeof(uint32_t));
    if (!bin) {
        res = spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for %llu tile entries", (unsigned long long)total);
        goto done;
    }
    /* 2c: fill, each chunk at its own offsets: bins stay in submission order. */
#pragma omp parallel for num_threads(c->threads) schedule(static, 1)
    for (int ch = 0; ch < nchunks; ch++) {
        uint32_t *off = counts + (size_t)ch * ntiles;
        size_t lo = (size_t)ch * chunk, hi = lo + chunk < n ? lo + chunk : n;
        for (size_t i = lo; i < hi; i++) {
            const int32_t *rc = rect + 4 * i;
            if (rc[0] < 0) continue;
            for (int ty = rc[1] / SW_TILE; ty <= rc[3] / SW_TILE; ty++)
                for (int tx = rc[0] / SW_TILE; tx <= rc[2] / SW_TILE; tx++) bin[off[ty * tiles_x + tx]++] = (uint32_t)i;
        }
    }
    /* 3: tiles in parallel, each in submission order. */
    sw_draw_job job = {d, rect, bin_start, bin, tiles_x};
#pragma omp parallel num_threads(c->threads)
    {
        unsigned fp = sw_fp_enter();
#pragma omp for schedule(dynamic, 1)
        for (int t = 0; t < ntiles; t++) raster_tile(c, tg, &job, t, &tile_stats[2 * t], &tile_stats[2 * t + 1]);
        sw_fp_leave(fp);
    }
    for (int t = 0; t < ntiles; t++) {
        st->generated += tile_stats[2 * t];
        st->passed += tile_stats[2 * t + 1];
    }
done:
    free(rect);
    free(counts);
    free(bin_start);
    free(tile_stats);
    free(bin);
    return res;
}
