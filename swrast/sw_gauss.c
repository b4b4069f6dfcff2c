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

spr_result sw__gauss_raster(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st)
{
    sw_context *c = sw_ctx(b);
    sw_target *tg = &c->targets[target];
    const int W = b->view.width, H = b->view.height;
    const int gx = (int)d->prm[SPR_GPRM_GX], gy = (int)d->prm[SPR_GPRM_GY], two = d->prm[SPR_GPRM_MODE] == SPR_GMODE_2D;
    float *color = SW_F(tg, COLOR), *trans = SW_F(tg, TRANS), *idepth = SW_F(tg, INVDEPTH), *sdepth = SW_F(tg, SURFDEPTH),
          *normal = SW_F(tg, NORMAL);
    uint32_t *contrib = SW_U(tg, CONTRIB);
    float *D = two ? sdepth : idepth;
    uint64_t visited = 0, blended = 0;
    spr_probe *probe = b->probe;
#pragma omp parallel num_threads(c->threads) reduction(+ : visited, blended)
    {
        unsigned fp = sw_fp_enter();
#pragma omp for schedule(dynamic, 1)
        for (int t = 0; t < gx * gy; t++) {
            const int i0 = (t % gx) * 16, j0 = (t / gx) * 16;
            for (int j = j0; j < j0 + 16 && j < H; j++)
                for (int i = i0; i < i0 + 16 && i < W; i++) {
                    const int y = H - 1 - j;
                    const size_t pix = (size_t)y * W + (size_t)i;
                    spr_pixel_in px = {.grec = d->rec, .granges = d->range, .glist = d->list, .i = pix, .x = i, .y = y};
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
        sw_fp_leave(fp);
    }
    st->splats = d->n;
    st->generated = visited;
    st->passed = blended;
    return SPR_OK;
}

/* gauss-blend: the tiles of the ellipse at position e of the order (its pixel box's tiles). */
typedef struct blend_bins { const float *rec; const uint32_t *order; } blend_bins;
static void box_tiles(const void *user, size_t e, int r[4])
{
    const blend_bins *bb = user;
    const float *R = bb->rec + (size_t)bb->order[e] * SPR_GREC_FLOATS;
    const int i0 = (int)R[SPR_GREC_BOX], j0 = (int)R[SPR_GREC_BOX + 1], i1 = (int)R[SPR_GREC_BOX + 2], j1 = (int)R[SPR_GREC_BOX + 3];
    if (i1 < i0 || j1 < j0) r[0] = r[1] = r[2] = r[3] = 0;
    else r[0] = i0 / 16, r[1] = j0 / 16, r[2] = i1 / 16 + 1, r[3] = j1 / 16 + 1;
}

/* gauss-blend: the positions in the order binned per tile, in order (spr__gauss_bin). */
spr_result sw__gauss_draw(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st)
{
    sw_context *c = sw_ctx(b);
    sw_target *tg = &c->targets[target];
    const int W = b->view.width, H = b->view.height;
    const int gx = (W + 15) / 16, gy = (H + 15) / 16, nt = gx * gy;
    uint32_t *start = NULL, *bin = NULL;
    const blend_bins bb = {d->rec, d->order};
    spr_result r = spr__gauss_bin(d->count, box_tiles, &bb, gx, gy, c->threads, &start, &bin, &b->err);
#define BOX(G, k) ((int)d->rec[(size_t)(G) * SPR_GREC_FLOATS + SPR_GREC_BOX + (k)])
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
                const uint32_t seq = bin[k], G = d->order[seq];
                const float *R = d->rec + (size_t)G * SPR_GREC_FLOATS;
                const int a0 = BOX(G, 0) > i0 ? BOX(G, 0) : i0, a1 = BOX(G, 2) < i0 + 15 ? BOX(G, 2) : i0 + 15;
                const int b0 = BOX(G, 1) > j0 ? BOX(G, 1) : j0, b1 = BOX(G, 3) < j0 + 15 ? BOX(G, 3) : j0 + 15;
                for (int j = b0; j <= b1; j++)
                    for (int i = a0; i <= a1; i++) {
                        float src[4] = {0, 0, 0, 0}, power, alpha;
                        const int hit = spr_gauss_blend_frag(d->prm, R[SPR_GREC_M], R[SPR_GREC_M + 1], R[SPR_GREC_CONIC], R[SPR_GREC_CONIC + 1],
                                                             R[SPR_GREC_CONIC + 2], R[SPR_GREC_OPACITY], R + SPR_GREC_COLOR, (float)i, (float)j, src,
                                                             &power, &alpha);
                        generated++;
                        if (!hit) continue;
                        passed++;
                        const int y = H - 1 - j;
                        if (probe && i == probe->x && y == probe->y) { /* pixel history: t = power, ρ = α */
                            spr_probe_frag f = {seq, G, power, alpha, 0.0f, {src[0], src[1], src[2], src[3]}, alpha};
                            spr_probe_add_frag(probe, &f);
                        }
                        spr_blend4(s, src, color + 4 * ((size_t)y * W + (size_t)i));
                    }
            }
        }
        sw_fp_leave(fp);
    }
done:
#undef BOX
    free(start);
    free(bin);
    st->splats = d->count;
    st->generated = generated;
    st->passed = passed;
    return r;
}
