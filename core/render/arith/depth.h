/* depth.h — depth test values and what a splat draw keeps (SPEC §3.3,
 * §6.2 step 2); the rules of base.h. */

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
