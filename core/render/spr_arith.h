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
 *   SPR_IOARR      float                       inout float array the function reads and updates
 *   SPR_OUT        float *                     out float   scalar the function sets
 *   SPR_SET(x)     (*(x))                      x           the scalar behind SPR_OUT
 *   SPR_REF(x)     &(x)                        x           pass a local as SPR_OUT
 *   SPR_FLOAT(i)   ((float)(i))                float(i)    int to float (exact below 2^24)
 *   SPR_INT(x)     ((int)(x))                  int(x)      float to int, truncating (small whole values)
 *   SPR_PIXEL      const spr_pixel_in *        ivec2       where a pixel's inputs live
 *   SPR_NOTE(px, tag, k, a, b, c, d)  a step of a per-pixel function, kept only at the
 *                  probed pixel of a pixel history (spr_probe_add_note / a buffer append;
 *                  nothing in normal GL programs); tags SPR_NOTE_* of spr_backend.h
 * and each backend supplies how inputs are fetched:
 *   spr_in_depth(px, k)      stored depth d_f of input target k
 *   spr_in_color(px, k, ch)  channel ch of input target k's colour plane
 *   spr_in_opacity(px, k)    input target k's opacity plane
 *   spr_in_normal(px, k, ch) channel ch of input target k's normal plane
 *   spr_px_cx(px), spr_px_cy(px)  the pixel centre x + 0.5, y + 0.5 (exact)
 *   spr_in_env(px, f, i, j, ch)   channel ch of texel (i, j) of cube face f
 *   spr_in_texel(px, k, ch)  channel ch of texel k of the rectangles' texels (SPEC 7.5)
 *   spr_list_first(px), spr_list_next(px, node)  a pixel's fragment list (−1 ends it)
 *   spr_list_t(px, node), spr_list_prim(px, node), spr_list_src(px, node, ch)  one node
 *   spr_neighbour(px, a, b)  1 when rectangle b is a neighbour of rectangle a
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

/* Ray–plane intersection: 1 when the ray meets the plane through p with
 * normal n at 0 ≤ t ≤ 1; gives t, the hit point relative to p
 * (q = o0 + t·d − p) and den = d·n (den > 0: back-facing; set even when
 * the result is 0).  Shared by disks and rectangles. */
SPR_FN int spr_ray_plane(SPR_CARR o0[3], SPR_CARR d[3], SPR_CARR p[3], SPR_CARR n[3], SPR_OUT t_out, SPR_OARR q[3],
                         SPR_OUT den_out)
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
    SPR_SET(t_out) = t;
    q[0] = q0;
    q[1] = q1;
    q[2] = q2;
    return 1;
}

/* Ray–disk intersection: 1 when the closed disk (p, n, r) covers the ray
 * within 0 ≤ t ≤ 1 (ρ² ≤ 1), with t, ρ² and den = d·n (den > 0: back-facing;
 * den is set even when the result is 0). */
SPR_FN int spr_ray_disk(SPR_CARR o0[3], SPR_CARR d[3], SPR_CARR p[3], SPR_CARR n[3], float r, SPR_OUT t_out,
                        SPR_OUT rho2_out, SPR_OUT den_out)
{
    float t;
    float q[3];
    if (spr_ray_plane(o0, d, p, n, SPR_REF(t), q, den_out) == 0) return 0;
    SPR_PRECISE float qq = (q[0] * q[0] + q[1] * q[1]) + q[2] * q[2];
    SPR_PRECISE float rho2 = qq / (r * r);
    if (!(rho2 <= 1.0f)) return 0;
    SPR_SET(t_out) = t;
    SPR_SET(rho2_out) = rho2;
    return 1;
}

/* Ray–ellipse intersection: 1 when the closed elliptical splat (p, n, e)
 * covers the ray within 0 ≤ t ≤ 1, with t, ρ² and den as spr_ray_disk.
 * e = (u, r_v): the unit major tangent axis u and the minor radius r_v;
 * r = r_u is the major radius (the splat's bounding radius).  v = n × u
 * (so n = u × v), ρ² = (q·u / r_u)² + (q·v / r_v)².  An ellipse with
 * r_v == r_u is a circle and takes the circle's arithmetic, bit for bit. */
SPR_FN int spr_ray_ellipse(SPR_CARR o0[3], SPR_CARR d[3], SPR_CARR p[3], SPR_CARR n[3], SPR_CARR e[4], float r,
                           SPR_OUT t_out, SPR_OUT rho2_out, SPR_OUT den_out)
{
    if (e[3] == r) return spr_ray_disk(o0, d, p, n, r, t_out, rho2_out, den_out);
    float t;
    float q[3];
    if (spr_ray_plane(o0, d, p, n, SPR_REF(t), q, den_out) == 0) return 0;
    SPR_PRECISE float v0 = n[1] * e[2] - n[2] * e[1];
    SPR_PRECISE float v1 = n[2] * e[0] - n[0] * e[2];
    SPR_PRECISE float v2 = n[0] * e[1] - n[1] * e[0];
    SPR_PRECISE float a = (q[0] * e[0] + q[1] * e[1]) + q[2] * e[2];
    SPR_PRECISE float b = (q[0] * v0 + q[1] * v1) + q[2] * v2;
    SPR_PRECISE float au = a / r;
    SPR_PRECISE float bv = b / e[3];
    SPR_PRECISE float rho2 = au * au + bv * bv;
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

/* Does splat (p, n, e, r) yield a fragment at this pixel?  Covered (above;
 * e as spr_ray_ellipse, e = (0, 0, 0, r) for a circular splat),
 * not back-facing when culling, and not inside the nearest layer when the
 * draw has a depth mask (z_near: the mask target's stored depth).  Gives t,
 * ρ² and ρ = sqrt(ρ²). */
SPR_FN int spr_splat_covers(SPR_CARR o0[3], SPR_CARR d[3], SPR_CARR p[3], SPR_CARR n[3], SPR_CARR e[4], float r,
                            int cull, int mask, float z_near, float eps_t, SPR_OUT t_out, SPR_OUT rho2_out,
                            SPR_OUT rho_out)
{
    float t;
    float rho2;
    float den;
    if (spr_ray_ellipse(o0, d, p, n, e, r, SPR_REF(t), SPR_REF(rho2), SPR_REF(den)) == 0) return 0;
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

/* ---- deferred shading and environment effects (SPEC §4.3, §6.3) ----
 * prm is the parameter array of SPR_PARAM_LIST (spr_backend.h). */

/* x^e for a whole e ≥ 0 by repeated squaring (SPEC §4.3 [decision]). */
SPR_FN float spr_ipow(float x, int e)
{
    SPR_PRECISE float r = 1.0f;
    SPR_PRECISE float b = x;
    int k = e;
    while (k > 0) {
        if (k % 2 == 1) r = r * b;
        k = k / 2;
        if (k > 0) b = b * b;
    }
    return r;
}

/* u = a/|a| with the correctly rounded sqrt; 0 when a is zero. */
SPR_FN int spr_normalize3(SPR_CARR a[3], SPR_OARR u[3])
{
    SPR_PRECISE float l2 = (a[0] * a[0] + a[1] * a[1]) + a[2] * a[2];
    if (!(l2 > 0.0f)) return 0;
    SPR_PRECISE float l = spr_sqrt(l2);
    SPR_PRECISE float x = a[0] / l;
    SPR_PRECISE float y = a[1] / l;
    SPR_PRECISE float z = a[2] / l;
    u[0] = x;
    u[1] = y;
    u[2] = z;
    return 1;
}

/* Unit direction v of the ray through pixel centre (cx, cy) (SPEC §2). */
SPR_FN void spr_view_dir(SPR_CARR prm[SPR_PRM_COUNT], float cx, float cy, SPR_OARR v[3])
{
    float M[16];
    for (int i = 0; i < 16; i++) M[i] = prm[SPR_PRM_M + i];
    float o0[3];
    float d[3];
    spr_ray_of_pixel(M, prm[SPR_PRM_SX], prm[SPR_PRM_SY], cx, cy, o0, d);
    float u[3];
    u[0] = 0.0f;
    u[1] = 0.0f;
    u[2] = 1.0f;
    if (spr_normalize3(d, u) == 0) {
        u[0] = 0.0f;
        u[1] = 0.0f;
        u[2] = 1.0f;
    }
    v[0] = u[0];
    v[1] = u[1];
    v[2] = u[2];
}

/* The composited normal acc (Σ w·n) made unit and turned towards the
 * viewer (n·v ≤ 0: point surfaces are two-sided); 0 when there is none. */
SPR_FN int spr_facing_normal(SPR_CARR acc[3], SPR_CARR v[3], SPR_OARR n[3])
{
    float u[3];
    if (spr_normalize3(acc, u) == 0) return 0;
    SPR_PRECISE float nv = (u[0] * v[0] + u[1] * v[1]) + u[2] * v[2];
    for (int i = 0; i < 3; i++) {
        n[i] = u[i];
        if (nv > 0.0f) n[i] = -u[i];
    }
    return 1;
}

/* Phong with one directional light (SPEC §4.3): for unit n facing the
 * viewer, view ray v, L = prm LIGHT, V = −v, R = 2(n·L)·n − L:
 * o = c·(ka + kd·max(n·L, 0)) + ks·max(R·V, 0)^e, no specular where n·L ≤ 0. */
SPR_FN void spr_phong(SPR_CARR prm[SPR_PRM_COUNT], SPR_CARR c[3], SPR_CARR n[3], SPR_CARR v[3], SPR_OARR o[3])
{
    float L[3];
    for (int i = 0; i < 3; i++) L[i] = prm[SPR_PRM_LIGHT + i];
    SPR_PRECISE float ndl = (n[0] * L[0] + n[1] * L[1]) + n[2] * L[2];
    SPR_PRECISE float diff = 0.0f;
    SPR_PRECISE float spec = 0.0f;
    if (ndl > 0.0f) {
        diff = ndl;
        SPR_PRECISE float two = ndl * 2.0f;
        SPR_PRECISE float r0 = two * n[0] - L[0];
        SPR_PRECISE float r1 = two * n[1] - L[1];
        SPR_PRECISE float r2 = two * n[2] - L[2];
        SPR_PRECISE float rv = (r0 * v[0] + r1 * v[1]) + r2 * v[2];
        SPR_PRECISE float rdv = -rv;
        if (rdv > 0.0f) spec = spr_ipow(rdv, SPR_INT(prm[SPR_PRM_EXP]));
    }
    SPR_PRECISE float kdd = prm[SPR_PRM_KD] * diff;
    SPR_PRECISE float lit = prm[SPR_PRM_KA] + kdd;
    SPR_PRECISE float s = prm[SPR_PRM_KS] * spec;
    for (int ch = 0; ch < 3; ch++) {
        SPR_PRECISE float cl = c[ch] * lit;
        SPR_PRECISE float x = cl + s;
        o[ch] = x;
    }
}

/* Shade the normalised colour o of a pixel in place when prm asks for Phong
 * and the pixel has a fragment (o[3] = 1) and a normal (nacc = Σ w·n). */
SPR_FN void spr_shade_pixel(SPR_PIXEL px, SPR_CARR prm[SPR_PRM_COUNT], SPR_CARR nacc[3], SPR_IOARR o[4])
{
    if (prm[SPR_PRM_SHADE] == 0.0f || o[3] == 0.0f) return;
    float v[3];
    spr_view_dir(prm, spr_px_cx(px), spr_px_cy(px), v);
    float n[3];
    if (spr_facing_normal(nacc, v, n) == 0) return;
    float c[3];
    for (int ch = 0; ch < 3; ch++) c[ch] = o[ch];
    float s[3];
    spr_phong(prm, c, n, v, s);
    for (int ch = 0; ch < 3; ch++) o[ch] = s[ch];
}

/* Channel ch of the cube map's nearest texel in direction dir (SPEC §6.3):
 * the major axis picks the face (GL's table: +x, −x, +y, −y, +z, −z), the
 * other two coordinates divided by it give (s, t) in [−1, 1], texel
 * floor((s + 1)·½·size) clamped to the face; no trigonometry. */
SPR_FN float spr_env_texel(SPR_PIXEL px, float size, SPR_CARR dir[3], int ch)
{
    float x = dir[0];
    float y = dir[1];
    float z = dir[2];
    float ax = x;
    float ay = y;
    float az = z;
    if (x < 0.0f) ax = -x;
    if (y < 0.0f) ay = -y;
    if (z < 0.0f) az = -z;
    int face = 0;
    float ma = ax;
    float sc = -z;
    float tc = -y;
    if (ax >= ay && ax >= az) {
        if (!(x > 0.0f)) {
            face = 1;
            sc = z;
        }
    } else if (ay >= az) {
        face = 2;
        ma = ay;
        sc = x;
        tc = z;
        if (!(y > 0.0f)) {
            face = 3;
            tc = -z;
        }
    } else {
        face = 4;
        ma = az;
        sc = x;
        tc = -y;
        if (!(z > 0.0f)) {
            face = 5;
            sc = -x;
        }
    }
    if (!(ma > 0.0f)) return 0.0f;
    SPR_PRECISE float qs = sc / ma;
    SPR_PRECISE float qt = tc / ma;
    SPR_PRECISE float us = (qs + 1.0f) * 0.5f;
    SPR_PRECISE float ut = (qt + 1.0f) * 0.5f;
    SPR_PRECISE float fi = spr_floor(us * size);
    SPR_PRECISE float fj = spr_floor(ut * size);
    SPR_PRECISE float last = size - 1.0f;
    if (!(fi >= 0.0f)) fi = 0.0f;
    if (!(fj >= 0.0f)) fj = 0.0f;
    if (fi > last) fi = last;
    if (fj > last) fj = last;
    return spr_in_env(px, face, SPR_INT(fi), SPR_INT(fj), ch);
}

/* ---- composite operations (SPEC §4.1 step 3, §4.2, §6), one per row of
 * SPR_COMPOSITE_LIST (spr_backend.h).  Each fills the output colour o, the
 * output normal on (Σ w·n, Σ w; zero where the op has none) and the output
 * depth d of one pixel from K input targets, under the parameters prm. ---- */

SPR_FN void spr_zero4(SPR_OARR o[4])
{
    for (int ch = 0; ch < 4; ch++) o[ch] = 0.0f;
}

/* ---- domain primitives: textured rectangles (SPEC §7.7) ----
 * R is a rectangle's float record (SPR_RECT_LIST, spr_backend.h). */

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
