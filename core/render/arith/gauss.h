/* gauss.h — the Gaussian splatting references (SPEC §10; restated operation
 * by operation in docs/gaussians.md): the shared exponential (§10.6),
 * per-Gaussian preprocessing of 3D Gaussians (§10.3) and of 2D surfels
 * (§10.5), the per-pixel front-to-back loop of gauss3d and gauss2d over a
 * tile's sorted list (§10.4, §10.5) and the fragment of the viewers' blend
 * (§10.7).  g is a frame's parameter array (SPR_GPRM_LIST, spr_backend.h,
 * filled once on the host); a record is one Gaussian's preprocessed values
 * (SPR_GREC_LIST).  Pixels are in pixel-index coordinates: pixel (i, j),
 * j = 0 the top row, has its centre at (i, j); plane row y is j = H − 1 − y.
 * The rules of base.h; literals are exact (other constants are parameters
 * or come from C as bit patterns: spr_exp_coef). */

/* e^x for x ≤ 0 (SPEC §10.6): n = floor(x·log2 e + ½), r = (x − n·ln2_hi) − n·ln2_lo
 * (ln2_hi has 17 significant bits, so n·ln2_hi is exact for |n| ≤ 126), e^r by
 * its Taylor polynomial to degree 7 written 1 + (r + r²·p(r)), then · 2^n
 * exactly; 0 below −87 (where 2^n would leave the normal range).  Within 1 ulp
 * of the correctly rounded e^x on [−10, 0] (tests/test_gauss.c). */
SPR_FN float spr_exp(float x)
{
    if (!(x >= -87.0f)) return 0.0f;
    SPR_PRECISE float t = x * spr_exp_coef[0];
    SPR_PRECISE float th = t + 0.5f;
    SPR_PRECISE float n = spr_floor(th);
    SPR_PRECISE float nh = n * spr_exp_coef[1];
    SPR_PRECISE float a = x - nh;
    SPR_PRECISE float nl = n * spr_exp_coef[2];
    SPR_PRECISE float r = a - nl;
    SPR_PRECISE float p = spr_exp_coef[3];
    for (int k = 4; k < SPR_EXP_COEFS; k++) p = p * r + spr_exp_coef[k];
    SPR_PRECISE float pr = p * r;
    SPR_PRECISE float q = pr * r;
    SPR_PRECISE float s = r + q;
    SPR_PRECISE float e = 1.0f + s;
    SPR_PRECISE float v = spr_ldexp(e, SPR_INT(n));
    return v;
}

/* (a0·b0 + a1·b1) + a2·b2: the three-term sums of SPEC §10.3, left to right. */
SPR_FN float spr_sum3(float a0, float b0, float a1, float b1, float a2, float b2)
{
    SPR_PRECISE float a = a0 * b0;
    SPR_PRECISE float b = a1 * b1;
    SPR_PRECISE float e = a2 * b2;
    SPR_PRECISE float ab = a + b;
    SPR_PRECISE float v = ab + e;
    return v;
}

/* The rotation matrix (row-major) of the unit quaternion q = (w, x, y, z)
 * (SPEC §10.3 step 2), in float: first row 1 − 2(y² + z²), 2(xy − wz), 2(xz + wy). */
SPR_FN void spr_quat_matrix(SPR_CARR q[4], SPR_OARR M[9])
{
    SPR_PRECISE float xx = q[1] * q[1];
    SPR_PRECISE float yy = q[2] * q[2];
    SPR_PRECISE float zz = q[3] * q[3];
    SPR_PRECISE float xy = q[1] * q[2];
    SPR_PRECISE float xz = q[1] * q[3];
    SPR_PRECISE float yz = q[2] * q[3];
    SPR_PRECISE float wx = q[0] * q[1];
    SPR_PRECISE float wy = q[0] * q[2];
    SPR_PRECISE float wz = q[0] * q[3];
    SPR_PRECISE float s0 = yy + zz;
    SPR_PRECISE float s1 = xx + zz;
    SPR_PRECISE float s2 = xx + yy;
    SPR_PRECISE float d01 = xy - wz;
    SPR_PRECISE float d02 = xz + wy;
    SPR_PRECISE float d10 = xy + wz;
    SPR_PRECISE float d12 = yz - wx;
    SPR_PRECISE float d20 = xz - wy;
    SPR_PRECISE float d21 = yz + wx;
    SPR_PRECISE float m0 = 2.0f * s0;
    SPR_PRECISE float m4 = 2.0f * s1;
    SPR_PRECISE float m8 = 2.0f * s2;
    SPR_PRECISE float r0 = 1.0f - m0;
    SPR_PRECISE float r1 = 2.0f * d01;
    SPR_PRECISE float r2 = 2.0f * d02;
    SPR_PRECISE float r3 = 2.0f * d10;
    SPR_PRECISE float r4 = 1.0f - m4;
    SPR_PRECISE float r5 = 2.0f * d12;
    SPR_PRECISE float r6 = 2.0f * d20;
    SPR_PRECISE float r7 = 2.0f * d21;
    SPR_PRECISE float r8 = 1.0f - m8;
    M[0] = r0;
    M[1] = r1;
    M[2] = r2;
    M[3] = r3;
    M[4] = r4;
    M[5] = r5;
    M[6] = r6;
    M[7] = r7;
    M[8] = r8;
}

/* t = R·μ + T, each component an explicit left-to-right sum (SPEC §10.3 step 1). */
SPR_FN void spr_gauss_to_camera(SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR mu[3], SPR_OARR t[3])
{
    for (int i = 0; i < 3; i++) {
        float abc = spr_sum3(g[SPR_GPRM_R + 3 * i], mu[0], g[SPR_GPRM_R + 3 * i + 1], mu[1], g[SPR_GPRM_R + 3 * i + 2], mu[2]);
        SPR_PRECISE float v = abc + g[SPR_GPRM_T + i];
        t[i] = v;
    }
}

/* Clear a record: culled for `why` (SPR_GCULL_*), no radius, empty rectangles. */
SPR_FN void spr_gauss_cull(float why, SPR_IOARR rec[SPR_GREC_FLOATS])
{
    for (int f = 0; f < SPR_GREC_FLOATS; f++) rec[f] = 0.0f;
    rec[SPR_GREC_CULL] = why;
}

/* The tile rectangle of a centre m and radii (rx, ry) (SPEC §10.3 step 8;
 * the extent rule of §10.9) and the pixel box of gauss-blend (§10.7: pixels
 * (i, j) with |i − m.x| ≤ rx and |j − m.y| ≤ ry, clamped to the image; empty
 * when i1 < i0).  Square and quad extents: tiles [trunc((m − r)/16),
 * trunc((m + r + 15)/16)); per-axis extents (gsplat): [floor((m' − r)/16),
 * ceil((m' + r)/16)) with m' = m + 0.5 the continuous centre; both clamped to
 * [0, tiles]. */
SPR_FN void spr_gauss_rects(SPR_CARR g[SPR_GPRM_COUNT], float mx, float my, float rx, float ry, SPR_IOARR rec[SPR_GREC_FLOATS])
{
    float m[2];
    m[0] = mx;
    m[1] = my;
    float rr[2];
    rr[0] = rx;
    rr[1] = ry;
    for (int a = 0; a < 2; a++) {
        float gn = g[SPR_GPRM_GX + a];
        float r = rr[a];
        SPR_PRECISE float lo = m[a] - r;
        SPR_PRECISE float hr = m[a] + r;
        float wn = g[SPR_GPRM_W + a];
        SPR_PRECISE float last = wn - 1.0f;
        if (g[SPR_GPRM_EXT] == SPR_GEXT_BOX_F) {
            /* OpenSplat: pixels [max(0, floor(m − r) − pad), min(W, ceil(m + r) + pad)), every tile they touch */
            SPR_PRECISE float fl0 = spr_floor(lo);
            SPR_PRECISE float p0 = fl0 - g[SPR_GPRM_EXT_PAD];
            SPR_PRECISE float ch1 = spr_ceil(hr);
            SPR_PRECISE float p1 = ch1 + g[SPR_GPRM_EXT_PAD];
            if (!(p0 >= 0.0f)) p0 = 0.0f;
            if (!(p1 <= wn)) p1 = wn;
            SPR_PRECISE float pl = p1 - 1.0f;
            float t0 = 0.0f;
            float t1 = 0.0f;
            if (pl >= p0) {
                SPR_PRECISE float q0 = p0 / 16.0f;
                SPR_PRECISE float q1 = pl / 16.0f;
                SPR_PRECISE float f0 = spr_floor(q0);
                SPR_PRECISE float f1 = spr_floor(q1);
                SPR_PRECISE float f2 = f1 + 1.0f;
                t0 = f0;
                t1 = f2;
            }
            rec[SPR_GREC_RECT + a] = t0;
            rec[SPR_GREC_RECT + 2 + a] = t1;
            rec[SPR_GREC_BOX + a] = p0;
            rec[SPR_GREC_BOX + 2 + a] = pl;
        } else if (g[SPR_GPRM_EXT] == SPR_GEXT_AXES_F) {
            SPR_PRECISE float mc = m[a] + 0.5f;
            SPR_PRECISE float clo = mc - r;
            SPR_PRECISE float chi = mc + r;
            SPR_PRECISE float q0 = clo / 16.0f;
            SPR_PRECISE float q1 = chi / 16.0f;
            SPR_PRECISE float f0 = spr_floor(q0);
            SPR_PRECISE float f1 = spr_ceil(q1);
            if (!(f0 >= 0.0f)) f0 = 0.0f;
            if (f0 > gn) f0 = gn;
            if (!(f1 >= 0.0f)) f1 = 0.0f;
            if (f1 > gn) f1 = gn;
            rec[SPR_GREC_RECT + a] = f0;
            rec[SPR_GREC_RECT + 2 + a] = f1;
        } else {
            SPR_PRECISE float lo16 = lo / 16.0f;
            SPR_PRECISE float hi = hr + 15.0f;
            SPR_PRECISE float hi16 = hi / 16.0f;
            /* min(n, max(0, trunc(v))): for v ≥ 0 trunc is floor, for v in (−1, 0) it is 0 */
            if (!(lo16 >= 0.0f)) lo16 = 0.0f;
            if (lo16 > gn) lo16 = gn;
            if (!(hi16 >= 0.0f)) hi16 = 0.0f;
            if (hi16 > gn) hi16 = gn;
            SPR_PRECISE float t0 = spr_floor(lo16);
            SPR_PRECISE float t1 = spr_floor(hi16);
            rec[SPR_GREC_RECT + a] = t0;
            rec[SPR_GREC_RECT + 2 + a] = t1;
        }
        if (g[SPR_GPRM_EXT] == SPR_GEXT_BOX_F) continue;
        SPR_PRECISE float b0 = spr_ceil(lo);
        SPR_PRECISE float b1 = spr_floor(hr);
        if (!(b0 >= 0.0f)) b0 = 0.0f;
        if (b0 > wn) b0 = wn;
        if (!(b1 <= last)) b1 = last;
        if (b1 < -1.0f) b1 = -1.0f;
        rec[SPR_GREC_BOX + a] = b0;
        rec[SPR_GREC_BOX + 2 + a] = b1;
    }
}

/* |x| without arithmetic that rounds. */
SPR_FN float spr_absf(float x)
{
    SPR_PRECISE float n = -x;
    if (x < 0.0f) return n;
    return x;
}

/* SPEC §10.3 steps 1–4 of the 3D Gaussian (μ, q, s): t = R·μ + T, L = Rq·S,
 * Σ = L·Lᵀ, the Jacobian J (2×3, row-major) with the profile's tangent clamp,
 * T = J·W, A = T·Σ and Σ' = A·Tᵀ (P, 2×2).  Returns SPR_GCULL_NONE, or why
 * the Gaussian is culled before step 5 (near plane, clip box: then only t
 * is set).  The forward pass (spr_gauss_preprocess3d) and its backward
 * (spr_gauss_preprocess3d_bwd) both start here. */
SPR_FN float spr_gauss_project3d(SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR mu[3], SPR_CARR q[4], SPR_CARR s[3], SPR_OARR t[3], SPR_OARR Rq[9],
                                 SPR_OARR L[9], SPR_OARR S[9], SPR_OARR J[6], SPR_OARR T[6], SPR_OARR A[6], SPR_OARR P[4])
{
    spr_gauss_to_camera(g, mu, t);
    if (g[SPR_GPRM_NEAR_LT] != 0.0f) { /* gsplat: culled below the near plane */
        if (t[2] < g[SPR_GPRM_NEAR]) {
            return SPR_GCULL_NEAR;
        }
    } else if (!(t[2] > g[SPR_GPRM_NEAR])) { /* the training code: culled at or below it */
        return SPR_GCULL_NEAR;
    }
    /* step 2: Σ = (Rq·S)(Rq·S)ᵀ, L = Rq·S */
    spr_quat_matrix(q, Rq);
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) {
            SPR_PRECISE float v = Rq[3 * i + k] * s[k];
            L[3 * i + k] = v;
        }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            float v = spr_sum3(L[3 * i], L[3 * j], L[3 * i + 1], L[3 * j + 1], L[3 * i + 2], L[3 * j + 2]);
            S[3 * i + j] = v;
        }
    /* step 3: the Jacobian with clamped tangents (profile rule 2: or not); rule 1's clip box */
    SPR_PRECISE float txz = t[0] / t[2];
    SPR_PRECISE float tyz = t[1] / t[2];
    if (g[SPR_GPRM_CLIP_K] > 0.0f) {
        SPR_PRECISE float nx0 = txz * g[SPR_GPRM_NDC];
        SPR_PRECISE float nx = nx0 + g[SPR_GPRM_NDC + 1];
        SPR_PRECISE float ny0 = tyz * g[SPR_GPRM_NDC + 2];
        SPR_PRECISE float ny = ny0 + g[SPR_GPRM_NDC + 3];
        float ax = spr_absf(nx);
        float ay = spr_absf(ny);
        if (ax > g[SPR_GPRM_CLIP_K] || ay > g[SPR_GPRM_CLIP_K]) {
            return SPR_GCULL_CLIP;
        }
    }
    SPR_PRECISE float cx = txz;
    SPR_PRECISE float cy = tyz;
    float lx = g[SPR_GPRM_LX];
    float ly = g[SPR_GPRM_LY];
    SPR_PRECISE float nlx = -g[SPR_GPRM_LXN];
    SPR_PRECISE float nly = -g[SPR_GPRM_LYN];
    if (g[SPR_GPRM_TCLAMP] != 0.0f) {
        if (cx < nlx) cx = nlx;
        if (cx > lx) cx = lx;
        if (cy < nly) cy = nly;
        if (cy > ly) cy = ly;
    }
    SPR_PRECISE float u = cx * t[2];
    SPR_PRECISE float v = cy * t[2];
    SPR_PRECISE float zz = t[2] * t[2];
    SPR_PRECISE float fu = g[SPR_GPRM_FX] * u;
    SPR_PRECISE float fv = g[SPR_GPRM_FY] * v;
    SPR_PRECISE float qu = fu / zz;
    SPR_PRECISE float qv = fv / zz;
    SPR_PRECISE float j00 = g[SPR_GPRM_FX] / t[2];
    SPR_PRECISE float j02 = -qu;
    SPR_PRECISE float j11 = g[SPR_GPRM_FY] / t[2];
    SPR_PRECISE float j12 = -qv;
    J[0] = j00;
    J[1] = 0.0f;
    J[2] = j02;
    J[3] = 0.0f;
    J[4] = j11;
    J[5] = j12;
    /* step 4: Σ' = (J·W)·Σ·(J·W)ᵀ, every product an explicit sum over k left to right */
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 3; j++) {
            float x = spr_sum3(J[3 * i], g[SPR_GPRM_R + j], J[3 * i + 1], g[SPR_GPRM_R + 3 + j], J[3 * i + 2], g[SPR_GPRM_R + 6 + j]);
            T[3 * i + j] = x;
        }
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 3; j++) {
            float x = spr_sum3(T[3 * i], S[j], T[3 * i + 1], S[3 + j], T[3 * i + 2], S[6 + j]);
            A[3 * i + j] = x;
        }
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            float x = spr_sum3(A[3 * i], T[3 * j], A[3 * i + 1], T[3 * j + 1], A[3 * i + 2], T[3 * j + 2]);
            P[2 * i + j] = x;
        }
    return SPR_GCULL_NONE;
}

/* SPEC §10.3 steps 1–8 for the 3D Gaussian (μ, q, s, o) of colour c (step 9,
 * on the host): the record of gauss3d and gauss-blend. */
SPR_FN void spr_gauss_preprocess3d(SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR mu[3], SPR_CARR q[4], SPR_CARR s[3], float o,
                                   SPR_CARR c[3], SPR_OARR rec[SPR_GREC_FLOATS])
{
    float t[3];
    float Rq[9];
    float L[9];
    float S[9];
    float J[6];
    float T[6];
    float A[6];
    float P[4];
    float why = spr_gauss_project3d(g, mu, q, s, t, Rq, L, S, J, T, A, P);
    for (int f = 0; f < SPR_GREC_FLOATS; f++) rec[f] = 0.0f;
    if (why != SPR_GCULL_NONE) {
        spr_gauss_cull(why, rec);
        return;
    }
    /* step 5: the dilation, the conic and (--gauss-aa) the opacity's compensation */
    SPR_PRECISE float a = P[0] + g[SPR_GPRM_EPS2D];
    float b = P[1];
    SPR_PRECISE float cc = P[3] + g[SPR_GPRM_EPS2D];
    SPR_PRECISE float ac = a * cc;
    SPR_PRECISE float bb = b * b;
    SPR_PRECISE float det = ac - bb;
    if (g[SPR_GPRM_DET_LE] != 0.0f) {
        if (!(det > 0.0f)) {
            spr_gauss_cull(SPR_GCULL_DET, rec);
            return;
        }
    } else if (det == 0.0f) {
        spr_gauss_cull(SPR_GCULL_DET, rec);
        return;
    }
    SPR_PRECISE float k = 1.0f / det;
    SPR_PRECISE float nb = -b;
    SPR_PRECISE float cA = cc * k;
    SPR_PRECISE float cB = nb * k;
    SPR_PRECISE float cC = a * k;
    SPR_PRECISE float op = o;
    if (g[SPR_GPRM_AA] != 0.0f) {
        SPR_PRECISE float p03 = P[0] * P[3];
        SPR_PRECISE float p11 = P[1] * P[1];
        SPR_PRECISE float det0 = p03 - p11;
        SPR_PRECISE float ratio = det0 / det;
        float f = g[SPR_GPRM_AA_MIN];
        if (g[SPR_GPRM_AA_FORM] == 0.0f) {
            if (!(ratio >= f)) ratio = f;
        }
        SPR_PRECISE float sq = spr_sqrt(ratio);
        if (g[SPR_GPRM_AA_FORM] != 0.0f) {
            if (!(sq >= f)) sq = f;
        }
        op = o * sq;
    }
    /* step 6: the extent (profile rule 4) */
    SPR_PRECISE float sum = a + cc;
    SPR_PRECISE float mid = 0.5f * sum;
    SPR_PRECISE float mm = mid * mid;
    SPR_PRECISE float disc = mm - det;
    if (!(disc >= g[SPR_GPRM_EXT_MIN])) disc = g[SPR_GPRM_EXT_MIN];
    SPR_PRECISE float e = spr_sqrt(disc);
    SPR_PRECISE float l1 = mid + e;
    SPR_PRECISE float l2 = mid - e;
    float k3 = g[SPR_GPRM_EXT_K];
    float rx = 0.0f;
    float ry = 0.0f;
    if (g[SPR_GPRM_EXT] == SPR_GEXT_BOX_F) {
        /* OpenSplat's pixel box: k·sqrt(Σ'_aa) of the dilated covariance, not rounded (spr_gauss_rects) */
        SPR_PRECISE float sa = spr_sqrt(a);
        SPR_PRECISE float sc = spr_sqrt(cc);
        SPR_PRECISE float ka = k3 * sa;
        SPR_PRECISE float kc = k3 * sc;
        rx = ka;
        ry = kc;
    } else if (g[SPR_GPRM_EXT] == SPR_GEXT_AXES_F) {
        /* per axis: ceil(k·sqrt(Σ'_aa)) of the dilated covariance */
        SPR_PRECISE float sa = spr_sqrt(a);
        SPR_PRECISE float sc = spr_sqrt(cc);
        SPR_PRECISE float ka = k3 * sa;
        SPR_PRECISE float kc = k3 * sc;
        SPR_PRECISE float ca = spr_ceil(ka);
        SPR_PRECISE float cc3 = spr_ceil(kc);
        rx = ca;
        ry = cc3;
    } else if (g[SPR_GPRM_EXT] == SPR_GEXT_QUAD_F) {
        /* the viewers' quad: half-axes L = k·sqrt(λ) along the eigenvectors, each at most EXT_CAP pixels */
        if (!(l2 > 0.0f)) {
            spr_gauss_cull(SPR_GCULL_DET, rec);
            return;
        }
        SPR_PRECISE float ev = l1 - a;
        SPR_PRECISE float b2 = b * b;
        SPR_PRECISE float ev2 = ev * ev;
        SPR_PRECISE float n2 = b2 + ev2;
        float ux = 1.0f;
        float uy = 0.0f;
        if (n2 > 0.0f) {
            SPR_PRECISE float nl = spr_sqrt(n2);
            SPR_PRECISE float vx = b / nl;
            SPR_PRECISE float vy = ev / nl;
            ux = vx;
            uy = vy;
        }
        SPR_PRECISE float s1 = spr_sqrt(l1);
        SPR_PRECISE float s2 = spr_sqrt(l2);
        SPR_PRECISE float L1 = k3 * s1;
        SPR_PRECISE float L2 = k3 * s2;
        float cap = g[SPR_GPRM_EXT_CAP];
        if (cap > 0.0f && L1 > cap) L1 = cap;
        if (cap > 0.0f && L2 > cap) L2 = cap;
        if (L1 < g[SPR_GPRM_MIN_PX] && L2 < g[SPR_GPRM_MIN_PX]) {
            spr_gauss_cull(SPR_GCULL_SMALL, rec);
            return;
        }
        /* the falloff follows the quad, as the viewers evaluate it in the quad's own coordinates: σ_i = L_i/k
         * (the eigenvalues with their floor, the cap), conic = u·uᵀ/σ₁² + v·vᵀ/σ₂² with v = (u.y, −u.x) */
        SPR_PRECISE float q1 = L1 / k3;
        SPR_PRECISE float q2 = L2 / k3;
        SPR_PRECISE float w1a = q1 * q1;
        SPR_PRECISE float w2a = q2 * q2;
        SPR_PRECISE float w1 = 1.0f / w1a;
        SPR_PRECISE float w2 = 1.0f / w2a;
        SPR_PRECISE float xx = ux * ux;
        SPR_PRECISE float yy = uy * uy;
        SPR_PRECISE float xy = ux * uy;
        SPR_PRECISE float A1 = xx * w1;
        SPR_PRECISE float A2 = yy * w2;
        SPR_PRECISE float C1 = yy * w1;
        SPR_PRECISE float C2 = xx * w2;
        SPR_PRECISE float dw = w1 - w2;
        SPR_PRECISE float nA = A1 + A2;
        SPR_PRECISE float nB = xy * dw;
        SPR_PRECISE float nC = C1 + C2;
        cA = nA;
        cB = nB;
        cC = nC;
        /* the quad's bounding box */
        float aux = spr_absf(ux);
        float auy = spr_absf(uy);
        SPR_PRECISE float x1 = L1 * aux;
        SPR_PRECISE float x2 = L2 * auy;
        SPR_PRECISE float y1 = L1 * auy;
        SPR_PRECISE float y2 = L2 * aux;
        SPR_PRECISE float bx = x1 + x2;
        SPR_PRECISE float by = y1 + y2;
        rx = bx;
        ry = by;
    } else {
        SPR_PRECISE float lmax = l1;
        if (l2 > lmax) lmax = l2;
        SPR_PRECISE float sl = spr_sqrt(lmax);
        SPR_PRECISE float r3 = k3 * sl;
        SPR_PRECISE float r = spr_ceil(r3);
        rx = r;
        ry = r;
    }
    /* step 7: the centre in pixel-index coordinates */
    SPR_PRECISE float txz = t[0] / t[2];
    SPR_PRECISE float tyz = t[1] / t[2];
    SPR_PRECISE float fx = g[SPR_GPRM_FX] * txz;
    SPR_PRECISE float fy = g[SPR_GPRM_FY] * tyz;
    SPR_PRECISE float mx = fx + g[SPR_GPRM_CX];
    SPR_PRECISE float my = fy + g[SPR_GPRM_CY];
    SPR_PRECISE float iz = 1.0f / t[2];
    rec[SPR_GREC_M] = mx;
    rec[SPR_GREC_M + 1] = my;
    rec[SPR_GREC_CONIC] = cA;
    rec[SPR_GREC_CONIC + 1] = cB;
    rec[SPR_GREC_CONIC + 2] = cC;
    rec[SPR_GREC_OPACITY] = op;
    rec[SPR_GREC_DEPTH] = t[2];
    rec[SPR_GREC_INVZ] = iz;
    rec[SPR_GREC_RADIUS] = rx;
    rec[SPR_GREC_RADIUS + 1] = ry;
    for (int ch = 0; ch < 3; ch++) rec[SPR_GREC_COLOR + ch] = c[ch];
    rec[SPR_GREC_CULL] = SPR_GCULL_NONE;
    /* step 8 */
    spr_gauss_rects(g, mx, my, rx, ry, rec);
}

/* Σ_k a[k]·b[k] over 8 terms, left to right from 0 (the quaternion's backward). */
SPR_FN float spr_dot8(SPR_CARR a[8], SPR_CARR b[8])
{
    SPR_PRECISE float s = 0.0f;
    for (int k = 0; k < 8; k++) {
        SPR_PRECISE float p = a[k] * b[k];
        s = s + p;
    }
    return s;
}

/* The backward of spr_quat_matrix: ∂L/∂q from ∂L/∂M (row-major), for the
 * unit quaternion q = (w, x, y, z); each component 2·Σ (∂M_ij/∂q_k / 2)·∂L/∂M_ij. */
SPR_FN void spr_quat_matrix_bwd(SPR_CARR q[4], SPR_CARR dM[9], SPR_OARR dq[4])
{
    SPR_PRECISE float x2 = 2.0f * q[1];
    SPR_PRECISE float y2 = 2.0f * q[2];
    SPR_PRECISE float z2 = 2.0f * q[3];
    SPR_PRECISE float nw = -q[0];
    SPR_PRECISE float nx = -q[1];
    SPR_PRECISE float ny = -q[2];
    SPR_PRECISE float nz = -q[3];
    SPR_PRECISE float nx2 = -x2;
    SPR_PRECISE float ny2 = -y2;
    SPR_PRECISE float nz2 = -z2;
    float a[8];
    float b[8];
    /* w: M01 −2z, M02 2y, M10 2z, M12 −2x, M20 −2y, M21 2x */
    a[0] = nz; b[0] = dM[1]; a[1] = q[2]; b[1] = dM[2]; a[2] = q[3]; b[2] = dM[3]; a[3] = nx; b[3] = dM[5];
    a[4] = ny; b[4] = dM[6]; a[5] = q[1]; b[5] = dM[7]; a[6] = 0.0f; b[6] = 0.0f; a[7] = 0.0f; b[7] = 0.0f;
    float sw = spr_dot8(a, b);
    /* x: M01 2y, M02 2z, M10 2y, M11 −4x, M12 −2w, M20 2z, M21 2w, M22 −4x */
    a[0] = q[2]; b[0] = dM[1]; a[1] = q[3]; b[1] = dM[2]; a[2] = q[2]; b[2] = dM[3]; a[3] = nx2; b[3] = dM[4];
    a[4] = nw; b[4] = dM[5]; a[5] = q[3]; b[5] = dM[6]; a[6] = q[0]; b[6] = dM[7]; a[7] = nx2; b[7] = dM[8];
    float sx = spr_dot8(a, b);
    /* y: M00 −4y, M01 2x, M02 2w, M10 2x, M12 2z, M20 −2w, M21 2z, M22 −4y */
    a[0] = ny2; b[0] = dM[0]; a[1] = q[1]; b[1] = dM[1]; a[2] = q[0]; b[2] = dM[2]; a[3] = q[1]; b[3] = dM[3];
    a[4] = q[3]; b[4] = dM[5]; a[5] = nw; b[5] = dM[6]; a[6] = q[3]; b[6] = dM[7]; a[7] = ny2; b[7] = dM[8];
    float sy = spr_dot8(a, b);
    /* z: M00 −4z, M01 −2w, M02 2x, M10 2w, M11 −4z, M12 2y, M20 2x, M21 2y */
    a[0] = nz2; b[0] = dM[0]; a[1] = nw; b[1] = dM[1]; a[2] = q[1]; b[2] = dM[2]; a[3] = q[0]; b[3] = dM[3];
    a[4] = nz2; b[4] = dM[4]; a[5] = q[2]; b[5] = dM[5]; a[6] = q[1]; b[6] = dM[6]; a[7] = q[2]; b[7] = dM[7];
    float sz = spr_dot8(a, b);
    SPR_PRECISE float dw = 2.0f * sw;
    SPR_PRECISE float dx = 2.0f * sx;
    SPR_PRECISE float dy = 2.0f * sy;
    SPR_PRECISE float dz = 2.0f * sz;
    dq[0] = dw;
    dq[1] = dx;
    dq[2] = dy;
    dq[3] = dz;
}

/* p0·q0 + p1·q1, left to right. */
SPR_FN float spr_sum2(float p0, float q0, float p1, float q1)
{
    SPR_PRECISE float a = p0 * q0;
    SPR_PRECISE float b = p1 * q1;
    SPR_PRECISE float v = a + b;
    return v;
}

/* The backward of spr_gauss_preprocess3d (SPEC 10.10 item 5; docs/gradients.md
 * "per Gaussian", operation by operation): from a Gaussian's gradient sums
 * (SPR_GPART_*: its record's conic, centre, opacity and 1/t.z) to gout
 * (gout, SPR_GOUT_*: ∂L/∂μ without the colour's view direction, ∂L/∂q, ∂L/∂σ,
 * ∂L/∂o).  It recomputes steps 1–5 (spr_gauss_project3d); a culled Gaussian
 * gets zeros.  The tangent clamp follows the profile: TCLAMP_BWD 0 the
 * exact derivative (a clamped tangent's u = c·t.z moves with t.z), 1
 * inria's (a clamped u held constant, which doubles J's t.z term). */
SPR_FN void spr_gauss_preprocess3d_bwd(SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR mu[3], SPR_CARR q[4], SPR_CARR s[3],
                                       SPR_CARR sum[SPR_GPART_FLOATS], SPR_OARR gout[SPR_GOUT_FLOATS])
{
    for (int f = 0; f < SPR_GOUT_FLOATS; f++) gout[f] = 0.0f;
    gout[SPR_GOUT_OPACITY] = sum[SPR_GPART_OPACITY];
    /* the chain is linear in the sums that enter it: none (a Gaussian no pixel blended), no gradient, whatever the
     * chain's factors (a scene at 1e-18 scale under a profile without a near cull overflowed them: inf·0, a NaN
     * whose sign the backends set differently; parity --random seed 20261207, scenes 720 and 727) */
    int any = 0;
    for (int f = SPR_GPART_CONIC; f < SPR_GPART_CONIC + 3; f++)
        if (sum[f] != 0.0f) any = 1;
    if (sum[SPR_GPART_M] != 0.0f || sum[SPR_GPART_M + 1] != 0.0f || sum[SPR_GPART_INVZ] != 0.0f) any = 1;
    if (any == 0) return;
    float t[3];
    float Rq[9];
    float L[9];
    float S[9];
    float J[6];
    float T[6];
    float A[6];
    float P[4];
    float why = spr_gauss_project3d(g, mu, q, s, t, Rq, L, S, J, T, A, P);
    if (why != SPR_GCULL_NONE) return;
    SPR_PRECISE float a = P[0] + g[SPR_GPRM_EPS2D];
    float b = P[1];
    SPR_PRECISE float cc = P[3] + g[SPR_GPRM_EPS2D];
    SPR_PRECISE float ac = a * cc;
    SPR_PRECISE float bb = b * b;
    SPR_PRECISE float det = ac - bb;
    if (g[SPR_GPRM_DET_LE] != 0.0f) {
        if (!(det > 0.0f)) return;
    } else if (det == 0.0f) {
        return;
    }
    SPR_PRECISE float k = 1.0f / det;
    SPR_PRECISE float nb = -b;
    SPR_PRECISE float cA = cc * k;
    SPR_PRECISE float cB = nb * k;
    SPR_PRECISE float cC = a * k;
    /* the conic (cc, −b, a)/det: with s = ⟨∂L/∂conic, conic⟩,
     * ∂L/∂a = vC·k − s·cA, ∂L/∂cc = vA·k − s·cC, ∂L/∂b = −vB·k − 2·s·cB */
    float vA = sum[SPR_GPART_CONIC];
    float vB = sum[SPR_GPART_CONIC + 1];
    float vC = sum[SPR_GPART_CONIC + 2];
    float sc = spr_sum3(vA, cA, vB, cB, vC, cC);
    SPR_PRECISE float ka = vC * k;
    SPR_PRECISE float sa = sc * cA;
    SPR_PRECISE float va = ka - sa;
    SPR_PRECISE float kc = vA * k;
    SPR_PRECISE float scc = sc * cC;
    SPR_PRECISE float vcc = kc - scc;
    SPR_PRECISE float kb = vB * k;
    SPR_PRECISE float sb = sc * cB;
    SPR_PRECISE float sb2 = 2.0f * sb;
    SPR_PRECISE float nkb = -kb;
    SPR_PRECISE float vb = nkb - sb2;
    SPR_PRECISE float hb = 0.5f * vb;
    /* V = ∂L/∂Σ' as a symmetric matrix [[va, hb], [hb, vcc]] (the dilation adds a constant);
     * Σ' = T·Σ·Tᵀ gives ∂L/∂T = 2·V·A (A = T·Σ) and ∂L/∂Σ = Tᵀ·V·T */
    float V[4];
    V[0] = va;
    V[1] = hb;
    V[2] = hb;
    V[3] = vcc;
    float VT[6];
    float dT[6];
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 3; j++) {
            float x = spr_sum2(V[2 * i], T[j], V[2 * i + 1], T[3 + j]);
            VT[3 * i + j] = x;
            float y = spr_sum2(V[2 * i], A[j], V[2 * i + 1], A[3 + j]);
            SPR_PRECISE float y2 = 2.0f * y;
            dT[3 * i + j] = y2;
        }
    float dS[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            float x = spr_sum2(T[i], VT[j], T[3 + i], VT[3 + j]);
            dS[3 * i + j] = x;
        }
    /* T = J·W: ∂L/∂J = ∂L/∂T·Wᵀ (only J00, J02, J11, J12 vary) */
    float dJ[6];
    for (int i = 0; i < 2; i++)
        for (int kk = 0; kk < 3; kk++) {
            float x = spr_sum3(dT[3 * i], g[SPR_GPRM_R + 3 * kk], dT[3 * i + 1], g[SPR_GPRM_R + 3 * kk + 1], dT[3 * i + 2], g[SPR_GPRM_R + 3 * kk + 2]);
            dJ[3 * i + kk] = x;
        }
    /* J(t): J00 = fx/t.z, J02 = −fx·u/t.z², u = c·t.z with c = t.x/t.z clamped (J11, J12 likewise) */
    float fx = g[SPR_GPRM_FX];
    float fy = g[SPR_GPRM_FY];
    SPR_PRECISE float iz = 1.0f / t[2];
    SPR_PRECISE float iz2 = iz * iz;
    SPR_PRECISE float iz3 = iz2 * iz;
    SPR_PRECISE float txz = t[0] / t[2];
    SPR_PRECISE float tyz = t[1] / t[2];
    SPR_PRECISE float cx = txz;
    SPR_PRECISE float cy = tyz;
    int clx = 0;
    int cly = 0;
    if (g[SPR_GPRM_TCLAMP] != 0.0f) {
        SPR_PRECISE float nlx = -g[SPR_GPRM_LXN];
        SPR_PRECISE float nly = -g[SPR_GPRM_LYN];
        if (cx < nlx) { cx = nlx; clx = 1; }
        if (cx > g[SPR_GPRM_LX]) { cx = g[SPR_GPRM_LX]; clx = 1; }
        if (cy < nly) { cy = nly; cly = 1; }
        if (cy > g[SPR_GPRM_LY]) { cy = g[SPR_GPRM_LY]; cly = 1; }
    }
    SPR_PRECISE float u = cx * t[2];
    SPR_PRECISE float v = cy * t[2];
    SPR_PRECISE float fxi = fx * iz2;
    SPR_PRECISE float fyi = fy * iz2;
    SPR_PRECISE float z00 = fxi * dJ[0];
    SPR_PRECISE float z11 = fyi * dJ[4];
    SPR_PRECISE float fu = fx * u;
    SPR_PRECISE float fu2 = 2.0f * fu;
    SPR_PRECISE float fu3 = fu2 * iz3;
    SPR_PRECISE float z02 = fu3 * dJ[2];
    SPR_PRECISE float fv = fy * v;
    SPR_PRECISE float fv2 = 2.0f * fv;
    SPR_PRECISE float fv3 = fv2 * iz3;
    SPR_PRECISE float z12 = fv3 * dJ[5];
    SPR_PRECISE float s0 = z02 - z00;
    SPR_PRECISE float s1 = s0 - z11;
    SPR_PRECISE float vt2 = s1 + z12;
    SPR_PRECISE float du0 = fxi * dJ[2];
    SPR_PRECISE float du = -du0;
    SPR_PRECISE float dv0 = fyi * dJ[5];
    SPR_PRECISE float dv = -dv0;
    SPR_PRECISE float vt0 = 0.0f;
    SPR_PRECISE float vt1 = 0.0f;
    if (clx == 0) vt0 = du;
    else if (g[SPR_GPRM_TCLAMP_BWD] == 0.0f) {
        SPR_PRECISE float ucx = du * cx;
        vt2 = vt2 + ucx;
    }
    if (cly == 0) vt1 = dv;
    else if (g[SPR_GPRM_TCLAMP_BWD] == 0.0f) {
        SPR_PRECISE float vcy = dv * cy;
        vt2 = vt2 + vcy;
    }
    /* the centre m = (fx·t.x/t.z + cx, fy·t.y/t.z + cy) and 1/t.z */
    SPR_PRECISE float vtx = fx * sum[SPR_GPART_M];
    SPR_PRECISE float vty = fy * sum[SPR_GPART_M + 1];
    SPR_PRECISE float mx0 = vtx * iz;
    SPR_PRECISE float my0 = vty * iz;
    vt0 = vt0 + mx0;
    vt1 = vt1 + my0;
    float mz0 = spr_sum2(vtx, txz, vty, tyz);
    SPR_PRECISE float mz = mz0 * iz;
    vt2 = vt2 - mz;
    SPR_PRECISE float iv = sum[SPR_GPART_INVZ] * iz2;
    vt2 = vt2 - iv;
    /* t = R·μ + T: ∂L/∂μ = Rᵀ·∂L/∂t */
    for (int j = 0; j < 3; j++) {
        float x = spr_sum3(g[SPR_GPRM_R + j], vt0, g[SPR_GPRM_R + 3 + j], vt1, g[SPR_GPRM_R + 6 + j], vt2);
        gout[SPR_GOUT_MEANS + j] = x;
    }
    /* Σ = L·Lᵀ: ∂L/∂L = 2·∂L/∂Σ·L; L = Rq·diag(σ): ∂L/∂σ_k = Σ_i ∂L/∂L_ik·Rq_ik, ∂L/∂Rq_ik = ∂L/∂L_ik·σ_k */
    float dL[9];
    for (int i = 0; i < 3; i++)
        for (int kk = 0; kk < 3; kk++) {
            float x = spr_sum3(dS[3 * i], L[kk], dS[3 * i + 1], L[3 + kk], dS[3 * i + 2], L[6 + kk]);
            SPR_PRECISE float x2 = 2.0f * x;
            dL[3 * i + kk] = x2;
        }
    float dR[9];
    for (int kk = 0; kk < 3; kk++) {
        float x = spr_sum3(dL[kk], Rq[kk], dL[3 + kk], Rq[3 + kk], dL[6 + kk], Rq[6 + kk]);
        gout[SPR_GOUT_SCALES + kk] = x;
        for (int i = 0; i < 3; i++) {
            SPR_PRECISE float y = dL[3 * i + kk] * s[kk];
            dR[3 * i + kk] = y;
        }
    }
    /* the quaternion as given (unit): ∂L/∂q̂ projected onto the tangent, v − (v·q)·q */
    float dq[4];
    spr_quat_matrix_bwd(q, dR, dq);
    float d01 = spr_sum2(dq[0], q[0], dq[1], q[1]);
    float d23 = spr_sum2(dq[2], q[2], dq[3], q[3]);
    SPR_PRECISE float dd = d01 + d23;
    for (int i = 0; i < 4; i++) {
        SPR_PRECISE float p = dd * q[i];
        SPR_PRECISE float x = dq[i] - p;
        gout[SPR_GOUT_QUATS + i] = x;
    }
    gout[SPR_GOUT_OPACITY] = sum[SPR_GPART_OPACITY];
    /* a zero as +0: the two backends disagreed on the sign of a zero gradient (measured on the donut: 333 zeros of
     * quats and scales, Gaussians no pixel reached, −0 on llvmpipe and zink, +0 in C); a comparison, not arithmetic */
    for (int f = 0; f < SPR_GOUT_FLOATS; f++)
        if (gout[f] == 0.0f) gout[f] = 0.0f;
}

/* SPEC §10.5 for a planar Gaussian (docs/gaussians.md, "gauss2d, operation
 * by operation"): the two axes of the largest σ (in axis order; a 2D
 * Gaussian's third σ is 0) span the disk, the third is its normal.  The
 * homogeneous map H = K·[σ_u·W·Rq e_u | σ_v·W·Rq e_v | t] takes (u, v, 1) to
 * (i·w, j·w, w); its rows Tu, Tv, Tw are kept.  The normal (camera space)
 * faces the camera; the centre and extent are those of the bounding box of
 * the disk's 3σ ellipse on screen (the dual-conic box of hbb1's
 * compute_aabb), the radius at least 3·FilterSize. */
SPR_FN void spr_gauss_preprocess2d(SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR mu[3], SPR_CARR q[4], SPR_CARR s[3], float o,
                                   SPR_CARR c[3], SPR_OARR rec[SPR_GREC_FLOATS])
{
    float t[3];
    spr_gauss_to_camera(g, mu, t);
    for (int f = 0; f < SPR_GREC_FLOATS; f++) rec[f] = 0.0f;
    if (!(t[2] > g[SPR_GPRM_NEAR])) {
        spr_gauss_cull(SPR_GCULL_NEAR, rec);
        return;
    }
    /* the axes: the smallest σ is the normal (ties: the later axis) */
    int nax = 2;
    if (s[1] < s[nax]) nax = 1;
    if (s[0] < s[nax]) nax = 0;
    int ua = 0;
    int va = 1;
    if (nax == 0) {
        ua = 1;
        va = 2;
    } else if (nax == 1) {
        va = 2;
    }
    float Rq[9];
    spr_quat_matrix(q, Rq);
    /* A = [σ_u·W·Rq e_u | σ_v·W·Rq e_v | t] in camera space, column by column */
    float A[9];
    for (int col = 0; col < 2; col++) {
        int ax = ua;
        if (col == 1) ax = va;
        float l[3];
        for (int i = 0; i < 3; i++) {
            SPR_PRECISE float v = Rq[3 * i + ax] * s[ax];
            l[i] = v;
        }
        for (int i = 0; i < 3; i++) {
            float v = spr_sum3(g[SPR_GPRM_R + 3 * i], l[0], g[SPR_GPRM_R + 3 * i + 1], l[1], g[SPR_GPRM_R + 3 * i + 2], l[2]);
            A[3 * i + col] = v;
        }
    }
    for (int i = 0; i < 3; i++) A[3 * i + 2] = t[i];
    /* H = K·A: Tu = fx·A0 + cx·A2, Tv = fy·A1 + cy·A2, Tw = A2 (cx, cy pixel-index) */
    float Tu[3];
    float Tv[3];
    float Tw[3];
    for (int j = 0; j < 3; j++) {
        SPR_PRECISE float a = g[SPR_GPRM_FX] * A[j];
        SPR_PRECISE float b = g[SPR_GPRM_CX] * A[6 + j];
        SPR_PRECISE float e = g[SPR_GPRM_FY] * A[3 + j];
        SPR_PRECISE float f = g[SPR_GPRM_CY] * A[6 + j];
        SPR_PRECISE float u = a + b;
        SPR_PRECISE float v = e + f;
        Tu[j] = u;
        Tv[j] = v;
        Tw[j] = A[6 + j];
    }
    /* the normal in camera space, facing the camera (culled edge-on: t·n == 0) */
    float nw[3];
    for (int i = 0; i < 3; i++) {
        float v = spr_sum3(g[SPR_GPRM_R + 3 * i], Rq[nax], g[SPR_GPRM_R + 3 * i + 1], Rq[3 + nax], g[SPR_GPRM_R + 3 * i + 2], Rq[6 + nax]);
        nw[i] = v;
    }
    float tn = spr_sum3(t[0], nw[0], t[1], nw[1], t[2], nw[2]);
    SPR_PRECISE float cosv = -tn;
    if (cosv == 0.0f) {
        spr_gauss_cull(SPR_GCULL_DET, rec);
        return;
    }
    if (cosv < 0.0f)
        for (int i = 0; i < 3; i++) {
            SPR_PRECISE float v = -nw[i];
            nw[i] = v;
        }
    /* the screen box of the 3σ ellipse: d = 9·Tw0² + 9·Tw1² − Tw2², f = (9, 9, −1)/d */
    SPR_PRECISE float w00 = Tw[0] * Tw[0];
    SPR_PRECISE float w11 = Tw[1] * Tw[1];
    SPR_PRECISE float w22 = Tw[2] * Tw[2];
    SPR_PRECISE float d0 = 9.0f * w00;
    SPR_PRECISE float d1 = 9.0f * w11;
    SPR_PRECISE float d01 = d0 + d1;
    SPR_PRECISE float d = d01 - w22;
    if (d == 0.0f) {
        spr_gauss_cull(SPR_GCULL_DET, rec);
        return;
    }
    SPR_PRECISE float kd = 1.0f / d;
    SPR_PRECISE float f0 = kd * 9.0f;
    SPR_PRECISE float f2 = -kd;
    float ext[2];
    float mid[2];
    for (int a = 0; a < 2; a++) {
        float R[3];
        for (int j = 0; j < 3; j++) R[j] = Tu[j];
        if (a == 1)
            for (int j = 0; j < 3; j++) R[j] = Tv[j];
        SPR_PRECISE float p0 = R[0] * Tw[0];
        SPR_PRECISE float p1 = R[1] * Tw[1];
        SPR_PRECISE float p2 = R[2] * Tw[2];
        float p = spr_sum3(f0, p0, f0, p1, f2, p2);
        SPR_PRECISE float r0 = R[0] * R[0];
        SPR_PRECISE float r1 = R[1] * R[1];
        SPR_PRECISE float r2 = R[2] * R[2];
        float ss = spr_sum3(f0, r0, f0, r1, f2, r2);
        SPR_PRECISE float pp = p * p;
        SPR_PRECISE float h0 = pp - ss;
        if (!(h0 >= g[SPR_GPRM_EXT2D_MIN])) h0 = g[SPR_GPRM_EXT2D_MIN];
        SPR_PRECISE float h = spr_sqrt(h0);
        mid[a] = p;
        ext[a] = h;
    }
    SPR_PRECISE float rad = ext[0];
    if (ext[1] > rad) rad = ext[1];
    if (g[SPR_GPRM_R2D_MIN] > rad) rad = g[SPR_GPRM_R2D_MIN];
    SPR_PRECISE float r = spr_ceil(rad);
    rec[SPR_GREC_M] = mid[0];
    rec[SPR_GREC_M + 1] = mid[1];
    for (int j = 0; j < 3; j++) {
        rec[SPR_GREC_TU + j] = Tu[j];
        rec[SPR_GREC_TV + j] = Tv[j];
        rec[SPR_GREC_TW + j] = Tw[j];
        rec[SPR_GREC_NORMAL + j] = nw[j];
        rec[SPR_GREC_COLOR + j] = c[j];
    }
    rec[SPR_GREC_OPACITY] = o;
    rec[SPR_GREC_DEPTH] = t[2];
    SPR_PRECISE float iz = 1.0f / t[2];
    rec[SPR_GREC_INVZ] = iz;
    rec[SPR_GREC_RADIUS] = r;
    rec[SPR_GREC_RADIUS + 1] = r;
    rec[SPR_GREC_CULL] = SPR_GCULL_NONE;
    spr_gauss_rects(g, mid[0], mid[1], r, r, rec);
}

/* The record of one Gaussian under the frame's mode (SPR_GMODE_*). */
SPR_FN void spr_gauss_preprocess(SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR mu[3], SPR_CARR q[4], SPR_CARR s[3], float o,
                                 SPR_CARR c[3], SPR_OARR rec[SPR_GREC_FLOATS])
{
    if (g[SPR_GPRM_MODE] == SPR_GMODE_2D) spr_gauss_preprocess2d(g, mu, q, s, o, c, rec);
    else spr_gauss_preprocess3d(g, mu, q, s, o, c, rec);
}

/* power of the 3D Gaussian with centre (mx, my) and conic (A, B, C) at pixel
 * (fi, fj): (−0.5·((A·d.x)·d.x + (C·d.y)·d.y)) − (B·d.x)·d.y, d = m − (i, j). */
SPR_FN float spr_gauss_power(float mx, float my, float A, float B, float C, float fi, float fj)
{
    SPR_PRECISE float dx = mx - fi;
    SPR_PRECISE float dy = my - fj;
    SPR_PRECISE float ad = A * dx;
    SPR_PRECISE float add = ad * dx;
    SPR_PRECISE float cd = C * dy;
    SPR_PRECISE float cdd = cd * dy;
    SPR_PRECISE float sum = add + cdd;
    SPR_PRECISE float h = -0.5f * sum;
    SPR_PRECISE float bd = B * dx;
    SPR_PRECISE float bdd = bd * dy;
    SPR_PRECISE float p = h - bdd;
    return p;
}

/* The backward of spr_gauss_power: v = ∂L/∂power gives d = (∂L/∂A, ∂L/∂B,
 * ∂L/∂C, ∂L/∂m.x, ∂L/∂m.y) = (dx²·(−½v), (dx·dy)·(−v), dy²·(−½v),
 * (A·dx + B·dy)·(−v), (B·dx + C·dy)·(−v)), d = m − (i, j). */
SPR_FN void spr_gauss_power_bwd(float mx, float my, float A, float B, float C, float fi, float fj, float v, SPR_OARR d[5])
{
    SPR_PRECISE float dx = mx - fi;
    SPR_PRECISE float dy = my - fj;
    SPR_PRECISE float xx = dx * dx;
    SPR_PRECISE float xy = dx * dy;
    SPR_PRECISE float yy = dy * dy;
    SPR_PRECISE float hv = -0.5f * v;
    SPR_PRECISE float nv = -v;
    SPR_PRECISE float dA = xx * hv;
    SPR_PRECISE float dB = xy * nv;
    SPR_PRECISE float dC = yy * hv;
    SPR_PRECISE float ax = A * dx;
    SPR_PRECISE float by = B * dy;
    SPR_PRECISE float sx = ax + by;
    SPR_PRECISE float bx = B * dx;
    SPR_PRECISE float cy = C * dy;
    SPR_PRECISE float sy = bx + cy;
    SPR_PRECISE float dmx = sx * nv;
    SPR_PRECISE float dmy = sy * nv;
    d[0] = dA;
    d[1] = dB;
    d[2] = dC;
    d[3] = dmx;
    d[4] = dmy;
}

/* α = min(cap, o·e^power) (SPEC §10.4). */
SPR_FN float spr_gauss_alpha(SPR_CARR g[SPR_GPRM_COUNT], float o, float power)
{
    float ex = spr_exp(power);
    SPR_PRECISE float a = o * ex;
    if (a > g[SPR_GPRM_CAP]) a = g[SPR_GPRM_CAP];
    return a;
}

/* The backward of spr_gauss_alpha (SPEC 10.10; docs/gradients.md): v = ∂L/∂α
 * gives ∂L/∂o = e^power·v and ∂L/∂power = (o·e^power)·v.  Where the cap holds
 * (o·e^power > CAP), a profile with GATE passes neither (the derivative of the
 * capped forward: gsplat, brush); one without passes both as if uncapped
 * (inria, OpenSplat). */
SPR_FN void spr_gauss_alpha_bwd(SPR_CARR g[SPR_GPRM_COUNT], float o, float power, float v, SPR_OUT do_out, SPR_OUT dp_out)
{
    float ex = spr_exp(power);
    SPR_PRECISE float a = o * ex;
    SPR_PRECISE float dov = ex * v;
    SPR_PRECISE float dpv = a * v;
    if (a > g[SPR_GPRM_CAP] && g[SPR_GPRM_GATE] != 0.0f) {
        dov = 0.0f;
        dpv = 0.0f;
    }
    SPR_SET(do_out) = dov;
    SPR_SET(dp_out) = dpv;
}

/* One Gaussian's visit of the front-to-back loop (SPEC §10.4) at a pixel of
 * transmittance T, given its power and opacity og: 0 blended (α and
 * Tn = T·(1 − α) set), 1 skipped for power > 0, 2 skipped as faint (α below
 * ALPHA_MIN, or the power below POWER_MIN, decided without the exponential:
 * α then 0), 3 the loop stops here (α and Tn set, not blended).  The forward
 * loop (spr_gauss_pixel) and its backward (spr_gauss_tile_bwd) both visit
 * through it, so the backward's α and T are the forward's bits. */
SPR_FN int spr_gauss_visit(SPR_CARR g[SPR_GPRM_COUNT], float og, float power, float T, SPR_OUT alpha_out, SPR_OUT tn_out)
{
    SPR_SET(alpha_out) = 0.0f;
    SPR_SET(tn_out) = T;
    if (power > 0.0f) return 1;
    if (power < g[SPR_GPRM_POWER_MIN] && og <= 1.0f) return 2;
    float alpha = spr_gauss_alpha(g, og, power);
    SPR_SET(alpha_out) = alpha;
    if (alpha < g[SPR_GPRM_ALPHA_MIN]) return 2;
    SPR_PRECISE float oma = 1.0f - alpha;
    SPR_PRECISE float Tn = T * oma;
    SPR_SET(tn_out) = Tn;
    int stop = 0;
    if (Tn < g[SPR_GPRM_T_MIN]) stop = 1;
    if (g[SPR_GPRM_STOP_LE] != 0.0f && Tn == g[SPR_GPRM_T_MIN]) stop = 1;
    if (stop != 0) return 3;
    return 0;
}

/* gauss2d at pixel (fi, fj) of the surfel of record G (SPEC §10.5): the
 * planes k = i·Tw − Tu and l = j·Tw − Tv meet in p = k × l, the local hit
 * s = (p.x/p.z, p.y/p.z), ρ₃ = s.x² + s.y², ρ₂ = 2·|m − (i, j)|²,
 * ρ = min(ρ₃, ρ₂), power = −0.5·ρ; depth = (s.x·Tw0 + s.y·Tw1) + Tw2.
 * Returns 0 when the ray is parallel to the disk (p.z == 0). */
SPR_FN int spr_gauss_surfel(SPR_PIXEL px, int G, float fi, float fj, SPR_OUT power_out, SPR_OUT depth_out)
{
    float Tu[3];
    float Tv[3];
    float Tw[3];
    for (int j = 0; j < 3; j++) {
        Tu[j] = spr_grec(px, G, SPR_GREC_TU + j);
        Tv[j] = spr_grec(px, G, SPR_GREC_TV + j);
        Tw[j] = spr_grec(px, G, SPR_GREC_TW + j);
    }
    float k[3];
    float l[3];
    for (int j = 0; j < 3; j++) {
        SPR_PRECISE float a = fi * Tw[j];
        SPR_PRECISE float b = fj * Tw[j];
        SPR_PRECISE float ka = a - Tu[j];
        SPR_PRECISE float lb = b - Tv[j];
        k[j] = ka;
        l[j] = lb;
    }
    SPR_PRECISE float x1 = k[1] * l[2];
    SPR_PRECISE float x2 = k[2] * l[1];
    SPR_PRECISE float y1 = k[2] * l[0];
    SPR_PRECISE float y2 = k[0] * l[2];
    SPR_PRECISE float z1 = k[0] * l[1];
    SPR_PRECISE float z2 = k[1] * l[0];
    SPR_PRECISE float p0 = x1 - x2;
    SPR_PRECISE float p1 = y1 - y2;
    SPR_PRECISE float p2 = z1 - z2;
    if (p2 == 0.0f) return 0;
    SPR_PRECISE float su = p0 / p2;
    SPR_PRECISE float sv = p1 / p2;
    SPR_PRECISE float uu = su * su;
    SPR_PRECISE float vv = sv * sv;
    SPR_PRECISE float rho3 = uu + vv;
    SPR_PRECISE float dx = spr_grec(px, G, SPR_GREC_M) - fi;
    SPR_PRECISE float dy = spr_grec(px, G, SPR_GREC_M + 1) - fj;
    SPR_PRECISE float dxx = dx * dx;
    SPR_PRECISE float dyy = dy * dy;
    SPR_PRECISE float dd = dxx + dyy;
    SPR_PRECISE float rho2 = 2.0f * dd;
    SPR_PRECISE float rho = rho3;
    if (rho2 < rho) rho = rho2;
    SPR_PRECISE float pw = -0.5f * rho;
    SPR_PRECISE float du = su * Tw[0];
    SPR_PRECISE float dv = sv * Tw[1];
    SPR_PRECISE float duv = du + dv;
    SPR_PRECISE float depth = duv + Tw[2];
    SPR_SET(power_out) = pw;
    SPR_SET(depth_out) = depth;
    return 1;
}

/* 1 when pixel (fi, fj) lies outside record G's pixel box under the extent SPR_GEXT_BOX (its tiles hold pixels the
 * box does not: they skip it); 0 otherwise and under every other extent. */
SPR_FN int spr_gauss_outside(SPR_PIXEL px, SPR_CARR g[SPR_GPRM_COUNT], int G, float fi, float fj)
{
    if (g[SPR_GPRM_EXT] != SPR_GEXT_BOX_F) return 0;
    if (fi < spr_grec(px, G, SPR_GREC_BOX) || fi > spr_grec(px, G, SPR_GREC_BOX + 2)) return 1;
    if (fj < spr_grec(px, G, SPR_GREC_BOX + 1) || fj > spr_grec(px, G, SPR_GREC_BOX + 3)) return 1;
    return 0;
}

/* The forward loop's state between calls of spr_gauss_pixel_run (SPR_GFS_*): the entries visited (a whole number, exact
 * as a float below 2^24, as aux's counts), T, C, N, D, the last contributor, the blended, and 1 once the pixel is done. */
SPR_FN void spr_gauss_pixel_begin(SPR_OARR st[SPR_GFS_FLOATS])
{
    for (int k = 0; k < SPR_GFS_FLOATS; k++) st[k] = 0.0f;
    st[SPR_GFS_T] = 1.0f;
}

/* SPEC §10.4 (mode 3D) and §10.5 (mode 2D): pixel px's tile list, front to
 * back, from the state st on, at most `budget` list entries a call (a GL
 * fragment resumes it draw after draw, within llvmpipe's 65,535 loop
 * iterations an invocation: gl_gauss.c); returns 1 once the list is done
 * (its end, or the stop).  Each Gaussian of the list makes a note
 * (SPR_NOTE_GAUSS_*: blended, or why it was skipped, or where the loop
 * stopped) with its power, α, T before and after. */
SPR_FN int spr_gauss_pixel_run(SPR_PIXEL px, SPR_CARR g[SPR_GPRM_COUNT], SPR_IOARR st[SPR_GFS_FLOATS], int budget)
{
    int x = spr_px_x(px);
    int y = spr_px_y(px);
    int jrow = SPR_INT(g[SPR_GPRM_H]) - 1 - y;
    float fi = SPR_FLOAT(x);
    float fj = SPR_FLOAT(jrow);
    int tile = (jrow / 16) * SPR_INT(g[SPR_GPRM_GX]) + x / 16;
    int first = spr_gtile_first(px, tile);
    int end = spr_gtile_end(px, tile);
    int two = 0;
    if (g[SPR_GPRM_MODE] == SPR_GMODE_2D) two = 1;
    if (st[SPR_GFS_DONE] != 0.0f) return 1;
    int k = SPR_INT(st[SPR_GFS_K]);
    if (k == 0) SPR_NOTE(px, SPR_NOTE_GAUSS_TILE, tile, fi, fj, SPR_FLOAT(first), SPR_FLOAT(end - first));
    SPR_PRECISE float T = st[SPR_GFS_T];
    SPR_PRECISE float C[3];
    SPR_PRECISE float N[3];
    for (int ch = 0; ch < 3; ch++) {
        C[ch] = st[SPR_GFS_C + ch];
        N[ch] = st[SPR_GFS_N + ch];
    }
    SPR_PRECISE float D = st[SPR_GFS_D];
    int last = SPR_INT(st[SPR_GFS_LAST]);
    int blended = SPR_INT(st[SPR_GFS_BLENDED]);
    int done = 0;
    int e = first + k;
    for (int u = 0; u < budget; u++) {
        if (e >= end) {
            done = 1;
            break;
        }
        int G = spr_glist(px, e);
        e = e + 1;
        k = k + 1;
        if (spr_gauss_outside(px, g, G, fi, fj) != 0) {
            SPR_NOTE(px, SPR_NOTE_GAUSS_OUTSIDE, G, 0.0f, 0.0f, T, T);
            continue;
        }
        float power = 0.0f;
        float depth = 0.0f;
        if (two != 0) {
            if (spr_gauss_surfel(px, G, fi, fj, SPR_REF(power), SPR_REF(depth)) == 0) {
                SPR_NOTE(px, SPR_NOTE_GAUSS_PARALLEL, G, 0.0f, 0.0f, T, T);
                continue;
            }
            if (depth < g[SPR_GPRM_NEAR]) {
                SPR_NOTE(px, SPR_NOTE_GAUSS_BEHIND, G, power, depth, T, T);
                continue;
            }
        } else {
            power = spr_gauss_power(spr_grec(px, G, SPR_GREC_M), spr_grec(px, G, SPR_GREC_M + 1), spr_grec(px, G, SPR_GREC_CONIC),
                                    spr_grec(px, G, SPR_GREC_CONIC + 1), spr_grec(px, G, SPR_GREC_CONIC + 2), fi, fj);
        }
        float og = spr_grec(px, G, SPR_GREC_OPACITY);
        float alpha = 0.0f;
        float Tn = T;
        int visit = spr_gauss_visit(g, og, power, T, SPR_REF(alpha), SPR_REF(Tn));
        if (visit == 1) {
            SPR_NOTE(px, SPR_NOTE_GAUSS_POWER, G, power, 0.0f, T, T);
            continue;
        }
        /* faint: the note computes α (the skip below POWER_MIN did not), only at a probed pixel */
        if (visit == 2) {
            SPR_NOTE(px, SPR_NOTE_GAUSS_FAINT, G, power, spr_gauss_alpha(g, og, power), T, T);
            continue;
        }
        if (visit == 3) {
            SPR_NOTE(px, SPR_NOTE_GAUSS_STOP, G, power, alpha, T, Tn);
            done = 1;
            break;
        }
        if (two != 0) {
            SPR_PRECISE float w = alpha * T;
            for (int ch = 0; ch < 3; ch++) {
                SPR_PRECISE float cw = spr_grec(px, G, SPR_GREC_COLOR + ch) * w;
                C[ch] = C[ch] + cw;
                SPR_PRECISE float nv = spr_grec(px, G, SPR_GREC_NORMAL + ch) * w;
                N[ch] = N[ch] + nv;
            }
            SPR_PRECISE float dw = depth * w;
            D = D + dw;
        } else {
            for (int ch = 0; ch < 3; ch++) {
                SPR_PRECISE float ca = spr_grec(px, G, SPR_GREC_COLOR + ch) * alpha;
                SPR_PRECISE float cat = ca * T;
                C[ch] = C[ch] + cat;
            }
            SPR_PRECISE float ia = spr_grec(px, G, SPR_GREC_INVZ) * alpha;
            SPR_PRECISE float iat = ia * T;
            D = D + iat;
        }
        SPR_NOTE(px, SPR_NOTE_GAUSS_BLEND, G, power, alpha, T, Tn);
        T = Tn;
        last = k;
        blended = blended + 1;
    }
    st[SPR_GFS_K] = SPR_FLOAT(k);
    st[SPR_GFS_T] = T;
    for (int ch = 0; ch < 3; ch++) {
        st[SPR_GFS_C + ch] = C[ch];
        st[SPR_GFS_N + ch] = N[ch];
    }
    st[SPR_GFS_D] = D;
    st[SPR_GFS_LAST] = SPR_FLOAT(last);
    st[SPR_GFS_BLENDED] = SPR_FLOAT(blended);
    if (done != 0) st[SPR_GFS_DONE] = 1.0f;
    return done;
}

/* A done pixel's values from its state (SPEC §10.4, §10.5): o = (C + T·bg, 1 − T), aux = (T, last contributor k, D,
 * Gaussians blended) with D = Σ (1/t.z)·α·T (3D: the inverse depth) or Σ depth·α·T (2D: the surface depth), and
 * nrm = (Σ n·α·T, 1 − T) (2D; zero in 3D).  Returns the Gaussians visited. */
SPR_FN int spr_gauss_pixel_end(SPR_PIXEL px, SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR bg[3], SPR_CARR st[SPR_GFS_FLOATS], SPR_OARR o[4],
                               SPR_OARR aux[4], SPR_OARR nrm[4])
{
    float T = st[SPR_GFS_T];
    for (int ch = 0; ch < 3; ch++) {
        SPR_PRECISE float tb = T * bg[ch];
        SPR_PRECISE float v = st[SPR_GFS_C + ch] + tb;
        o[ch] = v;
        nrm[ch] = st[SPR_GFS_N + ch];
    }
    SPR_PRECISE float cov = 1.0f - T;
    o[3] = cov;
    nrm[3] = cov;
    if (g[SPR_GPRM_MODE] != SPR_GMODE_2D) nrm[3] = 0.0f;
    aux[0] = T;
    aux[1] = st[SPR_GFS_LAST];
    aux[2] = st[SPR_GFS_D];
    aux[3] = st[SPR_GFS_BLENDED];
    SPR_NOTE(px, SPR_NOTE_GAUSS_END, SPR_INT(st[SPR_GFS_LAST]), T, st[SPR_GFS_D], st[SPR_GFS_K], st[SPR_GFS_BLENDED]);
    return SPR_INT(st[SPR_GFS_K]);
}

/* The forward loop at pixel px in one call (the CPU): spr_gauss_pixel_run from a fresh state, then
 * spr_gauss_pixel_end.  Returns the Gaussians visited. */
SPR_FN int spr_gauss_pixel(SPR_PIXEL px, SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR bg[3], SPR_OARR o[4], SPR_OARR aux[4],
                           SPR_OARR nrm[4])
{
    float st[SPR_GFS_FLOATS];
    spr_gauss_pixel_begin(st);
    spr_gauss_pixel_run(px, g, st, 2147483647);
    return spr_gauss_pixel_end(px, g, bg, st, o, aux, nrm);
}

/* A gradient term v added to partial f of list entry e (SPR_GPART_*): one
 * tile's walk owns its entries' partials, so the adds follow its order. */
SPR_FN void spr_gpart_add(SPR_PIXEL px, int e, int f, float v)
{
    SPR_PRECISE float s = spr_gpart(px, e, f) + v;
    spr_gpart_set(px, e, f, s);
}

/* The backward of one blend step of gauss3d (C += c·α·T, D += (1/t.z)·α·T,
 * T' = T·(1 − α); SPEC 10.10, docs/gradients.md "per pixel") for the
 * Gaussian at list entry e, blended with α at transmittance T, walking back
 * to front.  acc holds inria's recurrence, the colour and inverse depth
 * behind per unit of T' (4 values); behind the Gaussian walked before this one
 * (colour, 1/t.z, α; zero at first).  up is the pixel's upstream gradient
 * (∂L/∂C, ∂L/∂A, ∂L/∂D), bt = ⟨bg, ∂L/∂C⟩ − ∂L/∂A, Tf the final T.  Adds to
 * entry e's partials:
 *   ∂L/∂c = (α·T)·∂L/∂C,  ∂L/∂(1/t.z) = (α·T)·∂L/∂D,
 *   ∂L/∂α = T·Σ_ch (c − acc)·up − (Tf/(1 − α))·bt,
 * then through α (spr_gauss_alpha_bwd: the profile's cap gate) to the
 * opacity and the power, and through the power (spr_gauss_power_bwd) to the
 * conic and the centre; |∂L/∂m| per axis and a count of 1. */
SPR_FN void spr_gauss_blend_bwd(SPR_PIXEL px, SPR_CARR g[SPR_GPRM_COUNT], float fi, float fj, int e, float alpha, float T, float Tf,
                                SPR_CARR up[5], float bt, SPR_IOARR acc[4], SPR_IOARR behind[5])
{
    int G = spr_glist(px, e);
    float c[4];
    for (int ch = 0; ch < 3; ch++) c[ch] = spr_grec(px, G, SPR_GREC_COLOR + ch);
    c[3] = spr_grec(px, G, SPR_GREC_INVZ);
    float gk[4];
    for (int ch = 0; ch < 3; ch++) gk[ch] = up[ch];
    gk[3] = up[4];
    /* acc past the Gaussian behind: α'·c' + (1 − α')·acc */
    SPR_PRECISE float ob = 1.0f - behind[4];
    for (int ch = 0; ch < 4; ch++) {
        SPR_PRECISE float x = behind[4] * behind[ch];
        SPR_PRECISE float y = ob * acc[ch];
        SPR_PRECISE float z = x + y;
        acc[ch] = z;
    }
    SPR_PRECISE float w = alpha * T;
    SPR_PRECISE float d = 0.0f;
    for (int ch = 0; ch < 4; ch++) {
        SPR_PRECISE float vc = w * gk[ch];
        spr_gpart_add(px, e, SPR_GPART_COLOR + ch, vc);
        SPR_PRECISE float df = c[ch] - acc[ch];
        SPR_PRECISE float dg = df * gk[ch];
        d = d + dg;
    }
    SPR_PRECISE float td = T * d;
    SPR_PRECISE float oma = 1.0f - alpha;
    SPR_PRECISE float tf = Tf / oma;
    SPR_PRECISE float tb = tf * bt;
    SPR_PRECISE float va = td - tb;
    float og = spr_grec(px, G, SPR_GREC_OPACITY);
    float mx = spr_grec(px, G, SPR_GREC_M);
    float my = spr_grec(px, G, SPR_GREC_M + 1);
    float cA = spr_grec(px, G, SPR_GREC_CONIC);
    float cB = spr_grec(px, G, SPR_GREC_CONIC + 1);
    float cC = spr_grec(px, G, SPR_GREC_CONIC + 2);
    float power = spr_gauss_power(mx, my, cA, cB, cC, fi, fj);
    float vo = 0.0f;
    float vp = 0.0f;
    spr_gauss_alpha_bwd(g, og, power, va, SPR_REF(vo), SPR_REF(vp));
    spr_gpart_add(px, e, SPR_GPART_OPACITY, vo);
    float dp[5];
    spr_gauss_power_bwd(mx, my, cA, cB, cC, fi, fj, vp, dp);
    if (g[SPR_GPRM_HALF_B] != 0.0f) { /* the profile's halved off-diagonal (OpenSplat: 0.5·v_σ·x·y) */
        SPR_PRECISE float hb = 0.5f * dp[1];
        dp[1] = hb;
    }
    for (int k = 0; k < 3; k++) spr_gpart_add(px, e, SPR_GPART_CONIC + k, dp[k]);
    for (int k = 0; k < 2; k++) {
        spr_gpart_add(px, e, SPR_GPART_M + k, dp[3 + k]);
        float ab = spr_absf(dp[3 + k]);
        spr_gpart_add(px, e, SPR_GPART_ABS + k, ab);
    }
    spr_gpart_add(px, e, SPR_GPART_COUNT, 1.0f);
    for (int ch = 0; ch < 4; ch++) behind[ch] = c[ch];
    behind[4] = alpha;
}

/* The forward's visit of list entry e at pixel (fi, fj) with transmittance T, for the backward's walks: 2 (skipped) for
 * an entry outside its pixel box, else spr_gauss_visit's answer, α and T' set as it sets them. */
SPR_FN_INLINE int spr_gauss_bwd_visit(SPR_PIXEL px, SPR_CARR g[SPR_GPRM_COUNT], float fi, float fj, int e, float T, SPR_OUT alpha_out, SPR_OUT tn_out)
{
    SPR_SET(alpha_out) = 0.0f;
    SPR_SET(tn_out) = T;
    int G = spr_glist(px, e);
    if (spr_gauss_outside(px, g, G, fi, fj) != 0) return 2;
    float power = spr_gauss_power(spr_grec(px, G, SPR_GREC_M), spr_grec(px, G, SPR_GREC_M + 1), spr_grec(px, G, SPR_GREC_CONIC),
                                  spr_grec(px, G, SPR_GREC_CONIC + 1), spr_grec(px, G, SPR_GREC_CONIC + 2), fi, fj);
    return spr_gauss_visit(g, spr_grec(px, G, SPR_GREC_OPACITY), power, T, alpha_out, tn_out);
}

/* Pixel p of tile `tile` (its pixels row-major from the top row) for the
 * backward: v = (i, j, the upstream gradient ∂L/∂C, ∂L/∂A, ∂L/∂D,
 * bt = ⟨bg, ∂L/∂C⟩ − ∂L/∂A); returns 0 for a pixel outside the image. */
SPR_FN int spr_gauss_bwd_pixel(SPR_PIXEL px, SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR bg[3], int tile, int p, SPR_OARR v[8])
{
    int gx = SPR_INT(g[SPR_GPRM_GX]);
    int W = SPR_INT(g[SPR_GPRM_W]);
    int H = SPR_INT(g[SPR_GPRM_H]);
    int i = (tile % gx) * 16 + p % 16;
    int j = (tile / gx) * 16 + p / 16;
    for (int k = 0; k < 8; k++) v[k] = 0.0f;
    if (i >= W || j >= H) return 0;
    v[0] = SPR_FLOAT(i);
    v[1] = SPR_FLOAT(j);
    int at = (H - 1 - j) * W + i;
    for (int k = 0; k < 5; k++) v[2 + k] = spr_in_grad_i(px, at, k);
    float bgg = spr_sum3(bg[0], v[2], bg[1], v[3], bg[2], v[4]);
    SPR_PRECISE float bt = bgg - v[5];
    v[7] = bt;
    return 1;
}

/* The backward of gauss3d over tile `tile` (SPEC 10.10; docs/gradients.md
 * "per pixel"): its pixels from the state's SPR_GBS_PIX up to p1 − 1, in
 * order, each the forward loop's blended Gaussians walked back to front
 * through spr_gauss_blend_bwd with the forward's own α and T.  Per pixel, a
 * walk (spr_gauss_visit, the forward's operations) holds each blended
 * Gaussian's list entry, α and T (SPR_GBWD_HOLD of them; a pixel that blends
 * more is skipped and named in SPR_GBS_OVER) and gives T_f; then they are
 * walked back, and each one's α and T become those it was walked back with
 * (the profile's cap, T by division), which the host shows (explain --grad).  Resumable: one step a loop iteration (a pixel begun, a list
 * entry visited, a Gaussian walked back), at most `budget` of them a call,
 * everything between two calls in the state (SPR_GBS_*; a fresh state: the
 * first pixel, SPR_GBWD_BEGIN).  The CPU runs a tile in one call; a GL
 * fragment resumes it draw after draw, each call within llvmpipe's 65,535
 * loop iterations an invocation (gl_gauss.c), whatever the lists' length:
 * the bits are the same however the steps are split.  Returns 1 when the
 * tile's pixels are done. */
SPR_FN int spr_gauss_tile_bwd(SPR_PIXEL px, SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR bg[3], int tile, int p1, int budget)
{
    int first = spr_gtile_first(px, tile);
    int end = spr_gtile_end(px, tile);
    int p = spr_gbs_i(px, SPR_GBS_PIX);
    int phase = spr_gbs_i(px, SPR_GBS_PHASE);
    int e = spr_gbs_i(px, SPR_GBS_E);
    SPR_PRECISE float T = spr_gbs(px, SPR_GBS_T);
    int n = spr_gbs_i(px, SPR_GBS_N);
    int k = spr_gbs_i(px, SPR_GBS_K);
    float Tf = spr_gbs(px, SPR_GBS_TF);
    SPR_PRECISE float Tb = spr_gbs(px, SPR_GBS_TB);
    int over = spr_gbs_i(px, SPR_GBS_OVER);
    float acc[4];
    float behind[5];
    for (int c = 0; c < 4; c++) acc[c] = spr_gbs(px, SPR_GBS_ACC + c);
    for (int c = 0; c < 5; c++) behind[c] = spr_gbs(px, SPR_GBS_BEHIND + c);
    float v[8];
    float up[5];
    for (int c = 0; c < 8; c++) v[c] = 0.0f;
    if (p < p1 && phase != SPR_GBWD_BEGIN) spr_gauss_bwd_pixel(px, g, bg, tile, p, v);
    for (int c = 0; c < 5; c++) up[c] = v[2 + c];
    /* one loop a phase (a lane's steps all count against its budget): GL runs every branch of a loop's body for
     * all lanes, so a body that held both phases cost each step the walk and the walk back */
    for (int u = 0; u < budget;) {
        if (p >= p1) break;
        if (phase == SPR_GBWD_BEGIN) {
            int inside = spr_gauss_bwd_pixel(px, g, bg, tile, p, v);
            for (int c = 0; c < 5; c++) up[c] = v[2 + c];
            u = u + 1;
            if (inside == 0) {
                p = p + 1;
                continue;
            }
            e = first;
            T = 1.0f;
            n = 0;
            phase = SPR_GBWD_WALK;
        }
        for (; u < budget && phase == SPR_GBWD_WALK; u++) {
            /* the forward's walk, its blended Gaussians held */
            int stop = 0;
            if (e >= end) stop = 1;
            if (stop == 0) {
                float alpha = 0.0f;
                float Tn = T;
                int visit = spr_gauss_bwd_visit(px, g, v[0], v[1], e, T, SPR_REF(alpha), SPR_REF(Tn));
                if (visit == 3) stop = 1;
                if (visit == 0) {
                    if (n < SPR_GBWD_HOLD) {
                        spr_gbs_seti(px, SPR_GBS_SE + n, e);
                        spr_gbs_set(px, SPR_GBS_SA + n, alpha);
                        spr_gbs_set(px, SPR_GBS_ST + n, T);
                    }
                    n = n + 1;
                    T = Tn;
                }
                e = e + 1;
            }
            if (stop != 0) {
                Tf = T;
                Tb = Tf;
                k = n - 1;
                for (int c = 0; c < 4; c++) acc[c] = 0.0f;
                for (int c = 0; c < 5; c++) behind[c] = 0.0f;
                phase = SPR_GBWD_BACK;
                if (n > SPR_GBWD_HOLD) { /* more than held: the pixel skipped, the first such named */
                    if (over == 0) over = p + 1;
                    k = -1;
                }
            }
        }
        for (; u < budget && phase == SPR_GBWD_BACK; u++) {
            /* Gaussian k walked back; past the first, the next pixel */
            if (k < 0) {
                p = p + 1;
                phase = SPR_GBWD_BEGIN;
                break;
            }
            /* the profile's backward rules: its own α cap, and T recovered by division (OpenSplat) */
            float ab = spr_gbs(px, SPR_GBS_SA + k);
            if (g[SPR_GPRM_CAP_BWD] > 0.0f && ab > g[SPR_GPRM_CAP_BWD]) ab = g[SPR_GPRM_CAP_BWD];
            float Tk = spr_gbs(px, SPR_GBS_ST + k);
            if (g[SPR_GPRM_TDIV] != 0.0f) {
                SPR_PRECISE float om = 1.0f - ab;
                SPR_PRECISE float ra = 1.0f / om;
                SPR_PRECISE float tn = Tb * ra;
                Tb = tn;
                Tk = tn;
            }
            spr_gauss_blend_bwd(px, g, v[0], v[1], spr_gbs_i(px, SPR_GBS_SE + k), ab, Tk, Tf, up, v[7], acc, behind);
            spr_gbs_set(px, SPR_GBS_SA + k, ab); /* held as walked back with: explain --grad shows them */
            spr_gbs_set(px, SPR_GBS_ST + k, Tk);
            k = k - 1;
        }
    }
    spr_gbs_seti(px, SPR_GBS_PIX, p);
    spr_gbs_seti(px, SPR_GBS_PHASE, phase);
    spr_gbs_seti(px, SPR_GBS_E, e);
    spr_gbs_set(px, SPR_GBS_T, T);
    spr_gbs_seti(px, SPR_GBS_N, n);
    spr_gbs_seti(px, SPR_GBS_K, k);
    spr_gbs_set(px, SPR_GBS_TF, Tf);
    spr_gbs_set(px, SPR_GBS_TB, Tb);
    spr_gbs_seti(px, SPR_GBS_OVER, over);
    for (int c = 0; c < 4; c++) spr_gbs_set(px, SPR_GBS_ACC + c, acc[c]);
    for (int c = 0; c < 5; c++) spr_gbs_set(px, SPR_GBS_BEHIND + c, behind[c]);
    if (p >= p1) return 1;
    return 0;
}

/* Pixels p0 … p1 − 1 of tile `tile` in one call (the CPU; a pixel's terms for explain): a fresh state, no budget. */
SPR_FN void spr_gauss_tile_bwd_all(SPR_PIXEL px, SPR_CARR g[SPR_GPRM_COUNT], SPR_CARR bg[3], int tile, int p0, int p1)
{
    spr_gbs_seti(px, SPR_GBS_PIX, p0);
    spr_gbs_seti(px, SPR_GBS_PHASE, SPR_GBWD_BEGIN);
    spr_gauss_tile_bwd(px, g, bg, tile, p1, 2147483647);
}

/* A Gaussian's gradient sums (SPEC 10.10 item 4): the partials of its list
 * entries spr_gcsr(k0 … k1 − 1) (ascending: tile order), those in [base, end)
 * (a batch of tiles) added to sum in that order. */
SPR_FN void spr_gauss_gather(SPR_PIXEL px, int k0, int k1, int base, int end, SPR_IOARR sum[SPR_GPART_FLOATS])
{
    for (int k = k0; k < k1; k++) {
        int e = spr_gcsr(px, k);
        if (e >= base && e < end)
            for (int f = 0; f < SPR_GPART_FLOATS; f += 4) { /* four a pass: GL's loop iterations (spr_gauss_tile_bwd) */
                SPR_PRECISE float v0 = sum[f] + spr_gpart(px, e, f);
                SPR_PRECISE float v1 = sum[f + 1] + spr_gpart(px, e, f + 1);
                SPR_PRECISE float v2 = sum[f + 2] + spr_gpart(px, e, f + 2);
                SPR_PRECISE float v3 = sum[f + 3] + spr_gpart(px, e, f + 3);
                sum[f] = v0;
                sum[f + 1] = v1;
                sum[f + 2] = v2;
                sum[f + 3] = v3;
            }
    }
}

/* gauss-blend (SPEC §10.7, the profile's rules 4, 5, 8): what the Gaussian
 * with centre (mx, my), conic (A, B, C), opacity o and colour c offers pixel
 * (fi, fj) — 1 and src = (c·α, α) (premultiplied; STRAIGHT: (c, α)), or 0
 * where the ellipse is cut (power < −CUT: 4.5 for 3σ), power > 0, or
 * α < ALPHA_MIN; α = min(CAP, o·f), f = e^power, or with FALLOFF
 * f = (e^power − e^−CUT)/(1 − e^−CUT); power and α given either way. */
SPR_FN int spr_gauss_blend_frag(SPR_CARR g[SPR_GPRM_COUNT], float mx, float my, float A, float B, float C, float o, SPR_CARR c[3],
                                float fi, float fj, SPR_OARR src[4], SPR_OUT power_out, SPR_OUT alpha_out)
{
    float power = spr_gauss_power(mx, my, A, B, C, fi, fj);
    SPR_SET(power_out) = power;
    SPR_SET(alpha_out) = 0.0f;
    SPR_PRECISE float ncut = -g[SPR_GPRM_CUT];
    if (power < ncut || power > 0.0f) return 0;
    float alpha = 0.0f;
    if (g[SPR_GPRM_FALLOFF] != 0.0f) {
        float ex = spr_exp(power);
        float ec = spr_exp(ncut);
        SPR_PRECISE float num = ex - ec;
        SPR_PRECISE float den = 1.0f - ec;
        SPR_PRECISE float f = num / den;
        SPR_PRECISE float a = o * f;
        if (a > g[SPR_GPRM_CAP]) a = g[SPR_GPRM_CAP];
        alpha = a;
    } else {
        alpha = spr_gauss_alpha(g, o, power);
    }
    SPR_SET(alpha_out) = alpha;
    if (alpha < g[SPR_GPRM_ALPHA_MIN]) return 0;
    if (alpha == 0.0f) return 0;
    for (int ch = 0; ch < 3; ch++) {
        SPR_PRECISE float v = c[ch] * alpha;
        src[ch] = v;
        if (g[SPR_GPRM_STRAIGHT] != 0.0f) src[ch] = c[ch];
    }
    src[3] = alpha;
    return 1;
}
