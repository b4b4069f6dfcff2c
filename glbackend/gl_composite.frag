/* gl_composite.frag — a composite op as a full-screen pass: the per-pixel
 * function of one row of the composite table (SPR_COMP_ONE, defined by
 * gl_shaders.c for each op's own program) over the input layers
 * u_in_layer[0 … u_K−1]. */
uniform int u_K;
uniform float u_eps;
uniform float u_bg[3];
uniform float u_prm[SPR_PRM_COUNT];
layout(location = SPR_LOC_COLOR) out vec4 o_color;
layout(location = SPR_LOC_DEPTH) out float o_depth;
layout(location = SPR_LOC_NORMAL) out vec4 o_normal;
void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    float o[4];
    float on[4];
    float d;
    SPR_COMP_ONE(px, u_K, u_eps, u_bg, u_prm, o, on, d);
    o_color = vec4(o[0], o[1], o[2], o[3]);
    o_normal = vec4(on[0], on[1], on[2], on[3]);
    o_depth = d;
    gl_FragDepth = d;
}
