/* sw_composite.c — composite operations on the CPU: the loop over pixels
 * around the per-pixel functions of the composite table (SPR_COMPOSITE_LIST
 * in spr_backend.h, spr_comp_* in arith/composite.h).  Every op of the table
 * writes colour and depth; the output's test plane, when it has one,
 * receives the depth, as gl_FragDepth does in GL.
 */
#include "sw_internal.h"
#include "spr_fragment.h"

#include <stdlib.h>
#include <string.h>

/* One pixel loop per op of the table, so each op's function is inlined.
 * The pixels go by bands of SW_TILE rows (contiguous runs of bands a
 * thread), row by row.  Banded (every op but the prefix op, whose lists
 * are indexed by the pixel): the pixel index of the inputs is relative to
 * the band, so an input's tile still pending the zero clear is read from
 * the context's band of that clear (zband) instead of being filled first:
 * a tile no draw touched costs no memory traffic.  An input pending another
 * clear gets its band's pending tiles filled first. */
typedef struct sw_comp_io {
    const spr_composite_desc *cd;
    const float *prm;
    const float *const *color, *const *depth, *const *opac, *const *normal; /* the inputs' planes, whole */
    float *ocolor, *odepth, *otest, *onormal;
    int W, H;
    const spr_frag_lists *lists;
    const uint32_t *nbr;
    size_t nbr_words;
    spr_probe *probe;
    const sw_context *c;
    sw_target *const *in; /* the inputs' targets */
    int banded;
} sw_comp_io;
#define SW__COMP_LOOP(e, fn, max_in, reads, writes, summary)                                                       \
    static void comp_##fn(const sw_comp_io *io, int threads)                                                      \
    {                                                                                                             \
        const int W = io->W, H = io->H, K = io->cd->n_inputs, tiles_x = (W + SW_TILE - 1) / SW_TILE;              \
        const int bands = (H + SW_TILE - 1) / SW_TILE;                                                            \
        const float *const *zb = (const float *const *)io->c->zband;                                              \
        _Pragma("omp parallel num_threads(threads)")                                                              \
        {                                                                                                         \
            unsigned fp = sw_fp_enter();                                                                          \
            const float *col[SPR_MAX_COMPOSITE_INPUTS], *dep[SPR_MAX_COMPOSITE_INPUTS];                           \
            const float *opa[SPR_MAX_COMPOSITE_INPUTS], *nor[SPR_MAX_COMPOSITE_INPUTS];                           \
            _Pragma("omp for schedule(static)")                                                                   \
            for (int band = 0; band < bands; band++) {                                                            \
                const int y0 = band * SW_TILE, y1 = y0 + SW_TILE < H ? y0 + SW_TILE : H;                          \
                const size_t base = io->banded ? (size_t)y0 * W : 0; /* the inputs' index origin */               \
                if (io->banded)                                                                                   \
                    for (int k = 0; k < K; k++)                                                                   \
                        if (io->in[k]->pending && !io->in[k]->zero_clear)                                         \
                            for (int tx = 0; tx < tiles_x; tx++) sw__tile_fill(io->c, io->in[k], band * tiles_x + tx); \
                for (int y = y0; y < y1; y++)                                                                     \
                    for (int tx = 0; tx < tiles_x; tx++) {                                                        \
                        const int tile = band * tiles_x + tx;                                                     \
                        for (int k = 0; k < K; k++) {                                                             \
                            const sw_target *in = io->in[k];                                                      \
                            const int z = in->pending && in->zero_clear && in->tpend[tile]; /* never when not banded */ \
                            col[k] = !io->color[k] ? NULL : z ? zb[SPR_PLANE_COLOR] : io->color[k] + 4 * base;     \
                            dep[k] = !io->depth[k] ? NULL : z ? zb[SPR_PLANE_DEPTH] : io->depth[k] + base;         \
                            opa[k] = !io->opac[k] ? NULL : z ? zb[SPR_PLANE_OPACITY] : io->opac[k] + base;         \
                            nor[k] = !io->normal[k] ? NULL : z ? zb[SPR_PLANE_NORMAL] : io->normal[k] + 4 * base;  \
                        }                                                                                         \
                        const int x0 = tx * SW_TILE, x1 = x0 + SW_TILE < W ? x0 + SW_TILE : W;                    \
                        for (int x = x0; x < x1; x++) {                                                           \
                            const size_t i = (size_t)y * W + x;                                                   \
                            spr_pixel_in px = {.color = col, .depth = dep, .opacity = opa, .normal = nor,          \
                                               .env = io->cd->env, .lists = io->lists, .nbr = io->nbr,            \
                                               .nbr_words = io->nbr_words, .i = i - base, .x = x, .y = y};        \
                            if (io->probe && x == io->probe->x && y == io->probe->y) px.probe = io->probe;        \
                            float d, on[4];                                                                       \
                            spr_comp_##fn(&px, K, io->cd->eps_t, io->cd->background, io->prm, io->ocolor + 4 * i,  \
                                          on, &d);                                                                \
                            io->odepth[i] = d;                                                                    \
                            if (io->otest) io->otest[i] = d;                                                      \
                            if (io->onormal)                                                                      \
                                for (int ch = 0; ch < 4; ch++) io->onormal[4 * i + ch] = on[ch];                  \
                        }                                                                                         \
                    }                                                                                             \
            }                                                                                                     \
            sw_fp_leave(fp);                                                                                      \
        }                                                                                                         \
    }
SPR_COMPOSITE_LIST(SW__COMP_LOOP)
#undef SW__COMP_LOOP

typedef void (*sw_comp_loop)(const sw_comp_io *, int);
static const sw_comp_loop comp_loops[SPR_COMP__COUNT] = {
#define SW__COMP_FN(e, fn, max_in, reads, writes, summary) comp_##fn,
    SPR_COMPOSITE_LIST(SW__COMP_FN)
#undef SW__COMP_FN
};

/* The zero clear's band of the planes a composite reads, for this width. */
static spr_result zero_band(sw_context *c)
{
    const int W = c->base.view.width;
    static const spr_plane read[4] = {SPR_PLANE_COLOR, SPR_PLANE_DEPTH, SPR_PLANE_OPACITY, SPR_PLANE_NORMAL};
    if (c->zband_w == W) return SPR_OK;
    c->zband_w = 0;
    for (int q = 0; q < 4; q++) {
        const spr_plane p = read[q];
        const spr_plane_info *pi = spr_plane_info_of(p);
        const size_t n = (size_t)W * SW_TILE * (size_t)pi->channels;
        free(c->zband[p]);
        if (!(c->zband[p] = malloc(n * sizeof(float)))) return spr__fail(&c->base.err, SPR_E_NOMEM, "cpu: out of memory for a composite");
        static const float zero[4] = {0, 0, 0, 0};
        for (size_t k = 0; k < n; k++) {
            const uint32_t w = sw__clear_word(p, zero, (int)(k % (size_t)pi->channels)); /* the zero clear, as pend_all records it */
            memcpy(&c->zband[p][k], &w, 4);
        }
    }
    c->zband_w = W;
    return SPR_OK;
}

spr_result sw__composite(spr_backend *b, const spr_composite_desc *cd)
{
    sw_context *c = sw_ctx(b);
    const int K = cd->n_inputs;
    const int banded = cd->op != SPR_COMP_PREFIX;
    spr_result r = banded ? zero_band(c) : SPR_OK;
    if (r) return r;
    const float *color[SPR_MAX_COMPOSITE_INPUTS], *depth[SPR_MAX_COMPOSITE_INPUTS], *opac[SPR_MAX_COMPOSITE_INPUTS];
    const float *normal[SPR_MAX_COMPOSITE_INPUTS];
    sw_target *in[SPR_MAX_COMPOSITE_INPUTS];
    for (int k = 0; k < K; k++) {
        in[k] = banded ? &c->targets[cd->inputs[k]] : sw__target(c, cd->inputs[k]);
        color[k] = SW_F(in[k], COLOR);   /* NULL where absent: the prefix op reads lists */
        depth[k] = SW_F(in[k], DEPTH);
        opac[k] = SW_F(in[k], OPACITY);   /* NULL where absent: read only by ops whose row says so */
        normal[k] = SW_F(in[k], NORMAL);  /* NULL where absent: read only when the parameters ask */
    }
    /* the output: every pixel of colour, depth, test and normal is written; other planes need their clear first */
    sw_target *out = &c->targets[cd->output];
    const unsigned written = SPR_PLANE_BIT(SPR_PLANE_COLOR) | SPR_PLANE_BIT(SPR_PLANE_DEPTH) | SPR_PLANE_BIT(SPR_PLANE_TEST) | SPR_PLANE_BIT(SPR_PLANE_NORMAL);
    if (out->planes & ~written) sw__target(c, cd->output);
    static const float no_params[SPR_PRM_COUNT];
    sw_comp_io io = {cd, cd->params ? cd->params : no_params, color, depth, opac, normal,
                     SW_F(out, COLOR), SW_F(out, DEPTH), SW_F(out, TEST), SW_F(out, NORMAL), b->view.width, b->view.height,
                     NULL, NULL, 0, b->probe, c, in, banded};
    if (cd->op == SPR_COMP_PREFIX) { /* input 0's lists and the rectangles' neighbours (checked by core) */
        io.lists = &c->targets[cd->inputs[0]].lists;
        if (!io.lists->first) return spr__fail(&b->err, SPR_E_ARG, "cpu: prefix: target %d has no fragment lists", cd->inputs[0]);
        io.nbr = cd->rects->nbr;
        io.nbr_words = spr_rects_words(cd->rects->n);
    }
    comp_loops[cd->op](&io, c->threads);
    for (int k = 0; k < K; k++)
        if (in[k]->pending && !in[k]->zero_clear) in[k]->pending = 0; /* every tile of theirs filled */
    out->pending = 0; /* every tile written or filled */
    if (out->tpend) memset(out->tpend, 0, out->ntiles);
    return SPR_OK;
}
