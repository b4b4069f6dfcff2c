/* ray.h — camera rays and ray–splat intersections (SPEC §2, §1 ellipses);
 * the rules of base.h. */

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
