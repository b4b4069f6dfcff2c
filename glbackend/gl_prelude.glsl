/* gl_prelude.glsl — what GL does differently, ahead of the shared arithmetic.
 *
 * Gives the macros of core/render/spr_arith.h their GLSL meaning (the C
 * meaning is in core/render/spr_arith_c.h) and fetches a pixel's input
 * targets: every target plane is one layer of a per-plane array texture
 * (gl_backend.c), so input k is layer u_in_layer[k].  Reading layers other
 * than the ones being drawn is well defined in GL 4.5 after
 * glTextureBarrier() (ARB_texture_barrier's disjoint-texel rule).
 * Constants (SPR_* values, spr_gauss_coef, output locations) are emitted
 * before this text by gl_shaders.c from their C definitions.
 */
#define SPR_FN
#define SPR_PRECISE precise
#define SPR_CARR float
#define SPR_OARR out float
#define SPR_IOARR inout float
#define SPR_OUT out float
#define SPR_SET(x) x
#define SPR_REF(x) x
#define SPR_FLOAT(i) float(i)
#define SPR_INT(x) int(x)
#define SPR_PIXEL ivec2
#define spr_floor floor
#define spr_sqrt sqrt

layout(binding = 0) uniform sampler2DArray u_in_color;
layout(binding = 1) uniform sampler2DArray u_in_depth;
layout(binding = 2) uniform sampler2DArray u_in_opacity;
layout(binding = 3) uniform sampler2DArray u_in_normal;
layout(binding = 4) uniform sampler2DArray u_env; /* six layers: the cube faces, texel (i, j) of face f */
uniform int u_in_layer[SPR_MAX_INPUTS];

float spr_in_depth(ivec2 px, int k) { return texelFetch(u_in_depth, ivec3(px, u_in_layer[k]), 0).r; }
float spr_in_color(ivec2 px, int k, int ch) { return texelFetch(u_in_color, ivec3(px, u_in_layer[k]), 0)[ch]; }
float spr_in_opacity(ivec2 px, int k) { return texelFetch(u_in_opacity, ivec3(px, u_in_layer[k]), 0).r; }
float spr_in_normal(ivec2 px, int k, int ch) { return texelFetch(u_in_normal, ivec3(px, u_in_layer[k]), 0)[ch]; }
float spr_px_cx(ivec2 px) { return float(px.x) + 0.5; }
float spr_px_cy(ivec2 px) { return float(px.y) + 0.5; }
float spr_in_env(ivec2 px, int face, int i, int j, int ch) { return texelFetch(u_env, ivec3(i, j, face), 0)[ch]; }
