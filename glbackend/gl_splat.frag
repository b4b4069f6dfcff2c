/* gl_splat.frag — a splat draw's fragments: inputs from flat varyings,
 * uniforms and gl_FragCoord (exactly x + 0.5), every value from the shared
 * arithmetic, outputs to the target's planes.  Depth test, depth write and
 * blending are GL's fixed-function stages under the pass state. */
flat in vec4 v_pr;
flat in vec4 v_na;
flat in vec4 v_c;
flat in vec4 v_e;
flat in uint v_id;
flat in uint v_seq;
uniform float u_M[16];
uniform float u_sx, u_sy, u_eps, u_dmin, u_dmax, u_n, u_invn, u_kscale;
uniform int u_kernel, u_depth, u_output, u_cull, u_mask;
layout(location = SPR_LOC_COLOR) out vec4 o_color;
layout(location = SPR_LOC_DEPTH) out float o_depth;
layout(location = SPR_LOC_ID) out uint o_id;
layout(location = SPR_LOC_COUNT) out float o_count;
layout(location = SPR_LOC_OPACITY) out float o_opacity;
layout(location = SPR_LOC_NORMAL) out vec4 o_normal;
void main()
{
    float o0[3];
    float d[3];
    spr_ray_of_pixel(u_M, u_sx, u_sy, gl_FragCoord.x, gl_FragCoord.y, o0, d);
    float p[3] = float[3](v_pr.x, v_pr.y, v_pr.z);
    float n[3] = float[3](v_na.x, v_na.y, v_na.z);
    float z_near = 0.0;
    if (u_mask != 0) z_near = spr_in_depth(ivec2(gl_FragCoord.xy), 0);
    float t;
    float rho2;
    float rho;
    float e[4] = float[4](v_e.x, v_e.y, v_e.z, v_e.w);
    if (spr_splat_covers(o0, d, p, n, e, v_pr.w, u_cull, u_mask, z_near, u_eps, t, rho2, rho) == 0) discard;
    spr_count_fragment();
    float z = spr_test_depth(u_depth, u_eps, u_dmin, u_dmax, u_n, u_invn, t, rho);
    gl_FragDepth = z;
    float c[3] = float[3](v_c.x, v_c.y, v_c.z);
    float src[4];
    spr_fragment_color(u_output, u_kernel, u_kscale, rho2, rho, c, v_na.w, src);
    o_color = vec4(src[0], src[1], src[2], src[3]);
    float opacity = spr_fragment_opacity(u_output, src, v_na.w);
    o_opacity = opacity;
#ifdef SPR_PROBE
    spr_probe_frag(v_seq, v_id, t, rho, z, src, opacity);
#endif
    float nw[4];
    spr_fragment_normal(src, n, nw);
    o_normal = vec4(nw[0], nw[1], nw[2], nw[3]);
    o_depth = t;
    o_id = v_id;
    o_count = 1.0;
}
