/* sw_composite.c — composite operations on the CPU: the loop over pixels
 * around the per-pixel functions of the composite table (SPR_COMPOSITE_LIST
 * in spr_backend.h, spr_comp_* in arith/composite.h).  Every op of the table
 * writes colour and depth; the output's test plane, when it has one,
 * receives the depth, as gl_FragDepth does in GL.
 */
#include "sw_internal.h"
#include "spr_fragment.h"

/* One pixel loop per op of the table, so each op's function is inlined. */
typedef struct sw_comp_io {
    const spr_composite_desc *cd;
    const float *prm;
    const float *const *color, *const *depth, *const *opac, *const *normal;
    float *ocolor, *odepth, *otest, *onormal;
    int W;
    const spr_frag_lists *lists;
    const uint32_t *nbr;
    size_t nbr_words;
    spr_probe *probe;
} sw_comp_io;
#define SW__COMP_LOOP(e, fn, max_in, reads, writes, summary)                                                       \
    static void comp_##fn(const sw_comp_io *io, long np, int threads)                                               \
    {                                                                                                             \
        _Pragma("omp parallel num_threads(threads)")                                                              \
        {                                                                                                         \
            unsigned fp = sw_fp_enter();                                                                          \
            _Pragma("omp for schedule(static)")                                                                   \
            for (long i = 0; i < np; i++) {                                                                       \
                spr_pixel_in px = {.color = io->color, .depth = io->depth, .opacity = io->opac,                    \
                                   .normal = io->normal, .env = io->cd->env, .lists = io->lists,                  \
                                   .nbr = io->nbr, .nbr_words = io->nbr_words, .i = (size_t)i,                    \
                                   .x = (int)(i % io->W), .y = (int)(i / io->W)};                                 \
                if (io->probe && px.x == io->probe->x && px.y == io->probe->y) px.probe = io->probe;              \
                float d, on[4];                                                                                   \
                spr_comp_##fn(&px, io->cd->n_inputs, io->cd->eps_t, io->cd->background, io->prm,                   \
                              io->ocolor + 4 * i, on, &d);                                                        \
                io->odepth[i] = d;                                                                                \
                if (io->otest) io->otest[i] = d;                                                                  \
                if (io->onormal)                                                                                  \
                    for (int ch = 0; ch < 4; ch++) io->onormal[4 * i + ch] = on[ch];                              \
            }                                                                                                     \
            sw_fp_leave(fp);                                                                                      \
        }                                                                                                         \
    }
SPR_COMPOSITE_LIST(SW__COMP_LOOP)
#undef SW__COMP_LOOP

typedef void (*sw_comp_loop)(const sw_comp_io *, long, int);
static const sw_comp_loop comp_loops[SPR_COMP__COUNT] = {
#define SW__COMP_FN(e, fn, max_in, reads, writes, summary) comp_##fn,
    SPR_COMPOSITE_LIST(SW__COMP_FN)
#undef SW__COMP_FN
};

spr_result sw__composite(spr_backend *b, const spr_composite_desc *cd)
{
    sw_context *c = sw_ctx(b);
    sw_target *out = sw__target(c, cd->output);
    const long np = (long)b->view.width * b->view.height;
    const int K = cd->n_inputs;
    const float *color[SPR_MAX_COMPOSITE_INPUTS], *depth[SPR_MAX_COMPOSITE_INPUTS], *opac[SPR_MAX_COMPOSITE_INPUTS];
    const float *normal[SPR_MAX_COMPOSITE_INPUTS];
    for (int k = 0; k < K; k++) {
        sw_target *in = sw__target(c, cd->inputs[k]);
        color[k] = SW_F(in, COLOR);   /* NULL where absent: the prefix op reads lists */
        depth[k] = SW_F(in, DEPTH);
        opac[k] = SW_F(in, OPACITY);   /* NULL where absent: read only by ops whose row says so */
        normal[k] = SW_F(in, NORMAL);  /* NULL where absent: read only when the parameters ask */
    }
    static const float no_params[SPR_PRM_COUNT];
    sw_comp_io io = {cd, cd->params ? cd->params : no_params, color, depth, opac, normal,
                     SW_F(out, COLOR), SW_F(out, DEPTH), SW_F(out, TEST), SW_F(out, NORMAL), b->view.width, NULL, NULL, 0, b->probe};
    if (cd->op == SPR_COMP_PREFIX) { /* input 0's lists and the rectangles' neighbours (checked by core) */
        io.lists = &c->targets[cd->inputs[0]].lists;
        if (!io.lists->first) return spr__fail(&b->err, SPR_E_ARG, "cpu: prefix: target %d has no fragment lists", cd->inputs[0]);
        io.nbr = cd->rects->nbr;
        io.nbr_words = spr_rects_words(cd->rects->n);
    }
    comp_loops[cd->op](&io, np, c->threads);
    return SPR_OK;
}
