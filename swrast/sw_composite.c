/* sw_composite.c — composite operations on the CPU: the loop over pixels
 * around the per-pixel functions of the composite table (SPR_COMPOSITE_LIST
 * in spr_backend.h, spr_comp_* in spr_arith.h).  Every op of the table
 * writes colour and depth; the output's test plane, when it has one,
 * receives the depth, as gl_FragDepth does in GL.
 */
#include "sw_internal.h"
#include "spr_fragment.h"

/* One pixel loop per op of the table, so each op's function is inlined. */
#define SW__COMP_LOOP(e, fn, max_in, reads, writes, summary)                                                                     \
    static void comp_##fn(const spr_composite_desc *cd, long np, int threads, const float *const *color,          \
                          const float *const *depth, const float *const *opac, float *ocolor, float *odepth,        \
                          float *otest)                                                                             \
    {                                                                                                             \
        _Pragma("omp parallel num_threads(threads)")                                                              \
        {                                                                                                         \
            unsigned fp = sw_fp_enter();                                                                          \
            _Pragma("omp for schedule(static)")                                                                   \
            for (long i = 0; i < np; i++) {                                                                       \
                spr_pixel_in px = {color, depth, opac, (size_t)i};                                                \
                float d;                                                                                          \
                spr_comp_##fn(&px, cd->n_inputs, cd->eps_t, cd->background, ocolor + 4 * i, &d);                  \
                odepth[i] = d;                                                                                    \
                if (otest) otest[i] = d;                                                                          \
            }                                                                                                     \
            sw_fp_leave(fp);                                                                                      \
        }                                                                                                         \
    }
SPR_COMPOSITE_LIST(SW__COMP_LOOP)
#undef SW__COMP_LOOP

typedef void (*sw_comp_loop)(const spr_composite_desc *, long, int, const float *const *, const float *const *,
                             const float *const *, float *, float *, float *);
static const sw_comp_loop comp_loops[SPR_COMP__COUNT] = {
#define SW__COMP_FN(e, fn, max_in, reads, writes, summary) comp_##fn,
    SPR_COMPOSITE_LIST(SW__COMP_FN)
#undef SW__COMP_FN
};

spr_result sw__composite(spr_backend *b, const spr_composite_desc *cd)
{
    sw_context *c = sw_ctx(b);
    sw_target *out = &c->targets[cd->output];
    const long np = (long)b->view.width * b->view.height;
    const int K = cd->n_inputs;
    const float *color[SPR_MAX_COMPOSITE_INPUTS], *depth[SPR_MAX_COMPOSITE_INPUTS], *opac[SPR_MAX_COMPOSITE_INPUTS];
    for (int k = 0; k < K; k++) {
        color[k] = SW_F(&c->targets[cd->inputs[k]], COLOR);
        depth[k] = SW_F(&c->targets[cd->inputs[k]], DEPTH);
        opac[k] = SW_F(&c->targets[cd->inputs[k]], OPACITY); /* NULL where absent: read only by ops whose row says so */
    }
    comp_loops[cd->op](cd, np, c->threads, color, depth, opac, SW_F(out, COLOR), SW_F(out, DEPTH), SW_F(out, TEST));
    return SPR_OK;
}
