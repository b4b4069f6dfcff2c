/* algo_pbr2p1.c — standard 2+1-pass splatting (SPEC §4.1, the baseline of [ZP] §3.1).
 *
 *   pass 1 "visibility": all splats, z = d_f + ε_t, LESS, depth write on,
 *                        no colour          → Z = min(d_f) + ε_t per pixel
 *   pass 2 "blend":      all splats, z = d_f, LEQUAL against Z, no depth
 *                        write, add (w·c, w)
 *   pass 3 "normalize":  c = rgb / a where a > 0, else background
 *   with deferred shading (SPEC §4.3) pass 2 adds (w·n, w) to a normal plane
 *   too and pass 3 shades.
 */
#include "spr_algo.h"

spr_result spr__algo_pbr2p1(spr__run *run, int *final_target)
{
    int acc, out;
    spr_result r;
    if ((r = spr__run_target(run, SPR_PLANES_OPAQUE | spr__run_normal_planes(run), &acc)) ||
        (r = spr__run_target(run, SPR_PLANES_IMAGE, &out)))
        return r;
    spr_draw_desc d = {.cloud = run->cloud};

    spr_pass_state_defaults(&d.state);
    d.state.kernel = run->desc->kernel;
    d.state.depth_value = SPR_DEPTH_EPS_OFFSET;
    d.state.eps_t = run->eps_t;
    d.state.depth_func = SPR_FUNC_LESS;
    d.state.depth_write = 1;
    d.state.write_mask = SPR_WRITE_DEPTH | SPR_WRITE_ID;
    if ((r = spr__run_draw(run, "visibility", -1, acc, &d))) return r;

    d.state.depth_value = SPR_DEPTH_PLAIN;
    d.state.depth_func = SPR_FUNC_LEQUAL;
    d.state.depth_write = 0;
    spr_pass_state_blend(&d.state, SPR_BLEND_ADD);
    d.state.write_mask = SPR_WRITE_COLOR | SPR_WRITE_COUNT | spr__run_normal_planes(run);
    if ((r = spr__run_draw(run, "blend", -1, acc, &d))) return r;

    spr_composite_desc c = spr__run_comp(run, SPR_COMP_NORMALIZE, &acc, 1, out);
    if ((r = spr__run_composite(run, "normalize", &c))) return r;
    *final_target = out;
    return SPR_OK;
}
