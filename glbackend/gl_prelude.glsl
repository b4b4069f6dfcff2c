/* gl_prelude.glsl — what GL does differently, ahead of the shared arithmetic.
 *
 * Gives the macros of the shared arithmetic (core/render/arith/base.h) their GLSL meaning (the C
 * meaning is in core/render/spr_arith_c.h) and fetches a pixel's input
 * targets: every target plane is one layer of a per-plane array texture
 * (gl_backend.c), so input k is layer u_in_layer[k].  Reading layers other
 * than the ones being drawn is well defined in GL 4.5 after
 * glTextureBarrier() (ARB_texture_barrier's disjoint-texel rule).
 * Constants (SPR_* values, spr_gauss_coef, output locations) are emitted
 * before this text by gl_shaders.c from their C definitions.
 */
#define SPR_FN
#define SPR_FN_INLINE
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
#define spr_ceil ceil
#define spr_sqrt sqrt
#define spr_ldexp ldexp

layout(binding = 0) uniform sampler2DArray u_in_color;
layout(binding = 1) uniform sampler2DArray u_in_depth;
layout(binding = 2) uniform sampler2DArray u_in_opacity;
layout(binding = 3) uniform sampler2DArray u_in_normal;
layout(binding = 4) uniform sampler2DArray u_env; /* six layers: the cube faces, texel (i, j) of face f */
uniform int u_in_layer[SPR_MAX_INPUTS];
/* Rectangles (domain primitives) and fragment lists: shader storage, read
 * and written as raw 32-bit values (gl_backend.c uploads them unchanged). */
layout(std430, binding = 0) readonly buffer SprTexels { vec4 spr_texels[]; };
layout(std430, binding = 1) readonly buffer SprRectF { float spr_rect_f[]; };
layout(std430, binding = 2) readonly buffer SprRectI { uint spr_rect_i[]; };
/* The draw's fragment counter (gl_backend.c): a shader-storage word, not an
 * atomic counter buffer (gl_buffers.c says why). */
layout(std430, binding = SPR_SSBO_COUNTER) buffer SprCounter { uint spr_generated; };
void spr_count_fragment() { atomicAdd(spr_generated, 1u); }
/* Fragment lists and neighbours are read through buffer textures: on
 * llvmpipe 22.3 a shader-storage load inside a loop whose trip count it
 * cannot see stopped a list walk after one node (measured; gl_rect.c). */
layout(binding = 6) uniform usamplerBuffer u_list_meta;  /* (t bits, rectangle, next, 0) per node */
layout(binding = 7) uniform samplerBuffer u_list_src;    /* colour per node */
layout(binding = 8) uniform usamplerBuffer u_list_head;  /* first node per pixel */
layout(binding = 9) uniform usamplerBuffer u_nbr;        /* neighbour bits */
uniform int u_list_width;
uniform int u_nbr_words;
/* Gaussian records and tile lists (SPEC 10), through buffer textures for the same reason.  Records and
 * lists are four values a texel (RGBA32F, RGBA32UI): GL_MAX_TEXTURE_BUFFER_SIZE counts texels (2^27 on
 * llvmpipe and zink), so one texture holds 2^29 values, the records of 15.8M Gaussians (gl_gauss.c). */
layout(binding = 10) uniform samplerBuffer u_grec;     /* SPR_GREC_FLOATS per Gaussian, packed */
layout(binding = 11) uniform usamplerBuffer u_granges; /* first list entry per tile, GX·GY + 1 */
layout(binding = 12) uniform usamplerBuffer u_glist;   /* the tiles' sorted lists, packed */

#ifdef SPR_PROBE
/* The pixel probe (pixel history, SPEC §8): the debug variant of every
 * program (spr_gl_desc.probe) appends, at pixel u_probe only, its fragments
 * (kind 1) and the notes of the shared arithmetic (kind 2) to this buffer,
 * 16 words a record: kind, two integers, then float bits. */
layout(std430, binding = 6) coherent buffer SprProbe { uint spr_probe_n; uint spr_probe_pad0; uint spr_probe_pad1; uint spr_probe_pad2; uint spr_probe_rec[]; };
uniform ivec2 u_probe;
bool spr_probe_here() { return ivec2(gl_FragCoord.xy) == u_probe; }
uint spr_probe_slot()
{
    uint i = atomicAdd(spr_probe_n, 1u);
    return i < uint(2 * SPR_PROBE_MAX) ? i * 16u : 0xffffffffu;
}
void spr_probe_note(int tag, int k, float a, float b, float c, float d)
{
    if (!spr_probe_here()) return;
    uint o = spr_probe_slot();
    if (o == 0xffffffffu) return;
    spr_probe_rec[o] = 2u;
    spr_probe_rec[o + 1u] = uint(tag);
    spr_probe_rec[o + 2u] = uint(k);
    spr_probe_rec[o + 3u] = floatBitsToUint(a);
    spr_probe_rec[o + 4u] = floatBitsToUint(b);
    spr_probe_rec[o + 5u] = floatBitsToUint(c);
    spr_probe_rec[o + 6u] = floatBitsToUint(d);
}
void spr_probe_frag(uint seq, uint prim, float t, float rho, float z, float src[4], float opacity)
{
    if (!spr_probe_here()) return;
    uint o = spr_probe_slot();
    if (o == 0xffffffffu) return;
    spr_probe_rec[o] = 1u;
    spr_probe_rec[o + 1u] = seq;
    spr_probe_rec[o + 2u] = prim;
    spr_probe_rec[o + 3u] = floatBitsToUint(t);
    spr_probe_rec[o + 4u] = floatBitsToUint(rho);
    spr_probe_rec[o + 5u] = floatBitsToUint(z);
    for (int ch = 0; ch < 4; ch++) spr_probe_rec[o + 6u + uint(ch)] = floatBitsToUint(src[ch]);
    spr_probe_rec[o + 10u] = floatBitsToUint(opacity);
}
#define SPR_NOTE(px, tag, k, a, b, c, d) spr_probe_note(tag, k, a, b, c, d)
#else
#define SPR_NOTE(px, tag, k, a, b, c, d)
#endif

float spr_in_depth(ivec2 px, int k) { return texelFetch(u_in_depth, ivec3(px, u_in_layer[k]), 0).r; }
float spr_in_color(ivec2 px, int k, int ch) { return texelFetch(u_in_color, ivec3(px, u_in_layer[k]), 0)[ch]; }
float spr_in_opacity(ivec2 px, int k) { return texelFetch(u_in_opacity, ivec3(px, u_in_layer[k]), 0).r; }
float spr_in_normal(ivec2 px, int k, int ch) { return texelFetch(u_in_normal, ivec3(px, u_in_layer[k]), 0)[ch]; }
float spr_px_cx(ivec2 px) { return float(px.x) + 0.5; }
float spr_px_cy(ivec2 px) { return float(px.y) + 0.5; }
int spr_px_x(ivec2 px) { return px.x; }
int spr_px_y(ivec2 px) { return px.y; }
int spr_gtile_first(ivec2 px, int tile) { return int(texelFetch(u_granges, tile).r); }
int spr_gtile_end(ivec2 px, int tile) { return int(texelFetch(u_granges, tile + 1).r); }
int spr_glist(ivec2 px, int e) { return int(texelFetch(u_glist, e >> 2)[e & 3]); }
float spr_grec(ivec2 px, int G, int f)
{
    uint i = uint(G) * uint(SPR_GREC_FLOATS) + uint(f); /* < 2^29 (gl__gauss_fits) */
    return texelFetch(u_grec, int(i >> 2u))[i & 3u];
}
/* gauss3d's backward (SPEC 10.10, gl_gauss.c): the upstream gradient (5 values a pixel, pixel y·W + x), the list
 * entries' partials of a batch (SPR_GPART_FLOATS a entry, four a texel, from entry u_gpart_base: one tile's
 * fragment owns its entries' texels), each Gaussian's entries (ascending). */
layout(binding = 13) uniform samplerBuffer u_gup;
layout(binding = 14) uniform usamplerBuffer u_gcsr;
layout(rgba32f, binding = 5) uniform coherent imageBuffer u_gpart;
uniform int u_gpart_base;
float spr_in_grad_i(ivec2 px, int i, int k) { return texelFetch(u_gup, i * 5 + k).r; }
/* a tile's walk state (spr_gauss_tile_bwd): SPR_GBS_FLOATS values from spr__gbs_at, the fragment's own */
layout(r32ui, binding = 7) uniform coherent uimageBuffer u_gbs;
int spr__gbs_at = 0;
float spr_gbs(ivec2 px, int k) { return uintBitsToFloat(imageLoad(u_gbs, spr__gbs_at + k).r); }
void spr_gbs_set(ivec2 px, int k, float v) { imageStore(u_gbs, spr__gbs_at + k, uvec4(floatBitsToUint(v))); }
int spr_gbs_i(ivec2 px, int k) { return int(imageLoad(u_gbs, spr__gbs_at + k).r); }
void spr_gbs_seti(ivec2 px, int k, int v) { imageStore(u_gbs, spr__gbs_at + k, uvec4(uint(v))); }
int spr__gpart_texel(int e, int f) { return (e - u_gpart_base) * (SPR_GPART_FLOATS / 4) + f / 4; }
float spr_gpart(ivec2 px, int e, int f) { return imageLoad(u_gpart, spr__gpart_texel(e, f))[f & 3]; }
void spr_gpart_set(ivec2 px, int e, int f, float v)
{
    vec4 t = imageLoad(u_gpart, spr__gpart_texel(e, f));
    t[f & 3] = v;
    imageStore(u_gpart, spr__gpart_texel(e, f), t);
}
int spr_gcsr(ivec2 px, int k) { return int(texelFetch(u_gcsr, k).r); }
float spr_in_env(ivec2 px, int face, int i, int j, int ch) { return texelFetch(u_env, ivec3(i, j, face), 0)[ch]; }
float spr_in_texel(ivec2 px, int k, int ch) { return spr_texels[k][ch]; }
/* A list node: meta (t bits, rectangle, next, 0) and its colour; next 0xffffffff ends the list. */
int spr_list_first(ivec2 px)
{
    uint h = texelFetch(u_list_head, px.y * u_list_width + px.x).r;
    return h == 0xffffffffu ? -1 : int(h);
}
int spr_list_next(ivec2 px, int node)
{
    uint n = texelFetch(u_list_meta, node).z;
    return n == 0xffffffffu ? -1 : int(n);
}
float spr_list_t(ivec2 px, int node) { return uintBitsToFloat(texelFetch(u_list_meta, node).x); }
int spr_list_prim(ivec2 px, int node) { return int(texelFetch(u_list_meta, node).y); }
float spr_list_src(ivec2 px, int node, int ch) { return texelFetch(u_list_src, node)[ch]; }
int spr_neighbour(ivec2 px, int a, int b) { return int((texelFetch(u_nbr, a * u_nbr_words + b / 32).r >> uint(b % 32)) & 1u); }
