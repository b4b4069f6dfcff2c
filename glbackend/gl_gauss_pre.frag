/* gl_gauss_pre.frag — the Gaussians' preprocessing (SPEC §10.3, §10.5): one
 * fragment per Gaussian (Gaussian u_base + y·u_width + x of an
 * attachment-less framebuffer, gl_gauss.c) runs spr_gauss_preprocess of the
 * shared arithmetic on its inputs (mean, quaternion, σ, opacity, colour: 14
 * floats, packed by gl_gauss.c) and stores its record.  A fragment program,
 * not a compute one: llvmpipe runs fragments with denormals flushed, as the
 * reference does, and compute invocations without (PARITY.md rule 6). */
layout(std430, binding = 3) readonly buffer SprGaussIn { float spr_gin[]; };
layout(std430, binding = 4) writeonly buffer SprGaussRec { float spr_grec_out[]; };
uniform float u_g[SPR_GPRM_COUNT];
uniform uint u_n;
uniform uint u_base;
uniform uint u_width;
void main()
{
    uvec2 xy = uvec2(gl_FragCoord.xy);
    uint i = u_base + xy.y * u_width + xy.x;
    if (i >= u_n) return;
    uint o = i * 14u;
    float mu[3] = float[3](spr_gin[o], spr_gin[o + 1u], spr_gin[o + 2u]);
    float q[4] = float[4](spr_gin[o + 3u], spr_gin[o + 4u], spr_gin[o + 5u], spr_gin[o + 6u]);
    float s[3] = float[3](spr_gin[o + 7u], spr_gin[o + 8u], spr_gin[o + 9u]);
    float op = spr_gin[o + 10u];
    float c[3] = float[3](spr_gin[o + 11u], spr_gin[o + 12u], spr_gin[o + 13u]);
    float rec[SPR_GREC_FLOATS];
    spr_gauss_preprocess(u_g, mu, q, s, op, c, rec);
    uint r = i * uint(SPR_GREC_FLOATS);
    for (int f = 0; f < SPR_GREC_FLOATS; f++) spr_grec_out[r + uint(f)] = rec[f];
}
