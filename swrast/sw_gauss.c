/* sw_gauss.c — the Gaussian splatting references on the CPU (SPEC §10):
 *
 *   preprocess  one record per Gaussian (arith/gauss.h), in parallel;
 *   raster      the 16×16 tiles in parallel, each pixel of a tile running
 *               the front-to-back loop over its tile's sorted list
 *               (spr_gauss_pixel) and writing the planes its target has;
 *   draw        gauss-blend: the ellipses in the given order binned to the
 *               same tiles (each tile keeps the order), each pixel blending
 *               its fragments in that order with the reference's
 *               premultiplied `over` (spr_fixed.h).
 * Tiles are disjoint and every pixel sees its Gaussians in the one order,
 * so nothing depends on the thread count.
 */
#include "sw_internal.h"
#include "spr_fixed.h"
#include "spr_util.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

spr_result sw__gauss_preprocess(spr_backend *b, const spr_gauss_desc *d, float *rec)
{
    sw_context *c = sw_ctx(b);
#pragma omp parallel num_threads(c->threads)
    {
        unsigned fp = sw_fp_enter();
#pragma omp for schedule(static)
        for (long i = 0; i < (long)d->n; i++)
            spr_gauss_preprocess(d->prm, d->mu + 3 * i, d->q + 4 * i, d->s + 3 * i, d->opacity[i], d->color + 3 * i,
                                 rec + (size_t)i * SPR_GREC_FLOATS);
        sw_fp_leave(fp);
    }
    return SPR_OK;
}

/* A tile's records copied in list order before its pixels walk them (a tile's list lies scattered in file order):
 * the pixels read them in sequence, through a local list 0 … m − 1 (ids) and local ranges (range[t] = 0, range[t + 1]
 * = m), the raster's and the backward's alike.  One per thread; take returns −1 out of memory. */
typedef struct tile_copy { float *rec; uint32_t *ids, *range; size_t cap; } tile_copy;
static int tile_copy_init(tile_copy *tc, int nt)
{
    memset(tc, 0, sizeof *tc);
    tc->range = calloc((size_t)nt + 1, sizeof *tc->range);
    return tc->range ? 0 : -1;
}
static int tile_copy_take(tile_copy *tc, const float *rec, const uint32_t *range, const uint32_t *list, int t)
{
    const uint32_t first = range[t], m = range[t + 1] - first;
    if (m > tc->cap) {
        free(tc->rec), free(tc->ids);
        tc->cap = m;
        tc->rec = malloc(m * SPR_GREC_FLOATS * sizeof *tc->rec), tc->ids = malloc(m * sizeof *tc->ids);
        if (!tc->rec || !tc->ids) { tc->cap = 0; return -1; }
        for (uint32_t k = 0; k < m; k++) tc->ids[k] = k;
    }
    for (uint32_t k = 0; k < m; k++)
        memcpy(tc->rec + (size_t)k * SPR_GREC_FLOATS, rec + (size_t)list[first + k] * SPR_GREC_FLOATS, SPR_GREC_FLOATS * sizeof *tc->rec);
    tc->range[t] = 0, tc->range[t + 1] = m;
    return 0;
}
static void tile_copy_free(tile_copy *tc) { free(tc->rec), free(tc->ids), free(tc->range); }

spr_result sw__gauss_raster(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st)
{
    sw_context *c = sw_ctx(b);
    sw_target *tg = sw__target(c, target);
    const int W = b->view.width, H = b->view.height;
    const int gx = (int)d->prm[SPR_GPRM_GX], gy = (int)d->prm[SPR_GPRM_GY], two = d->prm[SPR_GPRM_MODE] == SPR_GMODE_2D;
    float *color = SW_F(tg, COLOR), *trans = SW_F(tg, TRANS), *idepth = SW_F(tg, INVDEPTH), *sdepth = SW_F(tg, SURFDEPTH),
          *normal = SW_F(tg, NORMAL);
    uint32_t *contrib = SW_U(tg, CONTRIB);
    float *D = two ? sdepth : idepth;
    uint64_t visited = 0, blended = 0;
    spr_probe *probe = b->probe;
    const int nt = gx * gy;
    int failed = 0;
#pragma omp parallel num_threads(c->threads) reduction(+ : visited, blended) reduction(| : failed)
    {
        unsigned fp = sw_fp_enter();
        /* each tile's records copied in list order (tile_copy); the tile of the probed pixel keeps the global ones,
         * so that its notes name the Gaussians */
        tile_copy tc;
        failed |= tile_copy_init(&tc, nt);
#pragma omp for schedule(dynamic, 1)
        for (int t = 0; t < nt; t++) {
            if (failed) continue;
            const int i0 = (t % gx) * 16, j0 = (t / gx) * 16;
            const int probed = probe && probe->x >= i0 && probe->x < i0 + 16 && H - 1 - probe->y >= j0 && H - 1 - probe->y < j0 + 16;
            if (!probed && tile_copy_take(&tc, d->rec, d->range, d->list, t)) { failed = 1; continue; }
            for (int j = j0; j < j0 + 16 && j < H; j++)
                for (int i = i0; i < i0 + 16 && i < W; i++) {
                    const int y = H - 1 - j;
                    const size_t pix = (size_t)y * W + (size_t)i;
                    spr_pixel_in px = {.grec = tc.rec, .granges = tc.range, .glist = tc.ids, .i = pix, .x = i, .y = y};
                    if (probed) px.grec = d->rec, px.granges = d->range, px.glist = d->list;
                    if (probe && i == probe->x && y == probe->y) px.probe = probe;
                    float o[4], aux[4], nrm[4];
                    visited += (uint64_t)spr_gauss_pixel(&px, d->prm, d->background, o, aux, nrm);
                    blended += (uint64_t)aux[3];
                    memcpy(color + 4 * pix, o, sizeof o);
                    if (trans) trans[pix] = aux[0];
                    if (contrib) contrib[pix] = (uint32_t)aux[1];
                    if (D) D[pix] = aux[2];
                    if (normal && two) memcpy(normal + 4 * pix, nrm, sizeof nrm);
                }
        }
        tile_copy_free(&tc);
        sw_fp_leave(fp);
    }
    if (failed) return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for a tile's Gaussians");
    st->splats = d->n;
    st->generated = visited;
    st->passed = blended;
    return SPR_OK;
}

/* gauss-blend reads of each record, copied in the order of the draw (so that
 * the tiles, whose entries follow that order, read them in sequence instead
 * of at random in file order): centre, conic, opacity, colour, box. */
enum { BL_M = 0, BL_CONIC = 2, BL_OPACITY = 5, BL_COLOR = 6, BL_BOX = 9, BL_FLOATS = 13 };

/* gauss-blend: the tiles of the ellipse at position e of the order (its pixel box's tiles). */
static void box_tiles(const void *user, size_t e, int r[4])
{
    const float *R = (const float *)user + e * BL_FLOATS;
    const int i0 = (int)R[BL_BOX], j0 = (int)R[BL_BOX + 1], i1 = (int)R[BL_BOX + 2], j1 = (int)R[BL_BOX + 3];
    if (i1 < i0 || j1 < j0) r[0] = r[1] = r[2] = r[3] = 0;
    else r[0] = i0 / 16, r[1] = j0 / 16, r[2] = i1 / 16 + 1, r[3] = j1 / 16 + 1;
}

/* Where in a row gauss-blend's cut (power < −CUT) can let a pixel through:
 * the ellipse A·dx² + 2B·dx·dy + C·dy² ≤ 2·CUT, d = m − (i, j), solved in double
 * for each row with its bound widened (2.02·CUT and one pixel each side) beyond
 * what the float power's rounding can move.  Pixels outside the span have
 * power < −4.5 in float too, so skipping them changes no bit; the spans are
 * used only for well-conditioned conics (A, C > 0, |B| ≤ 0.999·sqrt(AC): the
 * float power's error then stays below 0.3% of its value) near the image
 * (centre within 10^6 pixels, where m's rounding is below 0.06 pixel). */
typedef struct row_span { int ok; double A, B, C, mx, my, Q; } row_span;
static row_span span_of(const float *R, float cut)
{
    row_span rs = {0, R[BL_CONIC], R[BL_CONIC + 1], R[BL_CONIC + 2], R[BL_M], R[BL_M + 1], 2.02 * (double)cut};
    rs.ok = rs.A > 0.0 && rs.C > 0.0 && isfinite(rs.A * rs.C) && rs.B * rs.B <= 0.998 * rs.A * rs.C && fabs(rs.mx) < 1e6 && fabs(rs.my) < 1e6;
    return rs;
}
static int row_range(const row_span *rs, int j, int *lo, int *hi)
{
    const double dy = rs->my - j, Q = rs->Q;
    const double disc = rs->B * rs->B * dy * dy - rs->A * (rs->C * dy * dy - Q);
    if (disc < 0.0) return 0;
    const double sq = sqrt(disc), dlo = (-rs->B * dy - sq) / rs->A, dhi = (-rs->B * dy + sq) / rs->A; /* dx = m.x − i */
    const double ilo = floor(rs->mx - dhi) - 1.0, ihi = ceil(rs->mx - dlo) + 1.0;
    if (ilo > *lo) *lo = (int)ilo;
    if (ihi < *hi) *hi = (int)ihi;
    return *lo <= *hi;
}

/* gauss-blend: the positions in the order binned per tile, in order (spr__gauss_bin). */
spr_result sw__gauss_draw(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st)
{
    sw_context *c = sw_ctx(b);
    sw_target *tg = sw__target(c, target);
    const int W = b->view.width, H = b->view.height;
    const int gx = (W + 15) / 16, gy = (H + 15) / 16, nt = gx * gy;
    uint32_t *start = NULL, *bin = NULL;
    float *cg = spr__big_alloc(d->count * BL_FLOATS * sizeof *cg);
    if (!cg) return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for %zu Gaussians", d->count);
#pragma omp parallel for num_threads(c->threads) schedule(static)
    for (long e = 0; e < (long)d->count; e++) {
        const float *R = d->rec + (size_t)d->order[e] * SPR_GREC_FLOATS;
        float *o = cg + (size_t)e * BL_FLOATS;
        memcpy(o + BL_M, R + SPR_GREC_M, 2 * sizeof *o);
        memcpy(o + BL_CONIC, R + SPR_GREC_CONIC, 3 * sizeof *o);
        o[BL_OPACITY] = R[SPR_GREC_OPACITY];
        memcpy(o + BL_COLOR, R + SPR_GREC_COLOR, 3 * sizeof *o);
        memcpy(o + BL_BOX, R + SPR_GREC_BOX, 4 * sizeof *o);
    }
    spr_result r = spr__gauss_bin(d->count, box_tiles, cg, gx, gy, c->threads, &start, &bin, &b->err);
#define BOX(e, k) ((int)cg[(size_t)(e) * BL_FLOATS + BL_BOX + (k)])
    uint64_t generated = 0, passed = 0;
    const spr_pass_state *s = &d->state;
    spr_probe *probe = b->probe;
    float *color = SW_F(tg, COLOR);
    if (r) goto done;
#pragma omp parallel num_threads(c->threads) reduction(+ : generated, passed)
    {
        unsigned fp = sw_fp_enter();
#pragma omp for schedule(dynamic, 1)
        for (int t = 0; t < nt; t++) {
            const int i0 = (t % gx) * 16, j0 = (t / gx) * 16;
            for (uint32_t k = start[t]; k < start[t + 1]; k++) {
                const uint32_t seq = bin[k];
                const float *R = cg + (size_t)seq * BL_FLOATS;
                if (k + 4 < start[t + 1]) __builtin_prefetch(cg + (size_t)bin[k + 4] * BL_FLOATS); /* a tile's entries lie far apart in the order */
                const int a0 = BOX(seq, 0) > i0 ? BOX(seq, 0) : i0, a1 = BOX(seq, 2) < i0 + 15 ? BOX(seq, 2) : i0 + 15;
                const int b0 = BOX(seq, 1) > j0 ? BOX(seq, 1) : j0, b1 = BOX(seq, 3) < j0 + 15 ? BOX(seq, 3) : j0 + 15;
                const row_span rs = span_of(R, d->prm[SPR_GPRM_CUT]);
                for (int j = b0; j <= b1; j++) {
                    generated += (uint64_t)(a1 - a0 + 1); /* every pixel of the box is a fragment, as GL's quad gives it */
                    int lo = a0, hi = a1;
                    if (rs.ok && !row_range(&rs, j, &lo, &hi)) continue;
                    for (int i = lo; i <= hi; i++) {
                        float src[4] = {0, 0, 0, 0}, power, alpha;
                        const int hit = spr_gauss_blend_frag(d->prm, R[BL_M], R[BL_M + 1], R[BL_CONIC], R[BL_CONIC + 1], R[BL_CONIC + 2],
                                                             R[BL_OPACITY], R + BL_COLOR, (float)i, (float)j, src, &power, &alpha);
                        if (!hit) continue;
                        passed++;
                        const int y = H - 1 - j;
                        if (probe && i == probe->x && y == probe->y) { /* pixel history: t = power, ρ = α */
                            spr_probe_frag f = {seq, d->order[seq], power, alpha, 0.0f, {src[0], src[1], src[2], src[3]}, alpha};
                            spr_probe_add_frag(probe, &f);
                        }
                        spr_blend4(s, src, color + 4 * ((size_t)y * W + (size_t)i));
                    }
                }
            }
        }
        sw_fp_leave(fp);
    }
done:
#undef BOX
    free(start);
    free(bin);
    free(cg);
    st->splats = d->count;
    st->generated = generated;
    st->passed = passed;
    return r;
}

/* gauss3d's backward (SPEC 10.10): tiles in batches whose entries' partials
 * fit `batch` (spr_gauss_bwd_desc; 2^21 entries, 128 MiB, by default); in a
 * batch, each tile one walk over its pixels in row-major order from the top
 * row (spr_gauss_tile_bwd, in one call), tiles in parallel (disjoint entries); then each
 * Gaussian adds its entries' partials of the batch in order to its sums
 * (spr_gauss_gather), Gaussians in parallel; after the last batch, each
 * Gaussian's chain (spr_gauss_preprocess3d_bwd).  Nothing depends on the
 * thread count: every sum has one order. */
spr_result sw__gauss_backward(spr_backend *b, const spr_gauss_bwd_desc *d, float *sums, float *out)
{
    sw_context *c = sw_ctx(b);
    const int gx = (int)d->prm[SPR_GPRM_GX], nt = gx * (int)d->prm[SPR_GPRM_GY];
    const size_t cap = d->batch ? d->batch : (size_t)1 << 21, n = d->n;
    memset(sums, 0, n * SPR_GPART_FLOATS * sizeof *sums);
    const size_t most = spr_gauss_bwd_batch_most(d->range, nt, cap);
    int failed_any = 0, over_tile = -1, over_pix = 0;
    float *part = spr__big_alloc((most ? most : 1) * SPR_GPART_FLOATS * sizeof *part);
    if (!part) return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for the partials of %zu list entries", most);
    for (int t0 = 0, t1; t0 < nt; t0 = t1) {
        t1 = spr_gauss_bwd_batch_end(d->range, nt, t0, cap);
        const uint32_t base = d->range[t0], end = d->range[t1];
        memset(part, 0, (size_t)(end - base) * SPR_GPART_FLOATS * sizeof *part);
        int failed = 0;
#pragma omp parallel num_threads(c->threads) reduction(| : failed)
        {
            unsigned fp = sw_fp_enter();
            /* each tile's records copied in list order first, as the raster does (tile_copy): its local entry k is the
             * tile's entry range[t] + k, so its partials are those from part + (range[t] − base) */
            tile_copy tc;
            failed |= tile_copy_init(&tc, nt);
            uint32_t *state = malloc(SPR_GBS_FLOATS * sizeof *state); /* a tile's walk, its blended Gaussians held */
            if (!state) failed = 1;
#pragma omp for schedule(dynamic, 1)
            for (int t = t0; t < t1; t++) {
                if (failed) continue;
                if (tile_copy_take(&tc, d->rec, d->range, d->list, t)) { failed = 1; continue; }
                const uint32_t first = d->range[t];
                memset(state, 0, SPR_GBS_SE * sizeof *state); /* the rest is written before it is read */
                spr_pixel_in px = {.grec = tc.rec, .granges = tc.range, .glist = tc.ids, .gup = d->up, .gpart = part + (size_t)(first - base) * SPR_GPART_FLOATS,
                                   .gpart_base = 0, .gbs = state};
                spr_gauss_tile_bwd_all(&px, d->prm, d->background, t, 0, 256);
                const int over = (int)state[SPR_GBS_OVER];
#pragma omp critical(sw_gauss_over)
                if (over && (over_tile < 0 || t < over_tile)) over_tile = t, over_pix = over - 1;
            }
            free(state);
            tile_copy_free(&tc);
#pragma omp for schedule(static)
            for (long G = 0; G < (long)n; G++) {
                spr_pixel_in px = {.gpart = part, .gpart_base = base, .gcsr = d->csr};
                spr_gauss_gather(&px, (int)d->csr_start[G], (int)d->csr_start[G + 1], (int)base, (int)end, sums + (size_t)G * SPR_GPART_FLOATS);
            }
            sw_fp_leave(fp);
        }
        if ((failed_any = failed) || over_tile >= 0) break;
    }
    free(part);
    if (failed_any) return spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for a tile's Gaussians");
    if (over_tile >= 0) return spr_gauss_bwd_over(&b->err, "cpu", gx, over_tile, over_pix);
#pragma omp parallel num_threads(c->threads)
    {
        unsigned fp = sw_fp_enter();
#pragma omp for schedule(static)
        for (long G = 0; G < (long)n; G++)
            spr_gauss_preprocess3d_bwd(d->prm, d->mu + 3 * G, d->q + 4 * G, d->s + 3 * G, sums + (size_t)G * SPR_GPART_FLOATS,
                                       out + (size_t)G * SPR_GOUT_FLOATS);
        sw_fp_leave(fp);
    }
    return SPR_OK;
}
