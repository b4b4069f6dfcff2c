/* shade.h — deferred shading and environment lookups (SPEC §4.3, §6.3);
 * prm is the parameter array of SPR_PARAM_LIST (spr_backend.h); the rules
 * of base.h. */

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
