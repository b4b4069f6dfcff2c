/* rect.h — domain primitives: textured rectangles (SPEC §7.7); R is a
 * rectangle's float record (SPR_RECT_LIST, spr_backend.h); the rules of
 * base.h. */

/* Ray–rectangle: 1 when the ray meets R's plane at 0 ≤ t ≤ 1 inside the
 * rectangle; gives t and the hit point's (s, w) along u and v. */
SPR_FN int spr_rect_hit(SPR_CARR o0[3], SPR_CARR d[3], SPR_CARR R[SPR_RECT_FLOATS], SPR_OUT t_out, SPR_OUT s_out,
                        SPR_OUT w_out)
{
    float c[3];
    float n[3];
    for (int i = 0; i < 3; i++) {
        c[i] = R[SPR_RECT_C + i];
        n[i] = R[SPR_RECT_N + i];
    }
    float t;
    float q[3];
    float den;
    if (spr_ray_plane(o0, d, c, n, SPR_REF(t), q, SPR_REF(den)) == 0) return 0;
    SPR_PRECISE float s = (q[0] * R[SPR_RECT_U] + q[1] * R[SPR_RECT_U + 1]) + q[2] * R[SPR_RECT_U + 2];
    SPR_PRECISE float w = (q[0] * R[SPR_RECT_V] + q[1] * R[SPR_RECT_V + 1]) + q[2] * R[SPR_RECT_V + 2];
    if (!(s >= R[SPR_RECT_UMIN] && s <= R[SPR_RECT_UMAX] && w >= R[SPR_RECT_VMIN] && w <= R[SPR_RECT_VMAX])) return 0;
    SPR_SET(t_out) = t;
    SPR_SET(s_out) = s;
    SPR_SET(w_out) = w;
    return 1;
}

/* Index i clamped to [0, n − 1] (GL's clamp-to-edge). */
SPR_FN int spr_clampi(int i, int n)
{
    if (i < 0) return 0;
    if (i > n - 1) return n - 1;
    return i;
}

/* The texel coordinate of (s, w) along one axis: (s − min)/h, in texels. */
SPR_FN float spr_texel_coord(float s, float smin, float h)
{
    SPR_PRECISE float g = (s - smin) / h;
    return g;
}

/* The texture of rectangle R (tw × th texels from texel off) at (s, w):
 * nearest, or bilinear with the weights computed here (clamp to edge):
 * o = ((w00·t00 + w10·t10) + w01·t01) + w11·t11, w10 = fx·(1 − fy) etc. */
SPR_FN void spr_rect_sample(SPR_PIXEL px, SPR_CARR R[SPR_RECT_FLOATS], int tw, int th, int off, int linear, float s, float w,
                            SPR_OARR o[4])
{
    float gx = spr_texel_coord(s, R[SPR_RECT_UMIN], R[SPR_RECT_TEXEL]);
    float gy = spr_texel_coord(w, R[SPR_RECT_VMIN], R[SPR_RECT_TEXEL]);
    if (linear == 0) {
        int ix = spr_clampi(SPR_INT(spr_floor(gx)), tw);
        int iy = spr_clampi(SPR_INT(spr_floor(gy)), th);
        for (int ch = 0; ch < 4; ch++) o[ch] = spr_in_texel(px, off + iy * tw + ix, ch);
        return;
    }
    SPR_PRECISE float cx = gx - 0.5f;
    SPR_PRECISE float cy = gy - 0.5f;
    SPR_PRECISE float x0 = spr_floor(cx);
    SPR_PRECISE float y0 = spr_floor(cy);
    SPR_PRECISE float fx = cx - x0;
    SPR_PRECISE float fy = cy - y0;
    SPR_PRECISE float gx0 = 1.0f - fx;
    SPR_PRECISE float gy0 = 1.0f - fy;
    SPR_PRECISE float w00 = gx0 * gy0;
    SPR_PRECISE float w10 = fx * gy0;
    SPR_PRECISE float w01 = gx0 * fy;
    SPR_PRECISE float w11 = fx * fy;
    int ix0 = spr_clampi(SPR_INT(x0), tw);
    int ix1 = spr_clampi(SPR_INT(x0) + 1, tw);
    int iy0 = spr_clampi(SPR_INT(y0), th);
    int iy1 = spr_clampi(SPR_INT(y0) + 1, th);
    for (int ch = 0; ch < 4; ch++) {
        SPR_PRECISE float a = w00 * spr_in_texel(px, off + iy0 * tw + ix0, ch);
        SPR_PRECISE float b = w10 * spr_in_texel(px, off + iy0 * tw + ix1, ch);
        SPR_PRECISE float c = w01 * spr_in_texel(px, off + iy1 * tw + ix0, ch);
        SPR_PRECISE float e = w11 * spr_in_texel(px, off + iy1 * tw + ix1, ch);
        SPR_PRECISE float v = ((a + b) + c) + e;
        o[ch] = v;
    }
}

/* Is a sampled texel a fragment?  α > 0 and α ≥ the alpha reference. */
SPR_FN int spr_rect_alpha_passes(float alpha, float alpha_ref)
{
    if (alpha > 0.0f && alpha >= alpha_ref) return 1;
    return 0;
}

/* What a rectangle fragment offers the colour plane (SPR_ROUT_*) from its
 * texel tx = (c, α). */
SPR_FN void spr_rect_fragment(int out_kind, SPR_CARR tx[4], SPR_OARR src[4])
{
    if (out_kind == SPR_ROUT_COLOR) {
        src[0] = tx[0];
        src[1] = tx[1];
        src[2] = tx[2];
        src[3] = 1.0f;
    } else if (out_kind == SPR_ROUT_BLACK) {
        spr_zero4(src);
        src[3] = 1.0f;
    } else if (out_kind == SPR_ROUT_LUMINANCE) {
        src[0] = tx[3];
        src[1] = tx[3];
        src[2] = tx[3];
        src[3] = 0.0f;
    } else {
        float c[3];
        for (int ch = 0; ch < 3; ch++) c[ch] = tx[ch];
        spr_weighted4(tx[3], c, src);
    }
}

/* The domain sum over the background: rgb + (1 − min(max(a, 0), 1))·bg,
 * alpha 1 where a > 0 (SPEC 7.7). */
SPR_FN void spr_domain_resolve(SPR_CARR acc[4], SPR_CARR bg[3], SPR_OARR o[4])
{
    float a = acc[3];
    if (a < 0.0f) a = 0.0f;
    if (a > 1.0f) a = 1.0f;
    SPR_PRECISE float k = 1.0f - a;
    for (int ch = 0; ch < 3; ch++) {
        SPR_PRECISE float kb = k * bg[ch];
        SPR_PRECISE float v = acc[ch] + kb;
        o[ch] = v;
    }
    o[3] = 0.0f;
    if (acc[3] > 0.0f) o[3] = 1.0f;
}

