/* algo_zbuffer.c — no blending: the plain z-buffer baseline whose aliasing
 * splat blending exists to remove ([ZP] §1, Fig. 1's left image).
 *
 *   pass 1 "geometry":  all splats, z = d_f, LESS, depth write on, replace
 *                       with (w·c, w) under the constant kernel (w = 1)
 *   pass 2 "normalize": c = rgb / a — exactly the nearest splat's colour
 */
#include "spr_algo.h"

spr_result spr__algo_zbuffer(spr__run *run, int *final_target)
{
    int img, out;
    spr_result r;
    if ((r = spr__run_target(run, SPR_PLANES_OPAQUE, &img)) ||
        (r = spr__run_target(run, SPR_PLANES_IMAGE, &out)))
        return r;
    spr_draw_desc d = {.cloud = run->cloud};
    spr_pass_state_defaults(&d.state);
    d.state.kernel = SPR_KERNEL_CONSTANT;
    d.state.depth_func = SPR_FUNC_LESS;
    d.state.depth_write = 1;
    if ((r = spr__run_draw(run, "geometry", -1, img, &d))) return r;
    spr_composite_desc c = spr__run_comp(run, SPR_COMP_NORMALIZE, &img, 1, out);
    c.eps_t = 0.0f;
    if ((r = spr__run_composite(run, "normalize", &c))) return r;
    *final_target = out;
    return SPR_OK;
}
