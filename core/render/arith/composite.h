/* composite.h — composite operations (SPEC §4.1 step 3, §4.2, §6, §7.7),
 * one per row of SPR_COMPOSITE_LIST (spr_backend.h).  Each fills the
 * output colour o, the output normal on (Σ w·n, Σ w; zero where the op has
 * none) and the output depth d of one pixel from K input targets, under the
 * parameters prm; the rules of base.h. */

/* Does prm ask for the inputs' normals (shading or environment effects)? */
SPR_FN int spr_wants_normal(SPR_CARR prm[SPR_PRM_COUNT])
{
    if (prm[SPR_PRM_SHADE] != 0.0f || prm[SPR_PRM_ENV] != 0.0f) return 1;
    return 0;
}

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

/* §4.1 step 3: normalise input 0, Phong when prm asks (§4.3); depth copied. */
SPR_FN void spr_comp_normalize(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_CARR prm[SPR_PRM_COUNT],
                               SPR_OARR o[4], SPR_OARR on[4], SPR_OUT d)
{
    float acc[4];
    for (int ch = 0; ch < 4; ch++) acc[ch] = spr_in_color(px, 0, ch);
    spr_normalize_rgba(acc, bg, o);
    spr_zero4(on);
    if (spr_wants_normal(prm) != 0) {
        float nacc[3];
        for (int ch = 0; ch < 3; ch++) nacc[ch] = spr_in_normal(px, 0, ch);
        for (int ch = 0; ch < 4; ch++) on[ch] = spr_in_normal(px, 0, ch);
        spr_shade_pixel(px, prm, nacc, o);
    }
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

/* The §4.2 ε-composite of colour (acc), opacity (op) and, when prm wants
 * normals, the normal plane (nacc) over the inputs with d_f(k) ≤ d + ε_t,
 * in input order; gives d = min_k d_f(k). */
SPR_FN float spr_eps_composite(SPR_PIXEL px, int K, float eps_t, SPR_CARR prm[SPR_PRM_COUNT], int with_opacity,
                               SPR_OARR acc[4], SPR_OARR nacc[4], SPR_OUT op)
{
    float dmin = spr_nearest_depth(px, K);
    SPR_PRECISE float limit = dmin + eps_t;
    int wn = spr_wants_normal(prm);
    SPR_PRECISE float a[4];
    SPR_PRECISE float na[4];
    SPR_PRECISE float sop = 0.0f;
    for (int ch = 0; ch < 4; ch++) {
        a[ch] = 0.0f;
        na[ch] = 0.0f;
    }
    SPR_NOTE(px, SPR_NOTE_EPS_NEAREST, -1, dmin, limit, eps_t, SPR_FLOAT(K));
    for (int k = 0; k < K; k++) {
        float dk = spr_in_depth(px, k);
        if (!(dk <= limit)) {
            SPR_NOTE(px, SPR_NOTE_EPS_INPUT, k, dk, limit, 0.0f, a[3]);
            continue;
        }
        for (int ch = 0; ch < 4; ch++) a[ch] = a[ch] + spr_in_color(px, k, ch);
        SPR_NOTE(px, SPR_NOTE_EPS_INPUT, k, dk, limit, 1.0f, a[3]);
        if (with_opacity != 0) sop = sop + spr_in_opacity(px, k);
        if (wn != 0)
            for (int ch = 0; ch < 4; ch++) na[ch] = na[ch] + spr_in_normal(px, k, ch);
    }
    for (int ch = 0; ch < 4; ch++) {
        acc[ch] = a[ch];
        nacc[ch] = na[ch];
    }
    SPR_SET(op) = sop;
    return dmin;
}

/* §4.2 ([ZP] Fig. 6): the ε-composite, normalised; Phong when prm asks (§4.3). */
SPR_FN void spr_comp_deferred(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_CARR prm[SPR_PRM_COUNT],
                              SPR_OARR o[4], SPR_OARR on[4], SPR_OUT d)
{
    float acc[4];
    float nacc[4];
    float op;
    float dmin = spr_eps_composite(px, K, eps_t, prm, 0, acc, nacc, SPR_REF(op));
    spr_normalize_rgba(acc, bg, o);
    for (int ch = 0; ch < 4; ch++) on[ch] = nacc[ch];
    float n3[3];
    for (int ch = 0; ch < 3; ch++) n3[ch] = nacc[ch];
    spr_shade_pixel(px, prm, n3, o);
    SPR_SET(d) = dmin;
}

/* §6.2 step 3, the nearest layer: the ε-composite of colour (C_F), of the
 * opacity (α_F = Σ w·α over Σ w, in the fourth channel) and of the normal;
 * background and 0 where nothing was drawn.  Not shaded here: the final
 * transparent2 op shades C_F. */
SPR_FN void spr_comp_nearest(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_CARR prm[SPR_PRM_COUNT],
                             SPR_OARR o[4], SPR_OARR on[4], SPR_OUT d)
{
    float acc[4];
    float nacc[4];
    float op;
    float dmin = spr_eps_composite(px, K, eps_t, prm, 1, acc, nacc, SPR_REF(op));
    spr_normalize_rgba(acc, bg, o);
    if (acc[3] > 0.0f) {
        SPR_PRECISE float alpha_f = op / acc[3];
        o[3] = alpha_f;
    }
    for (int ch = 0; ch < 4; ch++) on[ch] = nacc[ch];
    SPR_SET(d) = dmin;
}

/* §6.3: the environment seen through the nearest layer, channel ch, for
 * unit normal n facing the viewer, view ray v, cos θ_I = −n·v: refraction
 * ratio e = η_ch^m (m = l + 1 layers when prm MULTI, else 1, Eq. 16),
 * sin²θ_T = e²·sin²θ_I; the refracted ray t = e·v + (e·cos θ_I − cos θ_T)·n,
 * or the reflected colour R under total internal reflection. */
SPR_FN float spr_env_refracted(SPR_PIXEL px, SPR_CARR prm[SPR_PRM_COUNT], SPR_CARR n[3], SPR_CARR v[3], float cos_i,
                               int m, float R, int ch)
{
    SPR_PRECISE float e = spr_ipow(prm[SPR_PRM_ETA + ch], m);
    SPR_PRECISE float c2 = cos_i * cos_i;
    SPR_PRECISE float sin2_i = 1.0f - c2;
    if (sin2_i < 0.0f) sin2_i = 0.0f;
    SPR_PRECISE float e2 = e * e;
    SPR_PRECISE float sin2_t = e2 * sin2_i;
    if (!(sin2_t < 1.0f)) return R;
    SPR_PRECISE float omt = 1.0f - sin2_t;
    SPR_PRECISE float cos_t = spr_sqrt(omt);
    SPR_PRECISE float eci = e * cos_i;
    SPR_PRECISE float coef = eci - cos_t;
    float t[3];
    for (int i = 0; i < 3; i++) {
        SPR_PRECISE float ev = e * v[i];
        SPR_PRECISE float cn = coef * n[i];
        SPR_PRECISE float ti = ev + cn;
        t[i] = ti;
    }
    return spr_env_texel(px, prm[SPR_PRM_ENV_SIZE], t, ch);
}

/* §6.2 step 3, the final image from input 0 = the nearest layer (C_F, α_F,
 * n_F) and input 1 = the average of the other layers (C_O, α_total):
 * I = α_F·C_F + (1 − α_F)·C_O where the nearest layer has a fragment (its
 * depth below the far plane), the background elsewhere; alpha 1 or 0.
 * C_F is Phong-shaded when prm asks (§4.3).  With environment effects
 * (§6.3; the other layers were drawn over a zero background):
 *   l = round(α_total/α), absorption A = (1 − α)^l (Eq. 15),
 *   F = F0 + (1 − F0)(1 − cos θ_I)^5 (Schlick), F0 = ((1 − η)/(1 + η))²,
 *   behind = C_O + A·T (T: the refracted environment, spr_env_refracted),
 *   I = F·R + (1 − F)·(α_F·C_F + (1 − α_F)·behind), R = env(reflected ray),
 * per channel (three η: dispersion); env(v) where nothing was drawn. */
SPR_FN void spr_comp_transparent2(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_CARR prm[SPR_PRM_COUNT],
                                  SPR_OARR o[4], SPR_OARR on[4], SPR_OUT d)
{
    float dn = spr_in_depth(px, 0);
    SPR_SET(d) = dn;
    spr_zero4(on);
    int env = 0;
    if (prm[SPR_PRM_ENV] != 0.0f) env = 1;
    float v[3];
    v[0] = 0.0f;
    v[1] = 0.0f;
    v[2] = 1.0f;
    if (spr_wants_normal(prm) != 0) spr_view_dir(prm, spr_px_cx(px), spr_px_cy(px), v);
    if (!(dn < 1.0f)) {
        for (int ch = 0; ch < 3; ch++) {
            o[ch] = bg[ch];
            if (env != 0) o[ch] = spr_env_texel(px, prm[SPR_PRM_ENV_SIZE], v, ch);
        }
        o[3] = 0.0f;
        return;
    }
    float a = spr_in_color(px, 0, 3);
    SPR_PRECISE float oma = 1.0f - a;
    float cf[3];
    for (int ch = 0; ch < 3; ch++) cf[ch] = spr_in_color(px, 0, ch);
    float n[3];
    int have_n = 0;
    if (spr_wants_normal(prm) != 0) {
        float nacc[3];
        for (int ch = 0; ch < 3; ch++) nacc[ch] = spr_in_normal(px, 0, ch);
        have_n = spr_facing_normal(nacc, v, n);
        if (have_n != 0) {
            on[0] = n[0];
            on[1] = n[1];
            on[2] = n[2];
            on[3] = 1.0f;
        }
    }
    if (have_n != 0 && prm[SPR_PRM_SHADE] != 0.0f) {
        float sh[3];
        spr_phong(prm, cf, n, v, sh);
        for (int ch = 0; ch < 3; ch++) cf[ch] = sh[ch];
    }
    if (env == 0) {
        for (int ch = 0; ch < 3; ch++) {
            SPR_PRECISE float f = a * cf[ch];
            SPR_PRECISE float g = oma * spr_in_color(px, 1, ch);
            SPR_PRECISE float x = f + g;
            o[ch] = x;
        }
        o[3] = 1.0f;
        return;
    }
    if (have_n == 0) {
        n[0] = -v[0];
        n[1] = -v[1];
        n[2] = -v[2];
    }
    SPR_PRECISE float nv = (n[0] * v[0] + n[1] * v[1]) + n[2] * v[2];
    SPR_PRECISE float cos_i = -nv;
    SPR_PRECISE float lq = spr_in_color(px, 1, 3) / prm[SPR_PRM_ALPHA];
    SPR_PRECISE float lr = spr_floor(lq + 0.5f);
    if (!(lr >= 0.0f)) lr = 0.0f;
    if (lr > 64.0f) lr = 64.0f;
    int l = SPR_INT(lr);
    int m = 1;
    if (prm[SPR_PRM_MULTI] != 0.0f) m = l + 1;
    SPR_PRECISE float oml = 1.0f - prm[SPR_PRM_ALPHA];
    SPR_PRECISE float absorb = spr_ipow(oml, l);
    SPR_PRECISE float two_c = cos_i * 2.0f;
    float r[3];
    for (int i = 0; i < 3; i++) {
        SPR_PRECISE float tn = two_c * n[i];
        SPR_PRECISE float ri = v[i] + tn;
        r[i] = ri;
    }
    SPR_PRECISE float omc = 1.0f - cos_i;
    SPR_PRECISE float omc5 = spr_ipow(omc, 5);
    for (int ch = 0; ch < 3; ch++) {
        float R = spr_env_texel(px, prm[SPR_PRM_ENV_SIZE], r, ch);
        float T = spr_env_refracted(px, prm, n, v, cos_i, m, R, ch);
        SPR_PRECISE float eta = prm[SPR_PRM_ETA + ch];
        SPR_PRECISE float f0n = 1.0f - eta;
        SPR_PRECISE float f0d = 1.0f + eta;
        SPR_PRECISE float f0q = f0n / f0d;
        SPR_PRECISE float f0 = f0q * f0q;
        SPR_PRECISE float omf0 = 1.0f - f0;
        SPR_PRECISE float fr = omf0 * omc5;
        SPR_PRECISE float F = f0 + fr;
        SPR_PRECISE float at = absorb * T;
        SPR_PRECISE float behind = spr_in_color(px, 1, ch) + at;
        SPR_PRECISE float fc = a * cf[ch];
        SPR_PRECISE float gb = oma * behind;
        SPR_PRECISE float trans = fc + gb;
        SPR_PRECISE float fR = F * R;
        SPR_PRECISE float omF = 1.0f - F;
        SPR_PRECISE float ft = omF * trans;
        SPR_PRECISE float x = fR + ft;
        o[ch] = x;
    }
    o[3] = 1.0f;
}

/* §6.1 ([ZP] §3.3): I = (1/K) Σ_k I_k, every channel; depth = min_k d_f(k). */
SPR_FN void spr_comp_average(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_CARR prm[SPR_PRM_COUNT],
                             SPR_OARR o[4], SPR_OARR on[4], SPR_OUT d)
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
    spr_zero4(on);
    SPR_SET(d) = dmin;
}

/* §6.4: depth-peeled layers, input j = layer j (0 nearest), each (c, α)
 * where its depth is below the far plane: blended back to front over the
 * background, c = α·c_j + (1 − α)·c; alpha 1 where any layer has a
 * fragment, else 0; depth of layer 0. */
SPR_FN void spr_comp_peel(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_CARR prm[SPR_PRM_COUNT],
                          SPR_OARR o[4], SPR_OARR on[4], SPR_OUT d)
{
    SPR_PRECISE float acc[3];
    for (int ch = 0; ch < 3; ch++) acc[ch] = bg[ch];
    float covered = 0.0f;
    for (int j = K - 1; j >= 0; j--) {
        float dj = spr_in_depth(px, j);
        if (!(dj < 1.0f)) continue;
        covered = 1.0f;
        float a = spr_in_color(px, j, 3);
        SPR_PRECISE float oma = 1.0f - a;
        for (int ch = 0; ch < 3; ch++) {
            SPR_PRECISE float f = a * spr_in_color(px, j, ch);
            SPR_PRECISE float g = oma * acc[ch];
            acc[ch] = f + g;
        }
    }
    for (int ch = 0; ch < 3; ch++) o[ch] = acc[ch];
    o[3] = covered;
    spr_zero4(on);
    SPR_SET(d) = spr_in_depth(px, 0);
}

/* §7.7: summed domain primitives of input 0 over the background; depth copied. */
SPR_FN void spr_comp_domainsum(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_CARR prm[SPR_PRM_COUNT],
                               SPR_OARR o[4], SPR_OARR on[4], SPR_OUT d)
{
    float acc[4];
    for (int ch = 0; ch < 4; ch++) acc[ch] = spr_in_color(px, 0, ch);
    spr_domain_resolve(acc, bg, o);
    spr_zero4(on);
    SPR_SET(d) = spr_in_depth(px, 0);
}

/* §7.7 soft dark back faces: rgb of input 0 clamped below at 0 (+0 for
 * −0 too), alpha and depth copied. */
SPR_FN void spr_comp_clamp(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_CARR prm[SPR_PRM_COUNT],
                           SPR_OARR o[4], SPR_OARR on[4], SPR_OUT d)
{
    for (int ch = 0; ch < 3; ch++) {
        float v = spr_in_color(px, 0, ch);
        if (!(v > 0.0f)) v = 0.0f;
        o[ch] = v;
    }
    o[3] = spr_in_color(px, 0, 3);
    spr_zero4(on);
    SPR_SET(d) = spr_in_depth(px, 0);
}

/* Does fragment (ta, pa) come before (tb, pb)?  Depth, then primitive. */
SPR_FN int spr_frag_before(float ta, int pa, float tb, int pb)
{
    if (ta < tb) return 1;
    if (ta == tb && pa < pb) return 1;
    return 0;
}

/* §7.7 prefix: the pixel's fragment list (in any order) sorted by (t,
 * primitive), at most SPR_LIST_MAX front-most kept; the front-most and,
 * in that order, every later one whose rectangle is its neighbour are
 * summed and resolved over the background; depth = the front-most t
 * (1 when the list is empty). */
SPR_FN void spr_comp_prefix(SPR_PIXEL px, int K, float eps_t, SPR_CARR bg[3], SPR_CARR prm[SPR_PRM_COUNT],
                            SPR_OARR o[4], SPR_OARR on[4], SPR_OUT d)
{
    float kt[SPR_LIST_MAX];
    int kp[SPR_LIST_MAX];
    int kn[SPR_LIST_MAX];
    int m = 0;
    int node = spr_list_first(px);
    while (node >= 0) {
        float t = spr_list_t(px, node);
        int p = spr_list_prim(px, node);
        int pos = m;
        if (m == SPR_LIST_MAX) {
            pos = -1;
            if (spr_frag_before(t, p, kt[SPR_LIST_MAX - 1], kp[SPR_LIST_MAX - 1]) != 0) pos = SPR_LIST_MAX - 1;
        }
        if (pos >= 0) {
            while (pos > 0 && spr_frag_before(t, p, kt[pos - 1], kp[pos - 1]) != 0) {
                kt[pos] = kt[pos - 1];
                kp[pos] = kp[pos - 1];
                kn[pos] = kn[pos - 1];
                pos = pos - 1;
            }
            kt[pos] = t;
            kp[pos] = p;
            kn[pos] = node;
            if (m < SPR_LIST_MAX) m = m + 1;
        }
        node = spr_list_next(px, node);
    }
    SPR_PRECISE float acc[4];
    for (int ch = 0; ch < 4; ch++) acc[ch] = 0.0f;
    for (int i = 0; i < m; i++) {
        if (i > 0 && spr_neighbour(px, kp[0], kp[i]) == 0) {
            SPR_NOTE(px, SPR_NOTE_PREFIX_NODE, kp[i], kt[i], 0.0f, SPR_FLOAT(i), acc[3]);
            continue;
        }
        for (int ch = 0; ch < 4; ch++) acc[ch] = acc[ch] + spr_list_src(px, kn[i], ch);
        SPR_NOTE(px, SPR_NOTE_PREFIX_NODE, kp[i], kt[i], 1.0f, SPR_FLOAT(i), acc[3]);
    }
    spr_domain_resolve(acc, bg, o);
    spr_zero4(on);
    SPR_SET(d) = 1.0f;
    if (m > 0) SPR_SET(d) = kt[0];
}
