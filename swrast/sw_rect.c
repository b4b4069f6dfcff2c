/* sw_rect.c — rectangle draws (domain primitives, SPEC §7.7) on the CPU.
 *
 *   1. rect[i] = the pixel rectangle of the i-th submitted rectangle
 *                (spr_rect_pixel_rect, shared with the GL backend)
 *   2. per work unit (a 32-pixel-wide column of the rectangles' union, cut
 *      in bands of B rows: B = 32, or fewer when the union is small, so a
 *      draw of one small rectangle still keeps every thread busy), in
 *      parallel: for i in submission order, for each pixel of rect ∩ unit: ray–rectangle hit → texture sample → alpha
 *      test → test value → depth test → blend/write (core/render/arith/, sw_fixed.h)
 * List draws (the prefix method) run step 2 twice: once counting each
 * pixel's fragments, then, after a prefix sum, filling the nodes — each
 * pixel's fragments stay contiguous and in submission order; the prefix
 * op sorts them anyway.  Units are disjoint and every pixel sees the
 * rectangles in submission order, so the result does not depend on the
 * thread count or on B.
 */
#include "sw_internal.h"
#include "sw_fixed.h"

#include <stdlib.h>
#include <string.h>

void sw__lists_free(spr_frag_lists *l)
{
    free(l->first);
    free(l->t);
    free(l->prim);
    free(l->src);
    memset(l, 0, sizeof *l);
}

typedef struct sw_rect_job {
    const spr_rect_draw_desc *d;
    const int32_t *rect;   /* 4 per submitted rectangle, x0 = −1: off screen */
    size_t n;
    int ux0, uy0;          /* the union's top-left pixel */
    int cols, band;        /* units: cols 32-pixel columns by bands of `band` rows */
    int phase;             /* 0: draw; 1: count list nodes; 2: fill list nodes */
    uint32_t *fill;        /* phase 1: per-pixel counts; phase 2: per-pixel nodes written */
} sw_rect_job;

static inline uint32_t rect_at(const spr_rect_draw_desc *d, size_t i) { return d->indices ? d->indices[i] : (uint32_t)i; }

static void rect_unit(sw_context *c, sw_target *tg, const sw_rect_job *job, int unit, uint64_t *gen_out, uint64_t *pass_out)
{
    const spr_rect_draw_desc *d = job->d;
    const spr_pass_state *s = &d->state;
    const spr_rects *rs = d->rects;
    const int W = c->base.view.width;
    const int tx0 = job->ux0 + (unit % job->cols) * SW_TILE, ty0 = job->uy0 + (unit / job->cols) * job->band;
    const int tx1 = tx0 + SW_TILE - 1, ty1 = ty0 + job->band - 1;
    const spr_fixed_planes pl = sw_fixed_planes(tg);
    spr_frag_lists *L = &tg->lists;
    const spr_pixel_in px = {.texels = rs->texels};
    const int linear = d->sampling != SPR_SAMPLE_NEAREST;
    spr_probe *probe = c->base.probe;
    uint64_t gen = 0, passed = 0;
    for (size_t i = 0; i < job->n; i++) {
        const int32_t *rc = job->rect + 4 * i;
        if (rc[0] < 0 || rc[2] < tx0 || rc[0] > tx1 || rc[3] < ty0 || rc[1] > ty1) continue;
        const uint32_t k = rect_at(d, i);
        const float *R = rs->f + (size_t)k * SPR_RECT_FLOATS;
        const uint32_t *I = rs->i + (size_t)k * SPR_RECTI_COUNT;
        int x0 = rc[0] > tx0 ? rc[0] : tx0, y0 = rc[1] > ty0 ? rc[1] : ty0;
        int x1 = rc[2] < tx1 ? rc[2] : tx1;
        int y1 = rc[3] < ty1 ? rc[3] : ty1;
        for (int y = y0; y <= y1; y++) {
            for (int x = x0; x <= x1; x++) {
                const size_t pix = (size_t)y * W + x;
                const float *ray = c->ray + 6 * pix;
                float t, su, sv, tx[4], src[4];
                if (!spr_rect_hit(ray, ray + 3, R, &t, &su, &sv)) continue;
                spr_rect_sample(&px, R, (int)I[SPR_RECTI_TW], (int)I[SPR_RECTI_TH], (int)I[SPR_RECTI_OFF], linear, su, sv, tx);
                if (!spr_rect_alpha_passes(tx[3], d->alpha_ref)) continue;
                gen++;
                spr_rect_fragment((int)d->output, tx, src);
                const float z = spr_test_depth((int)s->depth_value, s->eps_t, 0.0f, 1.0f, 1.0f, 1.0f, t, 0.0f);
                if (probe && job->phase != 1 && x == probe->x && y == probe->y) { /* pixel history */
                    spr_probe_frag f = {(uint32_t)i, k, t, 0.0f, z, {src[0], src[1], src[2], src[3]}, 0.0f};
                    spr_probe_add_frag(probe, &f);
                }
                if (job->phase == 1) { job->fill[pix]++; continue; }
                if (job->phase == 2) {
                    const size_t node = L->first[pix] + job->fill[pix]++;
                    L->t[node] = t;
                    L->prim[node] = k;
                    memcpy(L->src + 4 * node, src, sizeof src);
                    continue;
                }
                if (!spr_fixed_depth(s, &pl, pix, z)) continue;
                passed++;
                spr_fixed_writes(s, &pl, pix, t, src, k, NULL, NULL);
            }
        }
    }
    *gen_out = gen;
    *pass_out = passed;
}

static void run_units(sw_context *c, sw_target *tg, const sw_rect_job *job, int units, uint64_t *unit_stats)
{
#pragma omp parallel num_threads(c->threads)
    {
        unsigned fp = sw_fp_enter();
#pragma omp for schedule(dynamic, 1)
        for (int u = 0; u < units; u++) rect_unit(c, tg, job, u, &unit_stats[2 * u], &unit_stats[2 * u + 1]);
        sw_fp_leave(fp);
    }
}

spr_result sw__draw_rects(spr_backend *b, int target, const spr_rect_draw_desc *d, spr_draw_stats *st)
{
    sw_context *c = sw_ctx(b);
    sw_target *tg = sw__target(c, target);
    const spr_view *v = &b->view;
    sw__rays(c);
    const size_t n = d->indices ? d->count : d->rects->n, np = (size_t)v->width * (size_t)v->height;
    st->splats = n;
    if (d->list) sw__lists_free(&tg->lists);
    int32_t *rect = malloc((n ? n : 1) * 4 * sizeof(int32_t));
    uint32_t *fill = d->list ? calloc(np, sizeof(uint32_t)) : NULL;
    uint64_t *unit_stats = NULL;
    spr_result res = SPR_OK;
    if (!rect || (d->list && !fill)) goto oom_draw;
    int ux0 = v->width, uy0 = v->height, ux1 = -1, uy1 = -1; /* the union of the on-screen rectangles */
    for (size_t i = 0; i < n; i++) {
        int32_t *rc = rect + 4 * i;
        int x0, y0, x1, y1;
        if (!spr_rect_pixel_rect(v, d->rects->f + (size_t)rect_at(d, i) * SPR_RECT_FLOATS, &x0, &y0, &x1, &y1)) {
            rc[0] = -1;
            continue;
        }
        rc[0] = x0; rc[1] = y0; rc[2] = x1; rc[3] = y1;
        ux0 = x0 < ux0 ? x0 : ux0, uy0 = y0 < uy0 ? y0 : uy0, ux1 = x1 > ux1 ? x1 : ux1, uy1 = y1 > uy1 ? y1 : uy1;
    }
    ux0 -= ux0 % SW_TILE; /* columns on the tile grid: no cache line is written by two units */
    const int cols = ux1 < ux0 ? 0 : (ux1 - ux0 + SW_TILE) / SW_TILE, rows = uy1 < uy0 ? 0 : uy1 - uy0 + 1;
    int band = SW_TILE; /* halved until there are 8 units a thread, or rows of one pixel */
    while (band > 1 && (long)cols * ((rows + band - 1) / band) < 8L * c->threads) band /= 2;
    const int units = cols * ((rows + band - 1) / band);
    if (!(unit_stats = calloc((size_t)(units ? units : 1) * 2, sizeof(uint64_t)))) goto oom_draw;
    sw_rect_job job = {d, rect, n, ux0, uy0, cols ? cols : 1, band, d->list ? 1 : 0, fill};
    run_units(c, tg, &job, units, unit_stats);
    if (d->list) { /* nodes of pixel i at first[i] …, then the fill pass */
        spr_frag_lists *L = &tg->lists;
        uint64_t total = 0;
        if (!(L->first = malloc((np + 1) * sizeof(uint32_t)))) goto oom;
        for (size_t i = 0; i < np; i++) {
            L->first[i] = (uint32_t)total;
            total += fill[i];
            fill[i] = 0;
        }
        if (total > UINT32_MAX / 4) {
            res = spr__fail(&b->err, SPR_E_TOO_LARGE, "cpu: %llu list fragments in one draw", (unsigned long long)total);
            goto done;
        }
        L->first[np] = (uint32_t)total;
        L->n = L->cap = (size_t)total;
        L->t = malloc((total ? total : 1) * sizeof(float));
        L->prim = malloc((total ? total : 1) * sizeof(uint32_t));
        L->src = malloc((total ? total : 1) * 4 * sizeof(float));
        if (!L->t || !L->prim || !L->src) goto oom;
        job.phase = 2;
        memset(unit_stats, 0, (size_t)(units ? units : 1) * 2 * sizeof(uint64_t));
        run_units(c, tg, &job, units, unit_stats);
    }
    for (int u = 0; u < units; u++) {
        st->generated += unit_stats[2 * u];
        st->passed += unit_stats[2 * u + 1];
    }
    if (d->list) st->passed = st->generated; /* every fragment enters its list */
    goto done;
oom_draw:
    res = spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory drawing %zu rectangles", n);
    goto done;
oom:
    sw__lists_free(&tg->lists);
    res = spr__fail(&b->err, SPR_E_NOMEM, "cpu: out of memory for fragment lists");
done:
    free(rect);
    free(unit_stats);
    free(fill);
    return res;
}
