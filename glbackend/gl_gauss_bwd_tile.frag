/* gl_gauss_bwd_tile.frag — gauss3d's backward pass over the tiles (SPEC
 * 10.10): one fragment per 16×16 tile of a batch (tile u_t0 + y·u_width + x
 * of an attachment-less framebuffer, gl_gauss.c) resumes the tile's walk,
 * spr_gauss_tile_bwd of the shared arithmetic, for at most u_budget steps,
 * its state in u_gbs (SPR_GBS_FLOATS values a tile of the batch), and says
 * in spr_bwd_done whether the tile is done (bit 0) and which pixel blended
 * more than the state holds (SPR_GBS_OVER, the bits above).  The host draws again until every
 * tile is, a barrier between draws: each tile's pixels add their terms to its
 * list entries' partials (gl_prelude.glsl's spr_gpart) in the CPU's order,
 * and no fragment spends more than llvmpipe's 65,535 loop iterations, however
 * long its list (gallivm leaves every loop, silently, past them).  A fragment
 * program, not a compute one: llvmpipe runs fragments with denormals flushed,
 * as the reference does (PARITY.md rule 6). */
layout(std430, binding = 6) buffer SprBwdDone { uint spr_bwd_done[]; };
uniform float u_g[SPR_GPRM_COUNT];
uniform float u_bg[3];
uniform int u_t0;
uniform int u_t1;
uniform int u_width;
uniform int u_budget;
void main()
{
    ivec2 xy = ivec2(gl_FragCoord.xy);
    int t = u_t0 + xy.y * u_width + xy.x;
    if (t >= u_t1) return;
    spr__gbs_at = (t - u_t0) * SPR_GBS_FLOATS;
    int done = spr_gauss_tile_bwd(xy, u_g, u_bg, t, 256, u_budget);
    spr_bwd_done[t - u_t0] = uint(done) | (uint(spr_gbs_i(xy, SPR_GBS_OVER)) << 1u);
}
