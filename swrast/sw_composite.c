/* sw_composite.c — composite operations on the CPU: the loop over pixels
 * around the per-pixel functions of the composite table (SPR_COMPOSITE_LIST
 * in spr_backend.h, spr_comp_* in spr_arith.h).  The output's test plane,
 * when it has one, receives the output depth, as gl_FragDepth does in GL.
 */
#include "sw_internal.h"
#include "spr_fragment.h"

typedef void (*sw_comp_fn)(const spr_pixel_in *px, int K, float eps_t, const float bg[3], float o[4], float *d);
static const sw_comp_fn comp_fns[SPR_COMP__COUNT] = {
#define SW__COMP_FN(e, fn, max_in, summary) spr_comp_##fn,
    SPR_COMPOSITE_LIST(SW__COMP_FN)
#undef SW__COMP_FN
};

spr_result sw__composite(spr_backend *b, const spr_composite_desc *cd)
{
    sw_context *c = sw_ctx(b);
    sw_target *out = &c->targets[cd->output];
    const long np = (long)b->view.width * b->view.height;
    const int K = cd->n_inputs;
    const float *color[SPR_MAX_COMPOSITE_INPUTS], *depth[SPR_MAX_COMPOSITE_INPUTS];
    for (int k = 0; k < K; k++) {
        color[k] = SW_F(&c->targets[cd->inputs[k]], COLOR);
        depth[k] = SW_F(&c->targets[cd->inputs[k]], DEPTH);
    }
    const sw_comp_fn fn = comp_fns[cd->op];
    float *ocolor = SW_F(out, COLOR), *odepth = SW_F(out, DEPTH), *otest = SW_F(out, TEST);

#pragma omp parallel num_threads(c->threads)
    {
        unsigned fp = sw_fp_enter();
#pragma omp for schedule(static)
        for (long i = 0; i < np; i++) {
            spr_pixel_in px = {color, depth, (size_t)i};
            float d;
            fn(&px, K, cd->eps_t, cd->background, ocolor + 4 * i, &d);
            odepth[i] = d;
            if (otest) otest[i] = d;
        }
        sw_fp_leave(fp);
    }
    return SPR_OK;
}
