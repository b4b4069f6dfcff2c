/* gl_gauss_raster.frag — gauss3d and gauss2d's rasterization (SPEC §10.4,
 * §10.5): one fragment per pixel of an attachment-less framebuffer the size
 * of the image, running spr_gauss_pixel_run of the shared arithmetic over
 * its 16×16 tile's sorted list (records and lists through buffer textures,
 * gl_prelude.glsl), then storing the planes the target has into its layer
 * of the plane arrays; per tile the Gaussians visited and blended are
 * summed for the draw statistics.  A list longer than llvmpipe's loop budget
 * lets a fragment walk (65,535 iterations an invocation, then every loop
 * left silently) is walked u_steps entries a draw, the loop's state kept in
 * u_gfs between draws (u_round 0: a fresh state), and each pixel not done
 * counted in the last word of the counts: the host draws again until none
 * is.  A fragment program, not a compute one: llvmpipe runs fragments with
 * denormals flushed, as the reference does, and compute invocations without
 * (PARITY.md rule 6). */
layout(rgba32f, binding = 0) uniform writeonly image2DArray u_img_color;
layout(r32f, binding = 1) uniform writeonly image2DArray u_img_trans;
layout(r32ui, binding = 2) uniform writeonly uimage2DArray u_img_contrib;
layout(r32f, binding = 3) uniform writeonly image2DArray u_img_depth;
layout(rgba32f, binding = 4) uniform writeonly image2DArray u_img_normal;
layout(std430, binding = 5) buffer SprGaussCounts { uint spr_gcount[]; };
layout(rgba32f, binding = 6) uniform coherent imageBuffer u_gfs; /* SPR_GFS_FLOATS a pixel, pixel y·W + x */
uniform float u_g[SPR_GPRM_COUNT];
uniform float u_bg[3];
uniform int u_layer;
uniform int u_has; /* bits: 1 transmittance, 2 contrib, 4 depth (invdepth or surfdepth), 8 normal */
uniform int u_steps; /* 0: the whole list in this draw */
uniform int u_round;
void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    int W = int(u_g[SPR_GPRM_W]);
    int H = int(u_g[SPR_GPRM_H]);
    if (px.x >= W || px.y >= H) return;
    int j = H - 1 - px.y; /* the pixel-index row */
    uint tiles = uint(u_g[SPR_GPRM_GX]) * uint(u_g[SPR_GPRM_GY]);
    float st[SPR_GFS_FLOATS];
    int at = (px.y * W + px.x) * (SPR_GFS_FLOATS / 4);
    int budget = 2147483647;
    if (u_steps != 0) budget = u_steps;
    if (u_steps == 0 || u_round == 0) spr_gauss_pixel_begin(st);
    else {
        for (int q = 0; q < SPR_GFS_FLOATS / 4; q++) {
            vec4 t = imageLoad(u_gfs, at + q);
            for (int c = 0; c < 4; c++) st[4 * q + c] = t[c];
        }
        if (st[SPR_GFS_DONE] != 0.0) return; /* done in an earlier draw, its planes stored then */
    }
    int done = spr_gauss_pixel_run(px, u_g, st, budget);
    if (u_steps != 0)
        for (int q = 0; q < SPR_GFS_FLOATS / 4; q++) imageStore(u_gfs, at + q, vec4(st[4 * q], st[4 * q + 1], st[4 * q + 2], st[4 * q + 3]));
    if (done == 0) {
        atomicAdd(spr_gcount[2u * tiles], 1u);
        return;
    }
    float o[4];
    float aux[4];
    float nrm[4];
    int visited = spr_gauss_pixel_end(px, u_g, u_bg, st, o, aux, nrm);
    ivec3 at3 = ivec3(px, u_layer);
    imageStore(u_img_color, at3, vec4(o[0], o[1], o[2], o[3]));
    if ((u_has & 1) != 0) imageStore(u_img_trans, at3, vec4(aux[0]));
    if ((u_has & 2) != 0) imageStore(u_img_contrib, at3, uvec4(uint(aux[1])));
    if ((u_has & 4) != 0) imageStore(u_img_depth, at3, vec4(aux[2]));
    if ((u_has & 8) != 0) imageStore(u_img_normal, at3, vec4(nrm[0], nrm[1], nrm[2], nrm[3]));
    uint tile = uint(j / 16) * uint(u_g[SPR_GPRM_GX]) + uint(px.x / 16);
    atomicAdd(spr_gcount[2u * tile], uint(visited));
    atomicAdd(spr_gcount[2u * tile + 1u], uint(aux[3]));
}
