/* gl_shaders.c — the GLSL programs of the GL backend, assembled from files.
 *
 * Every program is "#version 450 core", then the shared constants emitted
 * here from their C definitions (enum values, plane output locations, the
 * gauss coefficients as exact bit patterns; for a composite program the
 * function of its row of SPR_COMPOSITE_LIST, one program per op, linked on
 * first use), then glbackend/gl_prelude.glsl, the shared arithmetic
 * of core/render/arith/ verbatim in the order of its ORDER file, and the
 * stage's main file.  The build
 * embeds those files as byte arrays (cmake/embed.cmake): no GLSL lives in a
 * C string literal here, only #define lines generated from C values.
 *
 * Uniform locations are resolved once when a program is linked; a uniform
 * the splat or rectangle program does not have is a build failure, never a
 * silent read of 0; a composite program has the uniforms its op reads.
 */
#include "gl_internal.h"
#include "spr_algo.h"
#include "spr_kernel.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The embedded files (generated gl_sources.c). */
extern const char *const spr__src_arith_parts[]; /* core/render/arith/, in ORDER (generated gl_arith_parts.c) */
extern const char spr__src_gauss_pre_frag[], spr__src_gauss_raster_frag[], spr__src_gauss_blend_frag[];
extern const char spr__src_gauss_bwd_tile_frag[], spr__src_gauss_bwd_gauss_frag[];
extern const char spr__src_prelude[], spr__src_splat_vert[], spr__src_splat_frag[],
    spr__src_full_vert[], spr__src_composite_frag[], spr__src_rect_frag[];

typedef struct strbuf { char *s; size_t n, cap; int oom; } strbuf;

static void sb_add(strbuf *b, const char *fmt, ...)
{
    va_list ap;
    for (;;) {
        size_t room = b->cap - b->n;
        va_start(ap, fmt);
        int w = b->s ? vsnprintf(b->s + b->n, room, fmt, ap) : -1;
        va_end(ap);
        if (w >= 0 && (size_t)w < room) { b->n += (size_t)w; return; }
        size_t cap = b->cap ? 2 * b->cap : 16384;
        while (w >= 0 && cap < b->n + (size_t)w + 1) cap *= 2;
        char *ns = realloc(b->s, cap);
        if (!ns) { b->oom = 1; return; }
        b->s = ns;
        b->cap = cap;
    }
}

/* The constants every fragment program shares, from their C definitions. */
static void add_constants(strbuf *b)
{
    static const struct { const char *name; int value; } k[] = {
        {"SPR_KERNEL_GAUSS", SPR_KERNEL_GAUSS}, {"SPR_KERNEL_CONSTANT", SPR_KERNEL_CONSTANT},
        {"SPR_KERNEL_LINEAR", SPR_KERNEL_LINEAR}, {"SPR_KERNEL_EPANECHNIKOV", SPR_KERNEL_EPANECHNIKOV},
        {"SPR_DEPTH_PLAIN", SPR_DEPTH_PLAIN}, {"SPR_DEPTH_EPS_OFFSET", SPR_DEPTH_EPS_OFFSET},
        {"SPR_DEPTH_LOWRES", SPR_DEPTH_LOWRES}, {"SPR_DEPTH_VORONOI", SPR_DEPTH_VORONOI},
        {"SPR_OUT_WEIGHTED", SPR_OUT_WEIGHTED}, {"SPR_OUT_ALPHA", SPR_OUT_ALPHA},
        {"SPR_GAUSS_DEGREE", SPR_GAUSS_DEGREE}, {"SPR_MAX_INPUTS", SPR_MAX_COMPOSITE_INPUTS},
        {"SPR_ROUT_WEIGHTED", SPR_ROUT_WEIGHTED}, {"SPR_ROUT_COLOR", SPR_ROUT_COLOR}, {"SPR_ROUT_BLACK", SPR_ROUT_BLACK},
        {"SPR_ROUT_LUMINANCE", SPR_ROUT_LUMINANCE}, {"SPR_SAMPLE_NEAREST", SPR_SAMPLE_NEAREST}, {"SPR_SAMPLE_LINEAR", SPR_SAMPLE_LINEAR},
        {"SPR_SAMPLE_HARDWARE", SPR_SAMPLE_HARDWARE}, {"SPR_LIST_MAX", SPR_LIST_MAX}, {"SPR_RECT_FLOATS", SPR_RECT_FLOATS},
        {"SPR_RECTI_TW", SPR_RECTI_TW}, {"SPR_RECTI_TH", SPR_RECTI_TH}, {"SPR_RECTI_OFF", SPR_RECTI_OFF},
        {"SPR_RECTI_DOMAIN", SPR_RECTI_DOMAIN}, {"SPR_RECTI_COUNT", SPR_RECTI_COUNT},
        {"SPR_NOTE_EPS_NEAREST", SPR_NOTE_EPS_NEAREST}, {"SPR_NOTE_EPS_INPUT", SPR_NOTE_EPS_INPUT},
        {"SPR_NOTE_PREFIX_NODE", SPR_NOTE_PREFIX_NODE}, {"SPR_PROBE_MAX", SPR_PROBE_MAX},
        {"SPR_NOTE_GAUSS_TILE", SPR_NOTE_GAUSS_TILE}, {"SPR_NOTE_GAUSS_BLEND", SPR_NOTE_GAUSS_BLEND},
        {"SPR_NOTE_GAUSS_POWER", SPR_NOTE_GAUSS_POWER}, {"SPR_NOTE_GAUSS_FAINT", SPR_NOTE_GAUSS_FAINT},
        {"SPR_NOTE_GAUSS_STOP", SPR_NOTE_GAUSS_STOP}, {"SPR_NOTE_GAUSS_PARALLEL", SPR_NOTE_GAUSS_PARALLEL},
        {"SPR_NOTE_GAUSS_BEHIND", SPR_NOTE_GAUSS_BEHIND}, {"SPR_NOTE_GAUSS_END", SPR_NOTE_GAUSS_END},
        {"SPR_NOTE_GAUSS_OUTSIDE", SPR_NOTE_GAUSS_OUTSIDE},
        {"SPR_SSBO_COUNTER", GL_SSBO_COUNTER}, {"SPR_GPRM_COUNT", SPR_GPRM_COUNT}, {"SPR_GREC_FLOATS", SPR_GREC_FLOATS}, {"SPR_EXP_COEFS", SPR_EXP_COEFS},
    };
    for (size_t i = 0; i < sizeof k / sizeof k[0]; i++) sb_add(b, "#define %s %d\n", k[i].name, k[i].value);
    /* fragment output location of each plane = its colour attachment */
#define GL__LOC(e, name, ch, type, clear) \
    if (gl__plane_attachment(SPR_PLANE_##e) >= 0) sb_add(b, "#define SPR_LOC_%s %d\n", #e, gl__plane_attachment(SPR_PLANE_##e));
    SPR_PLANE_LIST(GL__LOC)
#undef GL__LOC
    /* the Gaussian references' constants: cull reasons and modes (floats), offsets, the exponential's coefficients */
    static const struct { const char *name; float value; } kf[] = {
        {"SPR_GCULL_NONE", SPR_GCULL_NONE}, {"SPR_GCULL_NEAR", SPR_GCULL_NEAR}, {"SPR_GCULL_DET", SPR_GCULL_DET},
        {"SPR_GCULL_CLIP", SPR_GCULL_CLIP}, {"SPR_GCULL_SMALL", SPR_GCULL_SMALL},
        {"SPR_GMODE_3D", SPR_GMODE_3D}, {"SPR_GMODE_2D", SPR_GMODE_2D},
        {"SPR_GEXT_SQUARE_F", SPR_GEXT_SQUARE_F}, {"SPR_GEXT_AXES_F", SPR_GEXT_AXES_F}, {"SPR_GEXT_QUAD_F", SPR_GEXT_QUAD_F},
        {"SPR_GEXT_BOX_F", SPR_GEXT_BOX_F},
    };
    for (size_t i = 0; i < sizeof kf / sizeof kf[0]; i++) sb_add(b, "#define %s %d.0\n", kf[i].name, (int)kf[i].value);
#define GL__GPRM(name, n) sb_add(b, "#define SPR_GPRM_%s %d\n", #name, SPR_GPRM_##name);
    SPR_GPRM_LIST(GL__GPRM)
#undef GL__GPRM
#define GL__GREC(name, n) sb_add(b, "#define SPR_GREC_%s %d\n", #name, SPR_GREC_##name);
    SPR_GREC_LIST(GL__GREC)
#undef GL__GREC
#define GL__GPART(name, n) sb_add(b, "#define SPR_GPART_%s %d\n", #name, SPR_GPART_##name);
    SPR_GPART_LIST(GL__GPART)
#undef GL__GPART
#define GL__GOUT(name, n) sb_add(b, "#define SPR_GOUT_%s %d\n", #name, SPR_GOUT_##name);
    SPR_GOUT_LIST(GL__GOUT)
#undef GL__GOUT
#define GL__GFS(name, n) sb_add(b, "#define SPR_GFS_%s %d\n", #name, SPR_GFS_##name);
    SPR_GFS_LIST(GL__GFS)
#undef GL__GFS
#define GL__GBS(name, n) sb_add(b, "#define SPR_GBS_%s %d\n", #name, SPR_GBS_##name);
    SPR_GBS_LIST(GL__GBS)
#undef GL__GBS
sb_add(b, "#define SPR_GBWD_HOLD %d\n", SPR_GBWD_HOLD);
#define GL__GBWD(name) sb_add(b, "#define SPR_GBWD_%s %d\n", #name, SPR_GBWD_##name);
    SPR_GBWD_LIST(GL__GBWD)
#undef GL__GBWD
    sb_add(b, "#define SPR_GPART_FLOATS %d\n#define SPR_GOUT_FLOATS %d\n#define SPR_GBS_FLOATS %d\n#define SPR_GFS_FLOATS %d\n", SPR_GPART_FLOATS, SPR_GOUT_FLOATS, SPR_GBS_FLOATS,
           SPR_GFS_FLOATS);
    sb_add(b, "const float spr_exp_coef[%d] = float[](", SPR_EXP_COEFS);
    for (int i = 0; i < SPR_EXP_COEFS; i++) {
        uint32_t u;
        memcpy(&u, &spr_exp_coef[i], 4);
        sb_add(b, "%suintBitsToFloat(0x%08xu)", i ? ", " : "", u);
    }
    sb_add(b, ");\n");
    sb_add(b, "const float spr_gauss_coef[%d] = float[](", SPR_GAUSS_DEGREE + 1);
    for (int i = 0; i <= SPR_GAUSS_DEGREE; i++) {
        uint32_t u;
        memcpy(&u, &spr_gauss_coef[i], 4);
        sb_add(b, "%suintBitsToFloat(0x%08xu)", i ? ", " : "", u);
    }
    sb_add(b, ");\n");
    /* offsets of the shading parameters (SPR_PARAM_LIST) */
#define GL__PRM(name, n) sb_add(b, "#define SPR_PRM_%s %d\n", #name, SPR_PRM_##name);
    SPR_PARAM_LIST(GL__PRM)
#undef GL__PRM
    sb_add(b, "#define SPR_PRM_COUNT %d\n", SPR_PRM_COUNT);
    /* offsets of a rectangle's float record (SPR_RECT_LIST) */
#define GL__RECT(name, n) sb_add(b, "#define SPR_RECT_%s %d\n", #name, SPR_RECT_##name);
    SPR_RECT_LIST(GL__RECT)
#undef GL__RECT
}

/* The composite programs' one op: SPR_COMP_ONE calls its row's function
 * (gl_composite.frag), so each program holds the code of its op alone. */
static const char *const comp_fn[SPR_COMP__COUNT] = {
#define GL__FN(e, fn, max_in, reads, writes, summary) "spr_comp_" #fn,
    SPR_COMPOSITE_LIST(GL__FN)
#undef GL__FN
};

/* op ≥ 0: a composite program for that op. */
static char *assemble(const char *main_src, int fragment, int op, int probe)
{
    strbuf b = {0};
    sb_add(&b, "#version 450 core\n");
    if (fragment) {
        if (probe) sb_add(&b, "#define SPR_PROBE 1\n");
        add_constants(&b);
        if (op >= 0) sb_add(&b, "#define SPR_COMP_ONE %s\n", comp_fn[op]);
        sb_add(&b, "%s", spr__src_prelude);
        for (int k = 0; spr__src_arith_parts[k]; k++) sb_add(&b, "%s", spr__src_arith_parts[k]);
    }
    sb_add(&b, "%s", main_src);
    if (b.oom) { free(b.s); return NULL; }
    return b.s;
}

static GLuint compile(GLenum type, const char *src, const char *name, spr_error *err)
{
    GLuint sh = glCreateShader(type);
    glShaderSource(sh, 1, &src, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        for (char *p = log; *p; p++)
            if (*p == '\n') *p = ' ';
        spr__fail(err, SPR_E_BACKEND, "gl: shader %s does not compile: %s", name, log);
        glDeleteShader(sh);
        return 0;
    }
    return sh;
}

/* A program of compiled shaders, flagged for deletion with it; 0 and one
 * line with GL's log when it does not link. */
static GLuint link_shaders(const GLuint *sh, int n, const char *name, spr_error *err)
{
    GLuint p = glCreateProgram();
    for (int k = 0; k < n; k++) glAttachShader(p, sh[k]);
    glLinkProgram(p);
    for (int k = 0; k < n; k++) glDeleteShader(sh[k]);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        for (char *q = log; *q; q++)
            if (*q == '\n') *q = ' ';
        spr__fail(err, SPR_E_BACKEND, "gl: program %s does not link: %s", name, log);
        glDeleteProgram(p);
        return 0;
    }
    return p;
}

/* Link; the shaders stay attached (flagged for deletion with the program),
 * so spr_gl_program_source() can ask GL for the text it compiled. */
static GLuint link(const char *vs_main, const char *fs_main, int op, int probe, const char *name, spr_error *err)
{
    char *vs = assemble(vs_main, 0, -1, 0), *fs = assemble(fs_main, 1, op, probe);
    GLuint v = vs && fs ? compile(GL_VERTEX_SHADER, vs, name, err) : 0, f = v ? compile(GL_FRAGMENT_SHADER, fs, name, err) : 0;
    if (!vs || !fs) spr__fail(err, SPR_E_NOMEM, "gl: out of memory assembling %s", name);
    free(vs);
    free(fs);
    if (!v || !f) {
        if (v) glDeleteShader(v);
        return 0;
    }
    GLuint sh[2] = {v, f};
    return link_shaders(sh, 2, name, err);
}

/* Resolve `names` (NULL-terminated) into locs; a missing one fails unless
 * `optional` (a composite op reads only some: −1 makes glUniform a no-op). */
static spr_result resolve(GLuint p, const char *prog, const char *const *names, GLint *locs, int optional, spr_error *err)
{
    for (int i = 0; names[i]; i++) {
        locs[i] = glGetUniformLocation(p, names[i]);
        if (locs[i] < 0 && !optional) return spr__fail(err, SPR_E_BACKEND, "gl: program %s has no active uniform %s", prog, names[i]);
    }
    return SPR_OK;
}

static const char *const splat_uniforms[GL_SU__COUNT + 1] = {
#define GL__NAME(e, name) name,
    GL_SPLAT_UNIFORMS(GL__NAME)
#undef GL__NAME
    NULL};
static const char *const rect_uniforms[GL_RU__COUNT + 1] = {
#define GL__NAME(e, name) name,
    GL_RECT_UNIFORMS(GL__NAME)
#undef GL__NAME
    NULL};
static const char *const comp_uniforms[GL_CU__COUNT + 1] = {
#define GL__NAME(e, name) name,
    GL_COMP_UNIFORMS(GL__NAME)
#undef GL__NAME
    NULL};

spr_result gl__build_programs(gl_context *c, spr_error *err)
{
    c->prog_splat = link(spr__src_splat_vert, spr__src_splat_frag, -1, c->probe_programs, "splat", err);
    if (!c->prog_splat || resolve(c->prog_splat, "splat", splat_uniforms, c->su, 0, err)) return err->code;
    c->prog_rect = link(spr__src_splat_vert, spr__src_rect_frag, -1, c->probe_programs, "rect", err);
    if (!c->prog_rect || resolve(c->prog_rect, "rect", rect_uniforms, c->ru, 0, err)) return err->code;
    return SPR_OK;
}

spr_result gl__gauss_program(gl_context *c, int which, spr_error *err)
{
    if (c->gprog[which]) return SPR_OK;
    static const char *const names[GL_GPROG__COUNT] = {"gauss preprocess", "gauss raster", "gauss blend", "gauss backward tiles", "gauss backward Gaussians"};
    static const char *const need[GL_GPROG__COUNT][10] = {{"u_g", "u_n", "u_base", "u_width", NULL}, {"u_g", "u_bg", "u_layer", "u_has", "u_steps", "u_round", NULL},
                                                          {"u_g", "u_size", NULL}, {"u_g", "u_bg", "u_t0", "u_t1", "u_width", "u_budget", "u_gpart_base", NULL},
                                                          {"u_g", "u_n", "u_base", "u_width", "u_stage", "u_ebase", "u_eend", NULL}};
    /* fragment programs all: llvmpipe flushes denormals in fragments, not in compute invocations (PARITY.md rule 6) */
    GLuint p = which == GL_GPROG_PRE        ? link(spr__src_full_vert, spr__src_gauss_pre_frag, -1, 0, names[which], err)
               : which == GL_GPROG_RASTER   ? link(spr__src_full_vert, spr__src_gauss_raster_frag, -1, c->probe_programs, names[which], err)
               : which == GL_GPROG_BLEND    ? link(spr__src_splat_vert, spr__src_gauss_blend_frag, -1, c->probe_programs, names[which], err)
               : which == GL_GPROG_BWD_TILE ? link(spr__src_full_vert, spr__src_gauss_bwd_tile_frag, -1, 0, names[which], err)
                                            : link(spr__src_full_vert, spr__src_gauss_bwd_gauss_frag, -1, 0, names[which], err);
    if (!p) return err->code;
    for (int k = 0; need[which][k]; k++)
        if (glGetUniformLocation(p, need[which][k]) < 0) {
            glDeleteProgram(p);
            return spr__fail(err, SPR_E_BACKEND, "gl: program %s has no active uniform %s", names[which], need[which][k]);
        }
    c->gprog[which] = p;
    return SPR_OK;
}

spr_result gl__comp_program(gl_context *c, spr_composite_op op, spr_error *err)
{
    if (c->prog_comp[op]) return SPR_OK;
    char name[64];
    snprintf(name, sizeof name, "composite %s", spr_composite_info_of(op)->name);
    c->prog_comp[op] = link(spr__src_full_vert, spr__src_composite_frag, (int)op, c->probe_programs, name, err);
    if (!c->prog_comp[op]) return err->code;
    return resolve(c->prog_comp[op], name, comp_uniforms, c->cu[op], 1, err);
}

char *spr_gl_program_source(spr_backend *b, const char *program)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    spr_error err = {0};
    if (!strcmp(program, "composite") && gl__comp_program(c, (spr_composite_op)0, &err)) return NULL;
    for (int k = 0; k < GL_GPROG__COUNT; k++) {
        static const char *const gname[GL_GPROG__COUNT] = {"gauss-preprocess", "gauss-raster", "gauss-blend", "gauss-backward-tiles",
                                                           "gauss-backward-gaussians"};
        if (!strcmp(program, gname[k]) && gl__gauss_program(c, k, &err)) return NULL;
    }
    GLuint p = !strcmp(program, "splat") ? c->prog_splat : !strcmp(program, "composite") ? c->prog_comp[0] : !strcmp(program, "rect") ? c->prog_rect
               : !strcmp(program, "gauss-preprocess") ? c->gprog[GL_GPROG_PRE] : !strcmp(program, "gauss-raster") ? c->gprog[GL_GPROG_RASTER]
               : !strcmp(program, "gauss-blend") ? c->gprog[GL_GPROG_BLEND] : 0;
    if (!p) return NULL;
    GLuint sh[4];
    GLsizei n = 0;
    glGetAttachedShaders(p, 4, &n, sh);
    for (GLsizei i = 0; i < n; i++) {
        GLint type = 0, len = 0;
        glGetShaderiv(sh[i], GL_SHADER_TYPE, &type);
        if (type != GL_FRAGMENT_SHADER && type != GL_COMPUTE_SHADER) continue;
        glGetShaderiv(sh[i], GL_SHADER_SOURCE_LENGTH, &len);
        char *s = malloc((size_t)len + 1);
        if (!s) return NULL;
        glGetShaderSource(sh[i], len + 1, NULL, s);
        return s;
    }
    return NULL;
}
