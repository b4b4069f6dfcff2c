/* gl_gauss_bwd_tile.frag — gauss3d's backward pass, one pixel of every tile
 * (SPEC 10.10): one fragment per 16×16 tile of a batch (tile u_t0 +
 * y·u_width + x of an attachment-less framebuffer, gl_gauss.c) runs
 * spr_gauss_pixel_bwd of the shared arithmetic for the tile's pixels u_pix …
 * u_pix + u_npix − 1 (row-major from the top row) in order, which add their
 * terms to the tile's list entries' partials (an image of four floats a
 * texel, gl_prelude.glsl's spr_gpart).  gl_gauss.c draws the runs in order, a
 * barrier between draws, so each tile's partials take its pixels' terms in
 * the CPU's order; it sizes the runs so that a fragment stays within
 * llvmpipe's 65,535 loop iterations (a whole tile a fragment did not: its
 * loops stopped early, silently).  A fragment program, not a compute one: llvmpipe runs fragments
 * with denormals flushed, as the reference does (PARITY.md rule 6). */
uniform float u_g[SPR_GPRM_COUNT];
uniform float u_bg[3];
uniform int u_t0;
uniform int u_t1;
uniform int u_width;
uniform int u_pix;
uniform int u_npix;
void main()
{
    ivec2 xy = ivec2(gl_FragCoord.xy);
    int t = u_t0 + xy.y * u_width + xy.x;
    if (t >= u_t1) return;
    int W = int(u_g[SPR_GPRM_W]);
    int H = int(u_g[SPR_GPRM_H]);
    int gx = int(u_g[SPR_GPRM_GX]);
    for (int p = u_pix; p < u_pix + u_npix; p++) {
        int i = (t % gx) * 16 + p % 16;
        int j = (t / gx) * 16 + p / 16;
        if (i < W && j < H) spr_gauss_pixel_bwd(ivec2(i, H - 1 - j), u_g, u_bg);
    }
}
