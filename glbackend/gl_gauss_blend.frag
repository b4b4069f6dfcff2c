/* gl_gauss_blend.frag — gauss-blend's ellipses (SPEC §10.7): one instanced
 * quad per Gaussian over its pixel box (gl_splat.vert; the record's values
 * as flat varyings: v_pr = (m.x, m.y, A, B), v_na = (C, o, ·, ·), v_c the
 * colour), the fragment from spr_gauss_blend_frag of the shared
 * arithmetic; GL's blending (ONE, ONE_MINUS_SRC_ALPHA) does the rest. */
flat in vec4 v_pr;
flat in vec4 v_na;
flat in vec4 v_c;
flat in vec4 v_e;
flat in uint v_id;
flat in uint v_seq;
uniform float u_g[SPR_GPRM_COUNT];
layout(location = SPR_LOC_COLOR) out vec4 o_color;
void main()
{
    ivec2 xy = ivec2(gl_FragCoord.xy);
    float fi = float(xy.x);
    float fj = float(int(u_g[SPR_GPRM_H]) - 1 - xy.y);
    float c[3] = float[3](v_c.x, v_c.y, v_c.z);
    float src[4];
    float power;
    float alpha;
    spr_count_fragment();
    if (spr_gauss_blend_frag(u_g, v_pr.x, v_pr.y, v_pr.z, v_pr.w, v_na.x, v_na.y, c, fi, fj, src, power, alpha) == 0) discard;
#ifdef SPR_PROBE
    spr_probe_frag(v_seq, v_id, power, alpha, 0.0, src, alpha);
#endif
    o_color = vec4(src[0], src[1], src[2], src[3]);
}
