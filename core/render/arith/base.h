/* base.h — the shared arithmetic's manual and its smallest helpers.
 *
 * core/render/arith/ holds every float operation that reaches a plane,
 * written once (SPEC §2–§4, §7, §10; PARITY.md "Rules that make Tier A
 * hold"), split by concern into files that the build puts together in the
 * one order of core/render/arith/ORDER: C includes them in that order
 * (spr_arith_c.h, through the generated spr_arith_parts.h) and the GL
 * backend embeds the same bytes in that order into every program
 * (cmake/embed.cmake, gl_shaders.c).  Every file follows the rules below.
 *
 * Each file is C and GLSL at the same time.  The CPU backend compiles it as
 * C through spr_arith_c.h; the build embeds the very same bytes into every
 * GLSL program of the GL backend, after glbackend/gl_prelude.glsl, which
 * gives the macros below their GLSL meaning.  Nothing here is retyped
 * anywhere else, but for one copy: swrast/sw_raster.c's disk_lanes runs
 * spr_ray_disk on 8 pixels at once, operation for operation, and test
 * raster's disk_lanes_are_the_scalar_test holds it to this file's bits.
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
 *   SPR_FN_INLINE  static inline, always_inline (nothing)   a step of a hot loop called from two places
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

/* o = 0 in every channel. */
SPR_FN void spr_zero4(SPR_OARR o[4])
{
    for (int ch = 0; ch < 4; ch++) o[ch] = 0.0f;
}
