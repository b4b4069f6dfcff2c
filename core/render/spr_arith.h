/* spr_arith.h — every float operation that reaches a plane, written once
 * (SPEC §2, §3, §4; PARITY.md "Rules that make Tier A hold").
 *
 * This text is C and GLSL at the same time.  The CPU backend compiles it as
 * C through spr_arith_c.h; the build embeds the very same bytes into every
 * GLSL program of the GL backend (cmake/embed.cmake), after
 * glbackend/gl_prelude.glsl, which gives the macros below their GLSL meaning.
 * Nothing here is retyped anywhere else.
 *
 * The common subset, and why:
 *   - scalar float and int, fixed-size arrays, if, for, return; no vectors,
 *     no dot/length/normalize/mix/fma (they reorder or fuse: PARITY.md rule 2);
 *   - every arithmetic result is first stored in an SPR_PRECISE local, sums
 *     parenthesised in the order C evaluates them; function arguments, return
 *     values and conditions hold no arithmetic (GLSL's `precise` only binds
 *     the expression assigned to a precise variable);
 *   - no transcendental (rule 5): spr_floor and spr_sqrt only, correctly
 *     rounded on both sides; float literals carry the f suffix (GLSL ≥ 1.30
 *     reads it too); no #include, #if or #define in this file.
 *
 *   macro          C (spr_arith_c.h)           GLSL (gl_prelude.glsl)
 *   SPR_FN         static inline               (nothing)
 *   SPR_PRECISE    (nothing)                   precise
 *   SPR_CARR       const float                 float       read-only array parameter
 *   SPR_OARR       float                       out float   array the function fills
 *   SPR_OUT        float *                     out float   scalar the function sets
 *   SPR_SET(x)     (*(x))                      x           the scalar behind SPR_OUT
 *   SPR_REF(x)     &(x)                        x           pass a local as SPR_OUT
 *   SPR_FLOAT(i)   ((float)(i))                float(i)    int to float (exact below 2^24)
 *   SPR_PIXEL      const spr_pixel_in *        ivec2       where a pixel's inputs live
 * and each backend supplies how inputs are fetched:
 *   spr_in_depth(px, k)      stored depth d_f of input target k
 *   spr_in_color(px, k, ch)  channel ch of input target k's colour plane
 *   spr_in_opacity(px, k)    input target k's opacity plane
 * Constants (SPR_DEPTH_*, SPR_KERNEL_*, SPR_OUT_*, spr_gauss_coef) come from
 * their C definitions; the GL backend emits them as exact bit patterns.
 */

/* ---- camera and rays (SPEC §2) ---- */

/* M·(x, y, z, 1) with explicit sums, then the homogeneous divide. */
SPR_FN void spr_unproject(SPR_CARR M[16], float x, float y, float z, SPR_OARR o[3])
{
    SPR_PRECISE float hx = ((M[0] * x + M[1] * y) + M[2] * z) + M[3];
    SPR_PRECISE float hy = ((M[4] * x + M[5] * y) + M[6] * z) + M[7];
    SPR_PRECISE float hz = ((M[8] * x + M[9] * y) + M[10] * z) + M[11];
    SPR_PRECISE float hw = ((M[12] * x + M[13] * y) + M[14] * z) + M[15];
    SPR_PRECISE float ox = hx / hw;
    SPR_PRECISE float oy = hy / hw;
    SPR_PRECISE float oz = hz / hw;
    o[0] = ox;
    o[1] = oy;
    o[2] = oz;
}

/* Ray through the pixel centre (cx, cy) = (x + 0.5, y + 0.5): o0 on the near
 * plane, d = o1 − o0 to the far plane. */
SPR_FN void spr_ray_of_pixel(SPR_CARR M[16], float sx, float sy, float cx, float cy, SPR_OARR o0[3], SPR_OARR d[3])
{
    SPR_PRECISE float nx = cx * sx - 1.0f;
    SPR_PRECISE float ny = cy * sy - 1.0f;
    float a[3];
    float b[3];
    spr_unproject(M, nx, ny, -1.0f, a);
    spr_unproject(M, nx, ny, 1.0f, b);
    SPR_PRECISE float d0 = b[0] - a[0];
    SPR_PRECISE float d1 = b[1] - a[1];
    SPR_PRECISE float d2 = b[2] - a[2];
    o0[0] = a[0];
    o0[1] = a[1];
    o0[2] = a[2];
    d[0] = d0;
    d[1] = d1;
    d[2] = d2;
}

/* Ray–disk intersection: 1 when the closed disk (p, n, r) covers the ray
 * within 0 ≤ t ≤ 1 (ρ² ≤ 1), with t, ρ² and den = d·n (den > 0: back-facing;
 * den is set even when the result is 0). */
SPR_FN int spr_ray_disk(SPR_CARR o0[3], SPR_CARR d[3], SPR_CARR p[3], SPR_CARR n[3], float r, SPR_OUT t_out,
                        SPR_OUT rho2_out, SPR_OUT den_out)
{
    SPR_PRECISE float den = (d[0] * n[0] + d[1] * n[1]) + d[2] * n[2];
    SPR_SET(den_out) = den;
    if (den == 0.0f) return 0;
    SPR_PRECISE float a0 = p[0] - o0[0];
    SPR_PRECISE float a1 = p[1] - o0[1];
    SPR_PRECISE float a2 = p[2] - o0[2];
    SPR_PRECISE float num = (a0 * n[0] + a1 * n[1]) + a2 * n[2];
    SPR_PRECISE float t = num / den;
    if (!(t >= 0.0f && t <= 1.0f)) return 0;
    SPR_PRECISE float q0 = (o0[0] + t * d[0]) - p[0];
    SPR_PRECISE float q1 = (o0[1] + t * d[1]) - p[1];
    SPR_PRECISE float q2 = (o0[2] + t * d[2]) - p[2];
    SPR_PRECISE float qq = (q0 * q0 + q1 * q1) + q2 * q2;
    SPR_PRECISE float rho2 = qq / (r * r);
    if (!(rho2 <= 1.0f)) return 0;
    SPR_SET(t_out) = t;
    SPR_SET(rho2_out) = rho2;
    return 1;
}

/* ---- depth test values (SPEC §3.3) ---- */

/* z̃ of [ZP] Eq. 10, all in float. */
SPR_FN float spr_z_lowres(float d_min, float d_max, float n, float inv_n, float d_f)
{
    SPR_PRECISE float z = spr_floor(((d_f - d_min) / (d_max - d_min)) * n) * inv_n;
    return z;
}

/* Test value of a fragment, clamped to [0, 1] as GL clamps gl_FragDepth. */
SPR_FN float spr_test_depth(int kind, float eps_t, float d_min, float d_max, float n, float inv_n, float d_f, float rho)
{
    SPR_PRECISE float z = d_f;
    if (kind == SPR_DEPTH_EPS_OFFSET) {
        z = d_f + eps_t;
    } else if (kind == SPR_DEPTH_LOWRES || kind == SPR_DEPTH_VORONOI) {
        SPR_PRECISE float zl = spr_z_lowres(d_min, d_max, n, inv_n, d_f);
        z = zl;
        if (kind == SPR_DEPTH_VORONOI) z = zl + rho * inv_n; /* [ZP] Eq. 14 */
    }
    if (z < 0.0f) z = 0.0f;
    if (z > 1.0f) z = 1.0f;
    return z;
}

/* Depth mask of a draw (SPEC §6.2 step 2): 1 when a fragment at d_f lies
 * within the nearest layer, d_f ≤ Z with Z = z_near + ε_t, and must go. */
SPR_FN int spr_depth_masked(float d_f, float z_near, float eps_t)
{
    SPR_PRECISE float Z = z_near + eps_t;
    if (d_f <= Z) return 1;
    return 0;
}

/* Does splat (p, n, r) yield a fragment at this pixel?  Covered (above),
 * not back-facing when culling, and not inside the nearest layer when the
 * draw has a depth mask (z_near: the mask target's stored depth).  Gives t,
 * ρ² and ρ = sqrt(ρ²). */
SPR_FN int spr_splat_covers(SPR_CARR o0[3], SPR_CARR d[3], SPR_CARR p[3], SPR_CARR n[3], float r, int cull, int mask,
                            float z_near, float eps_t, SPR_OUT t_out, SPR_OUT rho2_out, SPR_OUT rho_out)
{
    float t;
    float rho2;
    float den;
    if (spr_ray_disk(o0, d, p, n, r, SPR_REF(t), SPR_REF(rho2), SPR_REF(den)) == 0) return 0;
    if (cull != 0 && den > 0.0f) return 0;
    if (mask != 0 && spr_depth_masked(t, z_near, eps_t) != 0) return 0;
    SPR_PRECISE float rho = spr_sqrt(rho2);
    SPR_SET(t_out) = t;
    SPR_SET(rho2_out) = rho2;
    SPR_SET(rho_out) = rho;
    return 1;
}

/* ---- kernels (SPEC §3.1) ---- */

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

/* What a fragment offers the colour plane: (w·c, w) or (c, α) (SPEC §3.4). */
SPR_FN void spr_fragment_color(int out_kind, int kernel, float rho2, float rho, SPR_CARR c[3], float alpha,
                               SPR_OARR src[4])
{
    if (out_kind == SPR_OUT_ALPHA) {
        src[0] = c[0];
        src[1] = c[1];
        src[2] = c[2];
        src[3] = alpha;
        return;
    }
    SPR_PRECISE float w = spr_kernel_weight(kernel, rho2, rho);
    SPR_PRECISE float wr = w * c[0];
    SPR_PRECISE float wg = w * c[1];
    SPR_PRECISE float wb = w * c[2];
    src[0] = wr;
    src[1] = wg;
    src[2] = wb;
    src[3] = w;
}

/* What a fragment offers the opacity plane (SPEC §6.2): w·α for the
 * weighted output (src[3] = w of spr_fragment_color), α for the (c, α) output. */
SPR_FN float spr_fragment_opacity(int out_kind, SPR_CARR src[4], float alpha)
{
    if (out_kind == SPR_OUT_ALPHA) return alpha;
    SPR_PRECISE float wa = src[3] * alpha;
    return wa;
}

/* ---- composite operations (SPEC §4.1 step 3, §4.2), one per row of
 * SPR_COMPOSITE_LIST (spr_backend.h).  Each fills the output colour o and
 * the output depth d of one pixel from K input targets. ---- */

/* a > 0 ? (rgb/a, 1) : (background, 0) — shared by every normalising op. */
SPR_FN void spr_normalize_rgba(SPR_CARR acc[4], SPR_CARR bg[3], SPR_OARR o[4])
{
    if (acc[3] > 0.0f) {
        SPR_PRECISE float r = acc[0] / acc[3];
        SPR_PRECISE float g = acc[1] / acc[3];
        SPR_PRECISE float b = acc[2] / acc[3];
        o[0] = r;
        o[1] = g;
        o[2] = b;
        o[3] = 1.0f;
    } else {
        o[0] = bg[0];
        o[1] = bg[1];
        o[2] = bg[2];
        o[3] = 0.0f;
    }
}

/* §4.1 step 3: normalise input 0; depth copied. */
SPR_FN void spr_comp_normalize(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_OARR o[4], SPR_OUT d)
{
    float acc[4];
    for (int ch = 0; ch < 4; ch++) acc[ch] = spr_in_color(px, 0, ch);
    spr_normalize_rgba(acc, bg, o);
    SPR_SET(d) = spr_in_depth(px, 0);
}

/* d = min_k d_f(k) over the K inputs (comparisons only). */
SPR_FN float spr_nearest_depth(SPR_PIXEL px, int K)
{
    float dmin = spr_in_depth(px, 0);
    for (int k = 1; k < K; k++) {
        float dk = spr_in_depth(px, k);
        if (dk < dmin) dmin = dk;
    }
    return dmin;
}

/* §6.2 step 3, the nearest layer: the §4.2 composite of colour, and α_F =
 * the same composite of the opacity plane (Σ w·α over Σ w) in the fourth
 * channel; background and 0 where nothing was drawn. */
SPR_FN void spr_comp_nearest(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_OARR o[4], SPR_OUT d)
{
    float dmin = spr_nearest_depth(px, K);
    SPR_PRECISE float limit = dmin + eps_t;
    SPR_PRECISE float acc[4];
    SPR_PRECISE float op = 0.0f;
    for (int ch = 0; ch < 4; ch++) acc[ch] = 0.0f;
    for (int k = 0; k < K; k++) {
        float dk = spr_in_depth(px, k);
        if (!(dk <= limit)) continue;
        for (int ch = 0; ch < 4; ch++) acc[ch] = acc[ch] + spr_in_color(px, k, ch);
        op = op + spr_in_opacity(px, k);
    }
    spr_normalize_rgba(acc, bg, o);
    if (acc[3] > 0.0f) {
        SPR_PRECISE float alpha_f = op / acc[3];
        o[3] = alpha_f;
    }
    SPR_SET(d) = dmin;
}

/* §6.2 step 3, the final image from input 0 = the nearest layer (C_F, α_F)
 * and input 1 = the average of the other layers (C_O):
 * I = α_F·C_F + (1 − α_F)·C_O where the nearest layer has a fragment (its
 * depth below the far plane), the background elsewhere; alpha 1 or 0. */
SPR_FN void spr_comp_transparent2(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_OARR o[4], SPR_OUT d)
{
    float dn = spr_in_depth(px, 0);
    SPR_SET(d) = dn;
    if (!(dn < 1.0f)) {
        o[0] = bg[0];
        o[1] = bg[1];
        o[2] = bg[2];
        o[3] = 0.0f;
        return;
    }
    float a = spr_in_color(px, 0, 3);
    SPR_PRECISE float oma = 1.0f - a;
    for (int ch = 0; ch < 3; ch++) {
        SPR_PRECISE float f = a * spr_in_color(px, 0, ch);
        SPR_PRECISE float g = oma * spr_in_color(px, 1, ch);
        SPR_PRECISE float v = f + g;
        o[ch] = v;
    }
    o[3] = 1.0f;
}

/* §4.2 ([ZP] Fig. 6): d = min_k d_f(k); sum the inputs with d_f(k) ≤ d + ε_t
 * in input order; normalise. */
SPR_FN void spr_comp_deferred(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_OARR o[4], SPR_OUT d)
{
    float dmin = spr_nearest_depth(px, K);
    SPR_PRECISE float limit = dmin + eps_t;
    SPR_PRECISE float acc[4];
    for (int ch = 0; ch < 4; ch++) acc[ch] = 0.0f;
    for (int k = 0; k < K; k++) {
        float dk = spr_in_depth(px, k);
        if (!(dk <= limit)) continue;
        for (int ch = 0; ch < 4; ch++) acc[ch] = acc[ch] + spr_in_color(px, k, ch);
    }
    spr_normalize_rgba(acc, bg, o);
    SPR_SET(d) = dmin;
}

/* §6.1 ([ZP] §3.3): I = (1/K) Σ_k I_k, every channel; depth = min_k d_f(k). */
SPR_FN void spr_comp_average(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_OARR o[4], SPR_OUT d)
{
    float dmin = spr_in_depth(px, 0);
    SPR_PRECISE float acc[4];
    for (int ch = 0; ch < 4; ch++) acc[ch] = 0.0f;
    for (int k = 0; k < K; k++) {
        float dk = spr_in_depth(px, k);
        if (dk < dmin) dmin = dk;
        for (int ch = 0; ch < 4; ch++) acc[ch] = acc[ch] + spr_in_color(px, k, ch);
    }
    SPR_PRECISE float inv_K = 1.0f / SPR_FLOAT(K);
    for (int ch = 0; ch < 4; ch++) {
        SPR_PRECISE float v = acc[ch] * inv_K;
        o[ch] = v;
    }
    SPR_SET(d) = dmin;
}
