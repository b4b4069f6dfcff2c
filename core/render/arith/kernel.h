/* kernel.h — blending weights and what a fragment offers each plane
 * (SPEC §3.1, §3.4, §4.3, §6.2); the rules of base.h. */

/* w(ρ) given ρ² and ρ = sqrt(ρ²); gauss is the shared Horner polynomial in
 * v = 2ρ² − 1 (coefficients spr_gauss_coef, highest degree first). */
SPR_FN float spr_kernel_weight(int kernel, float rho2, float rho)
{
    SPR_PRECISE float w = 1.0f;
    if (kernel == SPR_KERNEL_LINEAR) {
        w = 1.0f - rho;
    } else if (kernel == SPR_KERNEL_EPANECHNIKOV) {
        w = 1.0f - rho2;
    } else if (kernel == SPR_KERNEL_GAUSS) {
        SPR_PRECISE float v = rho2 * 2.0f - 1.0f;
        SPR_PRECISE float acc = spr_gauss_coef[0];
        for (int i = 1; i <= SPR_GAUSS_DEGREE; i++) acc = acc * v + spr_gauss_coef[i];
        w = acc;
    }
    return w;
}

/* o = (w·v, w): a weighted colour or normal and its weight. */
SPR_FN void spr_weighted4(float w, SPR_CARR v[3], SPR_OARR o[4])
{
    SPR_PRECISE float x = w * v[0];
    SPR_PRECISE float y = w * v[1];
    SPR_PRECISE float z = w * v[2];
    o[0] = x;
    o[1] = y;
    o[2] = z;
    o[3] = w;
}

/* What a fragment offers the colour plane: (w·c, w) or (c, α) (SPEC §3.4).
 * ks scales ρ² before the gauss kernel (1: none; spr_draw_kernel_scale). */
SPR_FN void spr_fragment_color(int out_kind, int kernel, float ks, float rho2, float rho, SPR_CARR c[3], float alpha,
                               SPR_OARR src[4])
{
    if (out_kind == SPR_OUT_ALPHA) {
        src[0] = c[0];
        src[1] = c[1];
        src[2] = c[2];
        src[3] = alpha;
        return;
    }
    SPR_PRECISE float kr2 = rho2;
    if (kernel == SPR_KERNEL_GAUSS && ks != 1.0f) kr2 = rho2 * ks; /* a capture cut at C σ: ks = (C/3)², the file's σ */
    float w = spr_kernel_weight(kernel, kr2, rho);
    spr_weighted4(w, c, src);
}

/* What a fragment offers the opacity plane (SPEC §6.2): w·α for the
 * weighted output (src[3] = w of spr_fragment_color), α for the (c, α) output. */
SPR_FN float spr_fragment_opacity(int out_kind, SPR_CARR src[4], float alpha)
{
    if (out_kind == SPR_OUT_ALPHA) return alpha;
    SPR_PRECISE float wa = src[3] * alpha;
    return wa;
}

/* What a fragment offers the normal plane (SPEC §4.3): (w·n, w), with
 * src[3] = w of spr_fragment_color's weighted output. */
SPR_FN void spr_fragment_normal(SPR_CARR src[4], SPR_CARR n[3], SPR_OARR o[4])
{
    spr_weighted4(src[3], n, o);
}
