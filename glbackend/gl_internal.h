/* gl_internal.h — private state of the GL backend, shared by its stages.
 *
 * Targets: each plane of the plane table is one GL_TEXTURE_2D_ARRAY (the
 * pool), and target handle t is layer t of every plane array; a target's
 * framebuffer attaches layer t of the planes it has.  Composites and depth
 * masks read other targets' layers straight from the pool (no copies).
 */
#ifndef GL_INTERNAL_H
#define GL_INTERNAL_H

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include "spr_glbackend.h"

typedef struct gl_target {
    GLuint fbo;
} gl_target;

/* Uniforms each program must have, resolved once at link time. */
#define GL_SPLAT_UNIFORMS(X)                                                                                   \
    X(M, "u_M") X(SIZE, "u_size") X(SX, "u_sx") X(SY, "u_sy") X(EPS, "u_eps") X(DMIN, "u_dmin") X(DMAX, "u_dmax") \
    X(N, "u_n") X(INVN, "u_invn") X(KSCALE, "u_kscale") X(KERNEL, "u_kernel") X(DEPTH, "u_depth") X(OUTPUT, "u_output") X(CULL, "u_cull") \
    X(MASK, "u_mask") X(LAYER, "u_in_layer")
#define GL_COMP_UNIFORMS(X) X(K, "u_K") X(EPS, "u_eps") X(BG, "u_bg") X(LAYER, "u_in_layer") X(PRM, "u_prm") \
    X(LISTW, "u_list_width") X(NBRW, "u_nbr_words")
#define GL_RECT_UNIFORMS(X)                                                                                    \
    X(M, "u_M") X(SIZE, "u_size") X(SX, "u_sx") X(SY, "u_sy") X(EPS, "u_eps") X(AREF, "u_alpha_ref") X(DEPTH, "u_depth") \
    X(OUTPUT, "u_output") X(SAMPLING, "u_sampling") X(LIST, "u_list") X(LISTW, "u_list_width") X(ATLAS, "u_atlas_size")
enum {
#define GL__E(e, name) GL_SU_##e,
    GL_SPLAT_UNIFORMS(GL__E)
#undef GL__E
    GL_SU__COUNT
};
enum {
#define GL__E(e, name) GL_RU_##e,
    GL_RECT_UNIFORMS(GL__E)
#undef GL__E
    GL_RU__COUNT
};
enum {
#define GL__E(e, name) GL_CU_##e,
    GL_COMP_UNIFORMS(GL__E)
#undef GL__E
    GL_CU__COUNT
};

/* The Gaussian programs (gl_gauss.c), linked on first use, and their buffers. */
enum { GL_GPROG_PRE = 0, GL_GPROG_RASTER, GL_GPROG_BLEND, GL_GPROG_BWD_TILE, GL_GPROG_BWD_GAUSS, GL_GPROG__COUNT };
enum { GL_GBUF_RECTEX = 0, GL_GBUF_RANGE, GL_GBUF_LIST, GL_GBUF_COUNT, GL_GBUF_UP, GL_GBUF_CSR, GL_GBUF_CSR_START, GL_GBUF_PART, GL_GBUF_SUMS,
       GL_GBUF_GIN, GL_GBUF_GOUT, GL_GBUF_GBS, GL_GBUF_DONE, GL_GBUF_GFS, GL_GBUF__COUNT };
/* Shader-storage binding of the draws' fragment counter (SPR_SSBO_COUNTER in
 * GLSL: gl_prelude.glsl's spr_count_fragment); 0-7 are the rectangles',
 * the lists', the Gaussian passes' and the probe's. */
#define GL_SSBO_COUNTER 8
/* gl__plane_attachment of a plane that is no attachment: the image planes (SPR_PLANE_*_IMAGE). */
#define GL_NOT_ATTACHED (-2)

typedef struct gl_context {
    spr_backend base; /* first: a gl_context is an spr_backend */
    EGLDisplay dpy;
    EGLContext ctx;
    char renderer[512];
    GLuint prog_splat, prog_rect;
    GLuint prog_comp[SPR_COMP__COUNT];       /* one program per composite op, linked on first use */
    GLint su[GL_SU__COUNT], cu[SPR_COMP__COUNT][GL_CU__COUNT], ru[GL_RU__COUNT];
    /* rectangles (gl_rect.c): the set last uploaded, its buffers, the Tier B atlas */
    uint64_t rects_serial;
    size_t rects_n;
    GLuint rect_buf[4];        /* texels, float records, integer records, neighbour bits */
    GLuint atlas, atlas_org;   /* made on the first hardware-sampled draw of a set */
    int atlas_w, atlas_h;
    GLuint list_meta, list_src, list_head; /* fragment lists of target list_target */
    GLuint list_tex[4];        /* buffer textures the prefix op reads them (and the neighbour bits) through */
    size_t list_cap;           /* nodes the lists hold */
    size_t list_head_cap;      /* list_head's bytes (gl__buffer_reserve: it follows the view) */
    int list_target;
    GLuint vao, instances, counters; /* counters: the draw's fragment counter, storage binding GL_SSBO_COUNTER */
    size_t instances_cap;
    GLuint pool[SPR_PLANE__COUNT]; /* one 2D array texture per plane, a layer per target handle */
    int pool_layers, pool_w, pool_h;
    gl_target *targets;
    int cap;
    GLuint env;  /* the cube map of the last composite with environment effects: six layers */
    GLuint gprog[GL_GPROG__COUNT];
    GLuint gbuf[GL_GBUF__COUNT];
    size_t gcap[GL_GBUF__COUNT];
    GLuint *gpre;   /* the preprocessing's buffers, two a batch (input, records: gl_gauss.c), n_gpre of them */
    size_t *gpre_cap, n_gpre;
    GLuint gtex[10];     /* records, tile ranges, tile lists as buffer textures (units 10, 11, 12); the backward's upstream
                           gradient, entries, entries' starts (units 13, 14, 15), partials and sums (image units 5, 6),
                           the tiles' walk state (image unit 7); the forward's pixel state (image unit 6) */
    GLuint gfbo;        /* the Gaussian programs' attachment-less framebuffer (its size set per draw) */
    int probe_programs; /* programs built with SPR_PROBE (spr_gl_desc.probe) */
    size_t gauss_batch, max_texels; /* spr_gl_desc's */
    int gauss_steps;
    GLuint probe_buf;   /* their records (gl_prelude.glsl) */
} gl_context;

static inline gl_context *gl_ctx(spr_backend *b) { return (gl_context *)b; }

/* gl_context.c */
spr_result gl__egl_open(gl_context *c, const spr_gl_desc *d, spr_error *err);
void gl__egl_close(gl_context *c);
/* Make c's context current on this thread if it is not (several GL
 * backends may live in one process). */
void gl__make_current(gl_context *c);
/* gl_buffers.c: buffers that shaders write, made, reset and read by its rules. */
/* *buf made if 0, given new storage of `bytes` (contents undefined). */
void gl__buffer_alloc(GLuint *buf, size_t bytes, GLenum usage);
/* gl__buffer_alloc only when *buf is 0 or bytes exceed *cap (then *cap = bytes). */
void gl__buffer_reserve(GLuint *buf, size_t *cap, size_t bytes, GLenum usage);
/* Bytes [offset, offset + bytes) of buf set to the 32-bit word (offset and bytes multiples of 4). */
void gl__buffer_fill(GLuint buf, size_t offset, size_t bytes, uint32_t word);
/* Bytes [offset, offset + bytes) of buf into out, after the barrier that makes shader writes visible. */
void gl__buffer_read(GLuint buf, size_t offset, size_t bytes, void *out);
/* gl_shaders.c */
spr_result gl__build_programs(gl_context *c, spr_error *err);
/* The program of composite op `op`, linked on its first use. */
spr_result gl__comp_program(gl_context *c, spr_composite_op op, spr_error *err);
/* gl_backend.c */
spr_result gl__check(spr_backend *b, const char *what);
/* Depth test, depth write, colour masks and blends of a draw under s. */
void gl__pass_state(const spr_pass_state *s);
/* One instance per rectangle or splat: pixel rectangle and id (gl_splat.vert). */
typedef struct gl_instance {
    int32_t rect[4];
    float pr[4];
    float na[4];
    float c[4];
    float e[4];     /* ellipse: u, r_v (spr_draw_ellipse) */
    uint32_t id;
    uint32_t seq;   /* submission index (pixel history) */
} gl_instance;
/* Upload m instances to the instance buffer. */
void gl__upload_instances(gl_context *c, const gl_instance *inst, size_t m);
/* Draw m instances with the samples-passed query and the generated counter. */
void gl__draw_instances(gl_context *c, size_t m, spr_draw_stats *st);
/* Pixel history: arm the bound program's probe before a draw or composite
 * (b->probe set), then move its records into b->probe (frags from index
 * `keep` on are replaced: a redrawn list draw records once).  Draws check
 * first that the programs were built with the probe (refused: the error). */
spr_result gl__probe_refused(gl_context *c);
void gl__probe_begin(gl_context *c);
spr_result gl__probe_end(gl_context *c, int keep);
/* gl_gauss.c; the program of GL_GPROG_* (gl_shaders.c) */
spr_result gl__gauss_program(gl_context *c, int which, spr_error *err);
spr_result gl__gauss_preprocess(spr_backend *b, const spr_gauss_desc *d, float *rec);
/* The Gaussian records of d->splats fit the driver's buffer textures (SPR_E_TOO_LARGE naming the limit). */
spr_result gl__gauss_fits(spr_backend *b, const spr_fit_desc *d);
spr_result gl__gauss_raster(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st);
spr_result gl__gauss_draw(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st);
spr_result gl__gauss_backward(spr_backend *b, const spr_gauss_bwd_desc *d, float *sums, float *out);
void gl__gauss_free(gl_context *c);
/* gl_rect.c */
spr_result gl__draw_rects(spr_backend *b, int target, const spr_rect_draw_desc *d, spr_draw_stats *st);
/* Bind the fragment lists and neighbours of cd for the prefix op. */
spr_result gl__bind_lists(gl_context *c, const spr_composite_desc *cd);
void gl__rects_free(gl_context *c);
/* Colour attachment (= fragment output location) of plane p; −1 for the
 * depth-test plane, which is the depth attachment; GL_NOT_ATTACHED for an
 * image plane. */
int gl__plane_attachment(spr_plane p);

#endif
