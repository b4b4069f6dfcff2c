/* gl_rect.frag — a rectangle draw's fragments (domain primitives, SPEC
 * §7.7): the rectangle's records from shader storage by its index (a flat
 * varying), the ray from gl_FragCoord, hit, texture and outputs from the
 * shared arithmetic.  Texture sampling is nearest or explicit bilinear
 * (Tier A), or GL's own bilinear texture() on the padded atlas (Tier B,
 * PARITY.md).  A list draw appends the fragment to its pixel's list
 * (an atomic node counter, an atomic exchange of the pixel's head) and
 * writes no plane. */
flat in vec4 v_pr;
flat in vec4 v_na;
flat in vec4 v_c;
flat in uint v_id;
flat in uint v_seq;
uniform float u_M[16];
uniform float u_sx, u_sy, u_eps, u_alpha_ref;
uniform int u_depth, u_output, u_sampling, u_list;
uniform vec2 u_atlas_size;
layout(binding = 5) uniform sampler2D u_atlas;
layout(std430, binding = 7) readonly buffer SprAtlasOrg { ivec2 spr_atlas_org[]; };
/* the fragment lists, written here (read by the prefix op through buffer textures) */
layout(std430, binding = 3) coherent buffer SprListMeta { uint spr_list_alloc; uint spr_list_cap; uint spr_list_pad0; uint spr_list_pad1; uvec4 spr_list_meta[]; };
layout(std430, binding = 4) coherent buffer SprListSrc { vec4 spr_list_srcv[]; };
layout(std430, binding = 5) coherent buffer SprListHead { uint spr_list_head[]; };
layout(location = SPR_LOC_COLOR) out vec4 o_color;
layout(location = SPR_LOC_DEPTH) out float o_depth;
layout(location = SPR_LOC_ID) out uint o_id;
layout(location = SPR_LOC_COUNT) out float o_count;
void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    float o0[3];
    float d[3];
    spr_ray_of_pixel(u_M, u_sx, u_sy, gl_FragCoord.x, gl_FragCoord.y, o0, d);
    int k = int(v_id);
    float R[SPR_RECT_FLOATS];
    for (int i = 0; i < SPR_RECT_FLOATS; i++) R[i] = spr_rect_f[k * SPR_RECT_FLOATS + i];
    int tw = int(spr_rect_i[k * SPR_RECTI_COUNT + SPR_RECTI_TW]);
    int th = int(spr_rect_i[k * SPR_RECTI_COUNT + SPR_RECTI_TH]);
    int off = int(spr_rect_i[k * SPR_RECTI_COUNT + SPR_RECTI_OFF]);
    float t;
    float s;
    float w;
    if (spr_rect_hit(o0, d, R, t, s, w) == 0) discard;
    float tx[4];
    if (u_sampling == SPR_SAMPLE_HARDWARE) {
        /* Tier B: texel coordinate inside the rectangle's padded atlas block */
        vec2 g = vec2(spr_texel_coord(s, R[SPR_RECT_UMIN], R[SPR_RECT_TEXEL]), spr_texel_coord(w, R[SPR_RECT_VMIN], R[SPR_RECT_TEXEL]));
        g = clamp(g, vec2(0.0), vec2(float(tw), float(th)));
        vec4 v = texture(u_atlas, (vec2(spr_atlas_org[k]) + 1.0 + g) / u_atlas_size);
        tx = float[4](v.x, v.y, v.z, v.w);
    } else {
        spr_rect_sample(px, R, tw, th, off, u_sampling == SPR_SAMPLE_LINEAR ? 1 : 0, s, w, tx);
    }
    if (spr_rect_alpha_passes(tx[3], u_alpha_ref) == 0) discard;
    spr_count_fragment();
    float src[4];
    spr_rect_fragment(u_output, tx, src);
    float z = spr_test_depth(u_depth, u_eps, 0.0, 1.0, 1.0, 1.0, t, 0.0);
#ifdef SPR_PROBE
    spr_probe_frag(v_seq, uint(k), t, 0.0, z, src, 0.0);
#endif
    if (u_list != 0) {
        uint node = atomicAdd(spr_list_alloc, 1u);
        if (node < spr_list_cap) {
            spr_list_srcv[node] = vec4(src[0], src[1], src[2], src[3]);
            uint next = atomicExchange(spr_list_head[px.y * u_list_width + px.x], node);
            spr_list_meta[node] = uvec4(floatBitsToUint(t), uint(k), next, 0u);
        }
        discard;
    }
    gl_FragDepth = z;
    o_color = vec4(src[0], src[1], src[2], src[3]);
    o_depth = t;
    o_id = uint(k);
    o_count = 1.0;
}
