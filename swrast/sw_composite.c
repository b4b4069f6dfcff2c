/* sw_composite.c — full-screen operations of the CPU backend.
 *
 * SPR_COMP_DEFERRED is the compositing pass of SPEC §4.2 ([ZP] Fig. 6):
 *     d = min_k d_f(k)
 *     for k = 0 … K−1: if d_f(k) ≤ d + ε_t: rgb += rgb_k; a += a_k
 *     color = a > 0 ? rgb / a : background
 * SPR_COMP_NORMALIZE is the last pass of SPEC §4.1.  Output alpha is 1 where
 * a fragment contributed, 0 on background; the output's stored depth is d.
 */
#include "sw_internal.h"

static void normalize_pixel(const float acc[4], const float bg[3], float out[4])
{
    if (acc[3] > 0.0f) {
        out[0] = acc[0] / acc[3];
        out[1] = acc[1] / acc[3];
        out[2] = acc[2] / acc[3];
        out[3] = 1.0f;
    } else {
        out[0] = bg[0];
        out[1] = bg[1];
        out[2] = bg[2];
        out[3] = 0.0f;
    }
}

spr_result sw__composite(spr_backend *b, const spr_composite_desc *cd)
{
    sw_context *c = sw_ctx(b);
    sw_target *out = &c->targets[cd->output];
    const long np = (long)b->view.width * b->view.height;
    const int K = cd->n_inputs;
    sw_target *in[SPR_MAX_COMPOSITE_INPUTS];
    for (int k = 0; k < K; k++) in[k] = &c->targets[cd->inputs[k]];

#pragma omp parallel num_threads(c->threads)
    {
        unsigned fp = sw_fp_enter();
#pragma omp for schedule(static)
        for (long i = 0; i < np; i++) {
            float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f}, d;
            if (cd->op == SPR_COMP_NORMALIZE) {
                for (int ch = 0; ch < 4; ch++) acc[ch] = in[0]->color[4 * i + ch];
                d = in[0]->depth[i];
            } else {
                d = in[0]->depth[i];
                for (int k = 1; k < K; k++)
                    if (in[k]->depth[i] < d) d = in[k]->depth[i];
                float limit = d + cd->eps_t;
                for (int k = 0; k < K; k++) {
                    if (!(in[k]->depth[i] <= limit)) continue;
                    for (int ch = 0; ch < 4; ch++) acc[ch] = acc[ch] + in[k]->color[4 * i + ch];
                }
            }
            normalize_pixel(acc, cd->background, out->color + 4 * i);
            out->depth[i] = d;
            out->test[i] = d;
        }
        sw_fp_leave(fp);
    }
    return SPR_OK;
}
