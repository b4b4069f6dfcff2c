/* gl_gauss_raster.comp — gauss3d and gauss2d's rasterization (SPEC §10.4,
 * §10.5): one work group per 16×16 tile, one invocation per pixel, running
 * spr_gauss_pixel of the shared arithmetic over the tile's sorted list
 * (records and lists through buffer textures, gl_prelude.glsl), then storing
 * the planes the target has into its layer of the plane arrays; per tile the
 * Gaussians visited and blended are summed for the draw statistics. */
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform writeonly image2DArray u_img_color;
layout(r32f, binding = 1) uniform writeonly image2DArray u_img_trans;
layout(r32ui, binding = 2) uniform writeonly uimage2DArray u_img_contrib;
layout(r32f, binding = 3) uniform writeonly image2DArray u_img_depth;
layout(rgba32f, binding = 4) uniform writeonly image2DArray u_img_normal;
layout(std430, binding = 5) buffer SprGaussCounts { uint spr_gcount[]; };
uniform float u_g[SPR_GPRM_COUNT];
uniform float u_bg[3];
uniform int u_layer;
uniform int u_has; /* bits: 1 transmittance, 2 contrib, 4 depth (invdepth or surfdepth), 8 normal */
void main()
{
    int i = int(gl_GlobalInvocationID.x);
    int j = int(gl_GlobalInvocationID.y);
    int W = int(u_g[SPR_GPRM_W]);
    int H = int(u_g[SPR_GPRM_H]);
    if (i >= W || j >= H) return;
    ivec2 px = ivec2(i, H - 1 - j);
#ifdef SPR_PROBE
    spr_probe_xy = px;
#endif
    float o[4];
    float aux[4];
    float nrm[4];
    int visited = spr_gauss_pixel(px, u_g, u_bg, o, aux, nrm);
    ivec3 at = ivec3(px, u_layer);
    imageStore(u_img_color, at, vec4(o[0], o[1], o[2], o[3]));
    if ((u_has & 1) != 0) imageStore(u_img_trans, at, vec4(aux[0]));
    if ((u_has & 2) != 0) imageStore(u_img_contrib, at, uvec4(uint(aux[1])));
    if ((u_has & 4) != 0) imageStore(u_img_depth, at, vec4(aux[2]));
    if ((u_has & 8) != 0) imageStore(u_img_normal, at, vec4(nrm[0], nrm[1], nrm[2], nrm[3]));
    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    atomicAdd(spr_gcount[2u * tile], uint(visited));
    atomicAdd(spr_gcount[2u * tile + 1u], uint(aux[3]));
}
