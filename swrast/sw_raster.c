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
 *                 kernel → blend/write  (core/render/arith/, then sw_fixed.h);
 *                 a disk's ray test runs on 8 pixels of a row at once
 *                 (disk_lanes: spr_ray_disk's operations lane by lane, AVX2
 *                 where the CPU has it, no FMA), the rest pixel by pixel
 * The bins of 1–2c are kept for the next draw when it draws the same splats
 * (pbr2p1's two passes).
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

enum { SW_PREFETCH = 16 }; /* splats ahead whose cloud lines 1–2a prefetches */

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

/* The fragment of splat `be` at pixel (x, y), which it covers at t with ρ²
 * (spr_splat_covers' tests, the depth mask aside, passed): the depth mask,
 * then test value, depth test, kernel and writes. */
static inline void fragment_at(sw_context *c, const spr_draw_desc *d, const spr_fixed_planes *pl, const float *z_near, float ks,
                               const sw_bin_entry *be, int x, int y, float t, float rho2, uint64_t *gen, uint64_t *passed)
{
    const spr_pass_state *s = &d->state;
    const size_t pix = (size_t)y * c->base.view.width + x;
    if (z_near && spr_depth_masked(t, z_near[pix], s->eps_t) != 0) return;
    const float rho = spr_sqrt(rho2);
    ++*gen;
    const float z = spr_test_value(s, t, rho);
    spr_probe *probe = c->base.probe;
    if (probe && x == probe->x && y == probe->y) { /* pixel history: the fragment before its depth test */
        spr_probe_frag f = {be->seq, be->sid, t, rho, z, {0.0f, 0.0f, 0.0f, 0.0f}, 0.0f};
        spr_fragment_color((int)s->output, (int)s->kernel, ks, rho2, rho, be->c, be->alpha, f.src);
        f.opacity = spr_fragment_opacity((int)s->output, f.src, be->alpha);
        spr_probe_add_frag(probe, &f);
    }
    if (!spr_fixed_depth(s, pl, pix, z)) return;
    ++*passed;
    const unsigned mask = s->write_mask;
    float src[4] = {0.0f, 0.0f, 0.0f, 0.0f}, op = 0.0f, nw[4];
    if (mask & (SPR_WRITE_COLOR | SPR_WRITE_OPACITY | SPR_WRITE_NORMAL)) {
        spr_fragment_color((int)s->output, (int)s->kernel, ks, rho2, rho, be->c, be->alpha, src);
        op = spr_fragment_opacity((int)s->output, src, be->alpha);
        if (mask & SPR_WRITE_NORMAL) spr_fragment_normal(src, be->n, nw);
    }
    spr_fixed_writes(s, pl, pix, t, src, be->sid, &op, mask & SPR_WRITE_NORMAL ? nw : NULL);
}

#ifdef SW_RASTER_CLONES
/* given on the command line (empty: the portable path alone, to test it) */
#elif defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#define SW_RASTER_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SW_RASTER_CLONES
#endif
typedef float sw_v8f __attribute__((vector_size(32)));
typedef int32_t sw_v8i __attribute__((vector_size(32)));

/* spr_ray_disk for the 8 pixels (x … x+7, y) at once, lane by lane the same
 * operations in the same order (IEEE single, no FMA: the lanes are the
 * scalar function's bits; test raster's disk_lanes_are_the_scalar_test
 * checks it): bit l of the result is set when pixel x+l is covered (and not
 * back-facing when culling), with its t and ρ² in t[l], rho2[l]. */
static inline unsigned disk_lanes(const sw_context *c, int x, int y, const float p[3], const float n[3], float rr, int cull, float t_out[8],
                                  float rho2_out[8])
{
    const size_t plane = (size_t)c->ray_wp * (size_t)c->base.view.height, at = (size_t)y * (size_t)c->ray_wp + (size_t)x;
    sw_v8f o0, o1, o2, d0, d1, d2;
    memcpy(&o0, c->ray_soa + at, sizeof o0);
    memcpy(&o1, c->ray_soa + plane + at, sizeof o1);
    memcpy(&o2, c->ray_soa + 2 * plane + at, sizeof o2);
    memcpy(&d0, c->ray_soa + 3 * plane + at, sizeof d0);
    memcpy(&d1, c->ray_soa + 4 * plane + at, sizeof d1);
    memcpy(&d2, c->ray_soa + 5 * plane + at, sizeof d2);
    const sw_v8f den = (d0 * n[0] + d1 * n[1]) + d2 * n[2];
    const sw_v8f a0 = p[0] - o0, a1 = p[1] - o1, a2 = p[2] - o2;
    const sw_v8f num = (a0 * n[0] + a1 * n[1]) + a2 * n[2];
    const sw_v8f t = num / den;
    const sw_v8f q0 = (o0 + t * d0) - p[0], q1 = (o1 + t * d1) - p[1], q2 = (o2 + t * d2) - p[2];
    const sw_v8f qq = (q0 * q0 + q1 * q1) + q2 * q2;
    const sw_v8f rho2 = qq / rr;
    sw_v8i cov = (den != 0.0f) & (t >= 0.0f) & (t <= 1.0f) & (rho2 <= 1.0f);
    if (cull) cov &= ~(den > 0.0f);
    memcpy(t_out, &t, sizeof t);
    memcpy(rho2_out, &rho2, sizeof rho2);
#if defined(__SSE__)
    __m128 lo, hi; /* the lanes' sign bits, four at a time (SSE: every x86-64) */
    memcpy(&lo, &cov, sizeof lo);
    memcpy(&hi, (const char *)&cov + sizeof lo, sizeof hi);
    return (unsigned)_mm_movemask_ps(lo) | (unsigned)_mm_movemask_ps(hi) << 4;
#else
    unsigned bits = 0;
    for (int l = 0; l < 8; l++) bits |= (unsigned)(cov[l] & 1) << l;
    return bits;
#endif
}

SW_RASTER_CLONES
static void raster_tile(sw_context *c, sw_target *tg, const sw_draw_job *job, int tile, uint64_t *gen_out,
                        uint64_t *pass_out)
{
    const spr_draw_desc *d = job->d;
    const spr_pass_state *s = &d->state;
    const int W = c->base.view.width;
    const int tx0 = (tile % job->tiles_x) * SW_TILE, ty0 = (tile / job->tiles_x) * SW_TILE;
    const spr_fixed_planes pl = sw_fixed_planes(tg);
    const float *z_near = d->depth_mask ? SW_F(&c->targets[d->mask_target], DEPTH) : NULL;
    uint64_t gen = 0, passed = 0;
    const float ks = spr_draw_kernel_scale(d);
    if (job->bin_start[tile] < job->bin_start[tile + 1]) sw__tile_fill(c, tg, tile); /* its pending clear, into the cache it is drawn in */
    for (uint32_t e = job->bin_start[tile]; e < job->bin_start[tile + 1]; e++) {
        const sw_bin_entry *be = &job->bin[e];
        const uint32_t sid = be->sid;
        int x0 = be->x0 > tx0 ? be->x0 : tx0, y0 = be->y0 > ty0 ? be->y0 : ty0;
        int x1 = be->x1 < tx0 + SW_TILE - 1 ? be->x1 : tx0 + SW_TILE - 1;
        int y1 = be->y1 < ty0 + SW_TILE - 1 ? be->y1 : ty0 + SW_TILE - 1;
        const float *p = be->p, *n = be->n;
        const float r = be->r;
        float el[4] = {0.0f, 0.0f, 0.0f, r};
        if (d->cloud->ell) spr_draw_ellipse(d, sid - d->id_base, r, el); /* elliptical: looked up, the bin keeps its line */
        if (el[3] == r && !c->scalar) { /* a disk (spr_ray_ellipse takes spr_ray_disk): 8 pixels of a row at once */
            const float rr = r * r;
            enum { BATCH = 8 }; /* blocks tested before their fragments: their divisions overlap */
            float t[BATCH][8], rho2[BATCH][8];
            unsigned bits[BATCH];
            int bx[BATCH], by[BATCH], nb = 0;
            for (int y = y0; y <= y1; y++)
                for (int x = x0; x <= x1; x += 8) {
                    bits[nb] = disk_lanes(c, x, y, p, n, rr, s->cull_backfaces, t[nb], rho2[nb]);
                    if (x1 - x < 7) bits[nb] &= (2u << (x1 - x)) - 1u; /* lanes past x1 */
                    bx[nb] = x, by[nb] = y;
                    if (++nb < BATCH && !(y == y1 && x + 8 > x1)) continue;
                    for (int k = 0; k < nb; k++)
                        for (unsigned m = bits[k]; m; m &= m - 1) {
                            const int l = __builtin_ctz(m);
                            fragment_at(c, d, &pl, z_near, ks, be, bx[k] + l, by[k], t[k][l], rho2[k][l], &gen, &passed);
                        }
                    nb = 0;
                }
            continue;
        }
        for (int y = y0; y <= y1; y++) {
            for (int x = x0; x <= x1; x++) {
                size_t pix = (size_t)y * W + x;
                const float *ray = c->ray + 6 * pix;
                float t, rho2, rho;
                if (!spr_splat_covers(ray, ray + 3, p, n, el, r, s->cull_backfaces, 0, 0.0f, s->eps_t, &t, &rho2, &rho)) continue;
                fragment_at(c, d, &pl, z_near, ks, be, x, y, t, rho2, &gen, &passed);
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
    sw_target *tg = &c->targets[target]; /* a pending tile is filled where a tile with splats is drawn (raster_tile) */
    if (d->depth_mask) sw__target(c, d->mask_target); /* read by the tiles: its pending tiles first */
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
            if (d->indices && i + SW_PREFETCH < hi) { /* a gather from the cloud (groups, back-to-front orders): its lines ahead of time */
                const size_t q = d->indices[i + SW_PREFETCH];
                __builtin_prefetch(cl->pos + 3 * q), __builtin_prefetch(cl->nrm + 3 * q), __builtin_prefetch(cl->color + 3 * q);
                __builtin_prefetch(cl->radius + q), __builtin_prefetch(cl->alpha + q);
            }
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
