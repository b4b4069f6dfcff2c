/* sw_raster.c — splat draws: bounds, binning to tiles, per-tile fragments.
 *
 *   1. rect[i]  = conservative pixel rectangle of the i-th submitted splat
 *   2. bins     = for each 32×32 tile, an entry per submitted splat touching
 *                 it, in submission order (chunks of the submission are
 *                 binned in parallel and concatenated in chunk order); an
 *                 entry carries everything the tile needs of its splat —
 *                 rectangle, centre, normal, colour, radius, opacity — so
 *                 the tile reads its bin as one stream instead of gathering
 *                 from the cloud (a cache miss per splat per array when the
 *                 file's order is not spatial: most of the time at 1M+)
 *   3. per tile = for each entry, for each pixel of rect ∩ tile:
 *                 ray–disk test → depth mask → test value → depth test →
 *                 kernel → blend/write  (core/render/arith/, then sw_fixed.h)
 * Tiles are disjoint, so the result does not depend on which thread runs
 * which tile; statistics are integer sums.
 */
#include "sw_internal.h"
#include "spr_fragment.h"
#include "sw_fixed.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* One splat in one tile's bin (64 bytes: one cache line). */
typedef struct sw_bin_entry {
    int16_t x0, y0, x1, y1;  /* its pixel rectangle (sides ≤ SPR_MAX_IMAGE_SIDE < 2^15) */
    uint32_t seq;            /* position in the submission */
    uint32_t sid;            /* splat id */
    float p[3], n[3], c[3];
    float r, alpha;
} sw_bin_entry;
_Static_assert(SPR_MAX_IMAGE_SIDE < 32768, "bin rectangles are int16");

typedef struct sw_draw_job {
    const spr_draw_desc *d;
    const uint32_t *bin_start;
    const sw_bin_entry *bin;
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
    const int W = c->base.view.width;
    const int tx0 = (tile % job->tiles_x) * SW_TILE, ty0 = (tile / job->tiles_x) * SW_TILE;
    const unsigned mask = s->write_mask;
    const spr_fixed_planes pl = sw_fixed_planes(tg);
    const float *z_near = d->depth_mask ? SW_F(&c->targets[d->mask_target], DEPTH) : NULL;
    uint64_t gen = 0, passed = 0;
    spr_probe *probe = c->base.probe;
    const float ks = spr_draw_kernel_scale(d);
    for (uint32_t e = job->bin_start[tile]; e < job->bin_start[tile + 1]; e++) {
        const sw_bin_entry *be = &job->bin[e];
        const uint32_t sid = be->sid;
        int x0 = be->x0 > tx0 ? be->x0 : tx0, y0 = be->y0 > ty0 ? be->y0 : ty0;
        int x1 = be->x1 < tx0 + SW_TILE - 1 ? be->x1 : tx0 + SW_TILE - 1;
        int y1 = be->y1 < ty0 + SW_TILE - 1 ? be->y1 : ty0 + SW_TILE - 1;
        const float *p = be->p, *n = be->n, *col = be->c;
        const float r = be->r;
        float e[4] = {0.0f, 0.0f, 0.0f, r};
        if (d->cloud->ell) spr_draw_ellipse(d, sid - d->id_base, r, e); /* elliptical: looked up, the bin keeps its line */
        for (int y = y0; y <= y1; y++) {
            for (int x = x0; x <= x1; x++) {
                size_t pix = (size_t)y * W + x;
                const float *ray = c->ray + 6 * pix;
                float t, rho2, rho;
                if (!spr_splat_covers(ray, ray + 3, p, n, e, r, s->cull_backfaces, z_near != NULL, z_near ? z_near[pix] : 0.0f,
                                      s->eps_t, &t, &rho2, &rho))
                    continue;
                gen++;
                const float z = spr_test_value(s, t, rho);
                if (probe && x == probe->x && y == probe->y) { /* pixel history: the fragment before its depth test */
                    spr_probe_frag f = {be->seq, sid, t, rho, z, {0.0f, 0.0f, 0.0f, 0.0f}, 0.0f};
                    spr_fragment_color((int)s->output, (int)s->kernel, ks, rho2, rho, col, be->alpha, f.src);
                    f.opacity = spr_fragment_opacity((int)s->output, f.src, be->alpha);
                    spr_probe_add_frag(probe, &f);
                }
                if (!spr_fixed_depth(s, &pl, pix, z)) continue;
                passed++;
                float src[4] = {0.0f, 0.0f, 0.0f, 0.0f}, op = 0.0f, nw[4];
                if (mask & (SPR_WRITE_COLOR | SPR_WRITE_OPACITY | SPR_WRITE_NORMAL)) {
                    spr_fragment_color((int)s->output, (int)s->kernel, ks, rho2, rho, col, be->alpha, src);
                    op = spr_fragment_opacity((int)s->output, src, be->alpha);
                    if (mask & SPR_WRITE_NORMAL) spr_fragment_normal(src, n, nw);
                }
                spr_fixed_writes(s, &pl, pix, t, src, sid, &op, mask & SPR_WRITE_NORMAL ? nw : NULL);
            }
        }
    }
    *gen_out = gen;
    *pass_out = passed;
}

/* 3: tiles in parallel, each in submission order. */
static spr_result raster_bins(sw_context *c, sw_target *tg, const spr_draw_desc *d, const uint32_t *bin_start, const sw_bin_entry *bin,
                              int tiles_x, int ntiles, uint64_t *tile_stats, spr_draw_stats *st)
{
    sw_draw_job job = {d, bin_start, bin, tiles_x};
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
    return SPR_OK;
}

spr_result sw__draw_splats(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st)
{
    sw_context *c = sw_ctx(b);
    sw_target *tg = sw__target(c, target);
    if (d->depth_mask) sw__target(c, d->mask_target); /* read by the tiles: its pending clear first */
    const spr_view *v = &b->view;
    sw__rays(c);
    const size_t n = d->indices ? d->count : d->cloud->n;
    const int tiles_x = (v->width + SW_TILE - 1) / SW_TILE, tiles_y = (v->height + SW_TILE - 1) / SW_TILE;
    const int ntiles = tiles_x * tiles_y;
    const int nchunks = c->threads * 4;
    st->splats = n;
    if (n == 0) return SPR_OK;

    /* the bins of the last draw when they are this draw's: 1–2c skipped */
    struct sw_bins_key key = {1, d->cloud->pos, d->cloud->nrm, d->cloud->radius, d->cloud->color, d->cloud->alpha, d->cloud->ell, n,
                              d->indices != NULL, d->radius_scale, d->alpha, d->id_base, d->seq_base, NULL, 0};
    struct sw_bins_key *kept = &c->bins;
    if (kept->valid && kept->pos == key.pos && kept->nrm == key.nrm && kept->radius == key.radius && kept->color == key.color &&
        kept->alpha == key.alpha && kept->ell == key.ell && kept->count == n && kept->has_indices == key.has_indices &&
        kept->radius_scale == key.radius_scale && kept->alpha_one == key.alpha_one && kept->id_base == key.id_base &&
        kept->seq_base == key.seq_base && (!d->indices || !memcmp(kept->indices, d->indices, n * sizeof *d->indices))) {
        uint64_t *tile_stats = sw_scratch_get(&c->scratch[SW_SCRATCH_STATS], (size_t)ntiles * 2 * sizeof(uint64_t));
        if (!tile_stats) return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory binning %zu splats", n);
        memset(tile_stats, 0, (size_t)ntiles * 2 * sizeof(uint64_t));
        return raster_bins(c, tg, d, c->scratch[SW_SCRATCH_BIN_START].p, c->scratch[SW_SCRATCH_BIN].p, tiles_x, ntiles, tile_stats, st);
    }
    kept->valid = 0;
    /* each splat's bin entry, staged in submission order by 1–2a (x0 = −1:
     * off screen): its attributes are gathered from the cloud once, where
     * they are read for the rectangle, and 2c copies them sequentially */
    sw_bin_entry *stage = sw_scratch_get(&c->scratch[SW_SCRATCH_RECT], n * sizeof(sw_bin_entry));
    uint32_t *counts = sw_scratch_get(&c->scratch[SW_SCRATCH_COUNTS], (size_t)nchunks * ntiles * sizeof(uint32_t));
    uint32_t *bin_start = sw_scratch_get(&c->scratch[SW_SCRATCH_BIN_START], ((size_t)ntiles + 1) * sizeof(uint32_t));
    uint64_t *tile_stats = sw_scratch_get(&c->scratch[SW_SCRATCH_STATS], (size_t)ntiles * 2 * sizeof(uint64_t));
    sw_bin_entry *bin = NULL;
    if (!stage || !counts || !bin_start || !tile_stats) return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory binning %zu splats", n);
    memset(counts, 0, (size_t)nchunks * ntiles * sizeof(uint32_t));
    memset(tile_stats, 0, (size_t)ntiles * 2 * sizeof(uint64_t));
    const size_t chunk = (n + nchunks - 1) / nchunks;

    /* 1–2a: rectangles and bin entries, and per-chunk tile counts. */
#pragma omp parallel for num_threads(c->threads) schedule(static, 1)
    for (int ch = 0; ch < nchunks; ch++) {
        uint32_t *cnt = counts + (size_t)ch * ntiles;
        size_t lo = (size_t)ch * chunk, hi = lo + chunk < n ? lo + chunk : n;
        const spr_cloud *cl = d->cloud;
        for (size_t i = lo; i < hi; i++) {
            uint32_t sid = splat_at(d, i);
            float r = spr_draw_radius(d, sid), el[4];
            spr_draw_ellipse(d, sid, r, el);
            sw_bin_entry *be = stage + i;
            int x0, y0, x1, y1;
            if (!spr_splat_pixel_rect_ell(v, cl->pos + 3 * (size_t)sid, cl->nrm + 3 * (size_t)sid, el, r, &x0, &y0, &x1, &y1)) {
                be->x0 = -1;
                continue;
            }
            be->x0 = (int16_t)x0, be->y0 = (int16_t)y0, be->x1 = (int16_t)x1, be->y1 = (int16_t)y1;
            be->seq = d->seq_base + (uint32_t)i;
            be->sid = d->id_base + sid;
            memcpy(be->p, cl->pos + 3 * (size_t)sid, sizeof be->p);
            memcpy(be->n, cl->nrm + 3 * (size_t)sid, sizeof be->n);
            memcpy(be->c, cl->color + 3 * (size_t)sid, sizeof be->c);
            be->r = r;
            be->alpha = d->alpha > 0.0f ? d->alpha : cl->alpha[sid];
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
        if (total > UINT32_MAX) return spr__fail(&b->err, SPR_E_TOO_LARGE, "cpu: more than 2^32 tile entries in one draw");
    }
    bin_start[ntiles] = (uint32_t)total;
    bin = sw_scratch_get(&c->scratch[SW_SCRATCH_BIN], (total ? total : 1) * sizeof *bin);
    if (!bin) return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for %llu tile entries", (unsigned long long)total);
    /* 2c: fill, each chunk at its own offsets: bins stay in submission order. */
#pragma omp parallel for num_threads(c->threads) schedule(static, 1)
    for (int ch = 0; ch < nchunks; ch++) {
        uint32_t *off = counts + (size_t)ch * ntiles;
        size_t lo = (size_t)ch * chunk, hi = lo + chunk < n ? lo + chunk : n;
        for (size_t i = lo; i < hi; i++) {
            const sw_bin_entry *be = stage + i;
            if (be->x0 < 0) continue;
            for (int ty = be->y0 / SW_TILE; ty <= be->y1 / SW_TILE; ty++)
                for (int tx = be->x0 / SW_TILE; tx <= be->x1 / SW_TILE; tx++) bin[off[ty * tiles_x + tx]++] = *be;
        }
    }
    /* the key of these bins, for the next draw */
    if (d->indices) {
        if (kept->cap < n) {
            uint32_t *ni = realloc(kept->indices, n * sizeof *ni);
            if (ni) kept->indices = ni, kept->cap = n;
        }
        if (kept->cap >= n) {
            memcpy(kept->indices, d->indices, n * sizeof *d->indices);
            key.indices = kept->indices, key.cap = kept->cap;
            *kept = key;
        }
    } else {
        key.indices = kept->indices, key.cap = kept->cap;
        *kept = key;
    }
    return raster_bins(c, tg, d, bin_start, bin, tiles_x, ntiles, tile_stats, st);
}
