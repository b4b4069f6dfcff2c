/* gl_gauss_bwd_gauss.frag — gauss3d's backward pass per Gaussian (SPEC
 * 10.10): one fragment per Gaussian (u_base + y·u_width + x, gl_gauss.c).
 * u_stage 0: its entries' partials of a batch of tiles [u_ebase, u_eend)
 * added in entry order to its sums (spr_gauss_gather; the sums an image of
 * four floats a texel); 1: the chain from its sums (spr_gauss_preprocess3d_bwd)
 * into SPR_GOUT_FLOATS values of the output buffer, from the preprocessing's
 * inputs (14 floats a Gaussian, packed as gl_gauss_pre.frag reads them). */
layout(std430, binding = 3) readonly buffer SprGaussIn { float spr_gin[]; };
layout(std430, binding = 4) writeonly buffer SprGaussOut { float spr_gout[]; };
layout(rgba32f, binding = 6) uniform coherent imageBuffer u_gsums;
layout(binding = 15) uniform usamplerBuffer u_gcsr_start;
uniform float u_g[SPR_GPRM_COUNT];
uniform uint u_n;
uniform uint u_base;
uniform uint u_width;
uniform int u_stage;
uniform int u_ebase;
uniform int u_eend;
void main()
{
    uvec2 xy = uvec2(gl_FragCoord.xy);
    uint G = u_base + xy.y * u_width + xy.x;
    if (G >= u_n) return;
    float sum[SPR_GPART_FLOATS];
    for (int k = 0; k < SPR_GPART_FLOATS / 4; k++) {
        vec4 v = imageLoad(u_gsums, int(G) * (SPR_GPART_FLOATS / 4) + k);
        for (int c = 0; c < 4; c++) sum[4 * k + c] = v[c];
    }
    if (u_stage == 0) {
        int k0 = int(texelFetch(u_gcsr_start, int(G)).r);
        int k1 = int(texelFetch(u_gcsr_start, int(G) + 1).r);
        spr_gauss_gather(ivec2(0), k0, k1, u_ebase, u_eend, sum);
        for (int k = 0; k < SPR_GPART_FLOATS / 4; k++)
            imageStore(u_gsums, int(G) * (SPR_GPART_FLOATS / 4) + k, vec4(sum[4 * k], sum[4 * k + 1], sum[4 * k + 2], sum[4 * k + 3]));
        return;
    }
    uint o = (G - u_base) * 14u;
    float mu[3] = float[3](spr_gin[o], spr_gin[o + 1u], spr_gin[o + 2u]);
    float q[4] = float[4](spr_gin[o + 3u], spr_gin[o + 4u], spr_gin[o + 5u], spr_gin[o + 6u]);
    float s[3] = float[3](spr_gin[o + 7u], spr_gin[o + 8u], spr_gin[o + 9u]);
    float out_[SPR_GOUT_FLOATS];
    spr_gauss_preprocess3d_bwd(u_g, mu, q, s, sum, out_);
    uint r = (G - u_base) * uint(SPR_GOUT_FLOATS);
    for (int f = 0; f < SPR_GOUT_FLOATS; f++) spr_gout[r + uint(f)] = out_[f];
}
