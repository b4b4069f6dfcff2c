/* gl_backend.c — the GL backend: targets as layers of per-plane array
 * textures, splat draws as instanced quads, composite ops as full-screen
 * passes.
 *
 * Planes (the plane table of spr_backend.h): the depth-test plane is the
 * DEPTH_ATTACHMENT (DEPTH_COMPONENT32F, written through gl_FragDepth); every
 * other plane is a colour attachment in table order, whose index is also the
 * fragment output location (SPR_LOC_*): RGBA32F colour blended as the pass
 * says, R32F stored depth replaced, R32UI id never blended, R32F count
 * blended (ONE, ONE), exact below 2^24.  Fragments generated are counted in
 * a shader-storage word (spr_count_fragment, gl_buffers.c's rules), fragments
 * passed by a GL_SAMPLES_PASSED query.
 */
#include "gl_internal.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

void spr_gl_defaults(spr_gl_desc *d)
{
    memset(d, 0, sizeof *d);
    d->device = -1, d->driver = SPR_GL_DRIVER_DEFAULT;
}

const char *spr_gl_renderer(const spr_backend *b) { return ((const gl_context *)b)->renderer; }

spr_result gl__check(spr_backend *b, const char *what)
{
    GLenum e = glGetError();
    if (e == GL_NO_ERROR) return SPR_OK;
    while (glGetError() != GL_NO_ERROR) {}
    return spr__fail(&b->err, SPR_E_BACKEND, "gl: %s: GL error 0x%x", what, (unsigned)e);
}

static void free_target(gl_target *t)
{
    if (t->fbo) glDeleteFramebuffers(1, &t->fbo);
    memset(t, 0, sizeof *t);
}

/* An image plane: written by the Gaussian rasterizers with imageStore, never a framebuffer attachment
 * (GL_MAX_COLOR_ATTACHMENTS is 8 on llvmpipe; the fragment-written planes use 6 of them). */
static int image_plane(spr_plane p)
{
    const spr_plane_info *pi = spr_plane_info_of(p);
    return pi && (pi->type == SPR_PLANE_F32_IMAGE || pi->type == SPR_PLANE_U32_IMAGE);
}

int gl__plane_attachment(spr_plane p)
{
    const spr_plane_info *pi = spr_plane_info_of(p);
    if (!pi || pi->type == SPR_PLANE_ZTEST) return -1;
    if (image_plane(p)) return GL_NOT_ATTACHED;
    int a = 0;
    for (int q = 0; q < (int)p; q++)
        if (spr_plane_info_of((spr_plane)q)->type != SPR_PLANE_ZTEST && !image_plane((spr_plane)q)) a++;
    return a;
}

/* Internal format of a plane: from its row of the plane table.  Counters
 * are floats blended (ONE, ONE): exact below 2^24, converted on read. */
static GLenum plane_format(spr_plane p)
{
    const spr_plane_info *pi = spr_plane_info_of(p);
    switch (pi->type) {
    case SPR_PLANE_ZTEST: return GL_DEPTH_COMPONENT32F;
    case SPR_PLANE_U32:
    case SPR_PLANE_U32_IMAGE: return GL_R32UI;
    case SPR_PLANE_COUNTER: return GL_R32F;
    case SPR_PLANE_F32:
    case SPR_PLANE_F32_IMAGE:
    default: return pi->channels == 4 ? GL_RGBA32F : GL_R32F;
    }
}

/* Attach layer t of every plane the target has; unused outputs go nowhere. */
static spr_result attach(gl_context *c, int t)
{
    gl_target *tg = &c->targets[t];
    unsigned planes = c->base.target_planes[t];
    GLenum bufs[SPR_PLANE__COUNT];
    int nb = 0;
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        int a = gl__plane_attachment((spr_plane)p), on = (planes & SPR_PLANE_BIT(p)) != 0;
        if (a == GL_NOT_ATTACHED) continue;
        GLenum at = a < 0 ? GL_DEPTH_ATTACHMENT : GL_COLOR_ATTACHMENT0 + (GLenum)a;
        if (on) glNamedFramebufferTextureLayer(tg->fbo, at, c->pool[p], 0, t);
        else glNamedFramebufferTexture(tg->fbo, at, 0, 0);
        if (a >= 0) bufs[nb++] = on ? at : GL_NONE;
    }
    glNamedFramebufferDrawBuffers(tg->fbo, nb, bufs);
    if (glCheckNamedFramebufferStatus(tg->fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return spr__fail(&c->base.err, SPR_E_BACKEND, "gl: incomplete framebuffer for target %d", t);
    return gl__check(&c->base, "attach");
}

/* A plane's array texture of `cap` layers. */
static GLuint new_plane_array(gl_context *c, spr_plane p, int cap)
{
    GLuint t;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t);
    glTextureStorage3D(t, 1, plane_format(p), c->base.view.width, c->base.view.height, cap);
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
}

/* Make the pool hold `layers` layers of every plane some target has, and
 * of the planes of `planes`: existing arrays are re-made larger with the
 * live layers copied and every live framebuffer re-attached; a plane no
 * target had before gets its array now (so the normal plane costs memory
 * only in frames that shade).  Handles are reused, so growing happens only
 * while an algorithm meets a larger target count than before. */
static spr_result grow_pool(gl_context *c, int layers, unsigned planes)
{
    const int W = c->base.view.width, H = c->base.view.height;
    int cap = c->pool_layers;
    if (layers > cap) {
        cap = cap ? cap : 4;
        while (cap < layers) cap *= 2;
        for (int p = 0; p < SPR_PLANE__COUNT; p++) {
            if (!c->pool[p]) continue;
            GLuint t = new_plane_array(c, (spr_plane)p, cap);
            for (int l = 0; l < c->pool_layers && l < c->base.n_targets; l++)
                if (c->base.target_planes[l] & SPR_PLANE_BIT(p))
                    glCopyImageSubData(c->pool[p], GL_TEXTURE_2D_ARRAY, 0, 0, 0, l, t, GL_TEXTURE_2D_ARRAY, 0, 0, 0, l, W, H, 1);
            glDeleteTextures(1, &c->pool[p]);
            c->pool[p] = t;
        }
    }
    for (int p = 0; p < SPR_PLANE__COUNT; p++)
        if ((planes & SPR_PLANE_BIT(p)) && !c->pool[p]) c->pool[p] = new_plane_array(c, (spr_plane)p, cap);
    const int grew = cap != c->pool_layers;
    c->pool_layers = cap;
    spr_result r = gl__check(&c->base, "target pool");
    for (int l = 0; grew && !r && l < c->base.n_targets; l++)
        if (c->base.target_planes[l] && c->targets[l].fbo) r = attach(c, l);
    return r;
}

static void drop_pool(gl_context *c)
{
    for (int p = 0; p < SPR_PLANE__COUNT; p++)
        if (c->pool[p]) glDeleteTextures(1, &c->pool[p]);
    memset(c->pool, 0, sizeof c->pool);
    c->pool_layers = 0;
}

static spr_result gl_set_view(spr_backend *b, const spr_view *v)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    /* no target lives across a view change (core checks); the pool is kept
     * while the size stays, so frames do not reallocate it */
    if (c->pool_w != v->width || c->pool_h != v->height) drop_pool(c);
    c->pool_w = v->width;
    c->pool_h = v->height;
    glViewport(0, 0, v->width, v->height);
    return gl__check(b, "viewport");
}

/* Every plane the target has: colour to `color`, the others to the clear
 * value of the plane table. */
static spr_result gl_clear(spr_backend *b, int t, const float color[4])
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    gl_target *tg = &c->targets[t];
    unsigned planes = b->target_planes[t];
    if (t == c->list_target) c->list_target = -1; /* a clear empties the fragment lists too */
    glBindFramebuffer(GL_FRAMEBUFFER, tg->fbo);
    for (int p = 0; p < SPR_PLANE__COUNT; p++)
        if (gl__plane_attachment((spr_plane)p) >= 0) glColorMaski((GLuint)gl__plane_attachment((spr_plane)p), GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        if (!(planes & SPR_PLANE_BIT(p))) continue;
        const spr_plane_info *pi = spr_plane_info_of((spr_plane)p);
        int a = gl__plane_attachment((spr_plane)p);
        float f = (float)pi->clear, fv[4] = {f, f, f, f};
        GLuint u[4] = {(GLuint)pi->clear, 0, 0, 0};
        if (a == GL_NOT_ATTACHED) { /* an image plane: its layer cleared as a texture */
            const int W = b->view.width, H = b->view.height;
            if (pi->type == SPR_PLANE_U32_IMAGE) glClearTexSubImage(c->pool[p], 0, 0, 0, t, W, H, 1, GL_RED_INTEGER, GL_UNSIGNED_INT, u);
            else glClearTexSubImage(c->pool[p], 0, 0, 0, t, W, H, 1, pi->channels == 4 ? GL_RGBA : GL_RED, GL_FLOAT,
                                    p == SPR_PLANE_COLOR ? color : fv);
        } else if (a < 0) glClearBufferfv(GL_DEPTH, 0, &f);
        else if (p == SPR_PLANE_COLOR) glClearBufferfv(GL_COLOR, a, color);
        else if (pi->type == SPR_PLANE_U32) glClearBufferuiv(GL_COLOR, a, u);
        else glClearBufferfv(GL_COLOR, a, fv);
    }
    return gl__check(b, "clear");
}

static spr_result gl_target_create(spr_backend *b, unsigned planes, int *out)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    spr_result r = spr__backend_add_target(b, planes, out, (void **)&c->targets, &c->cap, sizeof *c->targets);
    if (r) return r;
    const int t = *out;
    gl_target *tg = &c->targets[t];
    free_target(tg);
    glCreateFramebuffers(1, &tg->fbo);
    static const float zero[4] = {0, 0, 0, 0};
    if ((r = grow_pool(c, t + 1, planes)) || (r = attach(c, t)) || (r = gl_clear(b, t, zero))) {
        free_target(tg); /* no framebuffer left behind on any failure (core frees the slot) */
        return r;
    }
    return SPR_OK;
}

static void gl_target_destroy(spr_backend *b, int t)
{
    gl__make_current(gl_ctx(b));
    if (t == gl_ctx(b)->list_target) gl_ctx(b)->list_target = -1;
    free_target(&gl_ctx(b)->targets[t]);
}

static void blend_factors(spr_blend mode, GLenum *sf, GLenum *df)
{
    switch (mode) {
    case SPR_BLEND_PREMUL: *sf = GL_ONE; *df = GL_ONE_MINUS_SRC_ALPHA; break;
    case SPR_BLEND_ADD:
    case SPR_BLEND_SUB: *sf = GL_ONE; *df = GL_ONE; break;
    case SPR_BLEND_OVER: *sf = GL_SRC_ALPHA; *df = GL_ONE_MINUS_SRC_ALPHA; break;
    case SPR_BLEND_REPLACE:
    default: *sf = GL_ONE; *df = GL_ZERO; break;
    }
}

/* rgb and alpha blends of one draw buffer; no blending when both replace. */
static void set_blend(GLuint buf, spr_blend rgb, spr_blend alpha)
{
    if (rgb == SPR_BLEND_REPLACE && alpha == SPR_BLEND_REPLACE) {
        glDisablei(GL_BLEND, buf);
        return;
    }
    GLenum s0, d0, s1, d1;
    blend_factors(rgb, &s0, &d0);
    blend_factors(alpha, &s1, &d1);
    glEnablei(GL_BLEND, buf);
    glBlendEquationSeparatei(buf, rgb == SPR_BLEND_SUB ? GL_FUNC_REVERSE_SUBTRACT : GL_FUNC_ADD,
                             alpha == SPR_BLEND_SUB ? GL_FUNC_REVERSE_SUBTRACT : GL_FUNC_ADD); /* dst − src */
    glBlendFuncSeparatei(buf, s0, d0, s1, d1);
}

static spr_result gl_draw(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    const spr_pass_state *s = &d->state;
    const spr_view *v = &b->view;
    const size_t n = d->indices ? d->count : d->cloud->n;
    st->splats = n;
    if (b->probe && !c->probe_programs) return gl__probe_refused(c);
    if (n == 0) return SPR_OK;
    gl_instance *inst = malloc(n * sizeof *inst);
    if (!inst) return spr__fail(&b->err, SPR_E_NOMEM, "gl: out of memory for %zu instances", n);
    size_t m = 0;
    const spr_cloud *cl = d->cloud;
    for (size_t i = 0; i < n; i++) { /* submission order; off-screen splats have no fragment to draw */
        uint32_t sid = d->indices ? d->indices[i] : (uint32_t)i;
        float r = spr_draw_radius(d, sid);
        gl_instance *g = &inst[m];
        int x0, y0, x1, y1;
        spr_draw_ellipse(d, sid, r, g->e);
        if (!spr_splat_pixel_rect_ell(v, cl->pos + 3 * (size_t)sid, cl->nrm + 3 * (size_t)sid, g->e, r, &x0, &y0, &x1, &y1)) continue;
        g->rect[0] = x0; g->rect[1] = y0; g->rect[2] = x1; g->rect[3] = y1;
        for (int k = 0; k < 3; k++) {
            g->pr[k] = cl->pos[3 * (size_t)sid + k];
            g->na[k] = cl->nrm[3 * (size_t)sid + k];
            g->c[k] = cl->color[3 * (size_t)sid + k];
        }
        g->pr[3] = r;
        g->na[3] = d->alpha > 0.0f ? d->alpha : cl->alpha[sid];
        g->c[3] = 0.0f;
        g->id = d->id_base + sid;
        g->seq = d->seq_base + (uint32_t)i;
        m++;
    }
    gl__upload_instances(c, inst, m);
    free(inst);

    gl_target *tg = &c->targets[target];
    glBindFramebuffer(GL_FRAMEBUFFER, tg->fbo);
    glUseProgram(c->prog_splat);
    const GLint *u = c->su;
    glUniform1fv(u[GL_SU_M], 16, v->M);
    glUniform2f(u[GL_SU_SIZE], (float)v->width, (float)v->height);
    glUniform1f(u[GL_SU_SX], v->ndc_sx);
    glUniform1f(u[GL_SU_SY], v->ndc_sy);
    glUniform1f(u[GL_SU_EPS], s->eps_t);
    glUniform1f(u[GL_SU_DMIN], s->lowres.d_min);
    glUniform1f(u[GL_SU_DMAX], s->lowres.d_max);
    glUniform1f(u[GL_SU_N], s->lowres.n);
    glUniform1f(u[GL_SU_INVN], s->lowres.inv_n);
    glUniform1f(u[GL_SU_KSCALE], spr_draw_kernel_scale(d));
    glUniform1i(u[GL_SU_KERNEL], (int)s->kernel);
    glUniform1i(u[GL_SU_DEPTH], (int)s->depth_value);
    glUniform1i(u[GL_SU_OUTPUT], (int)s->output);
    glUniform1i(u[GL_SU_CULL], s->cull_backfaces);
    glUniform1i(u[GL_SU_MASK], d->depth_mask != 0);
    glUniform1i(u[GL_SU_LAYER], d->depth_mask ? d->mask_target : 0);
    if (d->depth_mask) { /* the mask target's stored depth, read-only (gl_prelude.glsl) */
        glBindTextureUnit(1, c->pool[SPR_PLANE_DEPTH]);
        glTextureBarrier();
    }

    gl__pass_state(s);
    gl__draw_instances(c, m, st);
    return gl__check(b, "draw");
}

void gl__upload_instances(gl_context *c, const gl_instance *inst, size_t m)
{
    if (m * sizeof *inst > c->instances_cap) {
        c->instances_cap = m * sizeof *inst;
        glNamedBufferData(c->instances, (GLsizeiptr)c->instances_cap, NULL, GL_STREAM_DRAW);
    }
    if (m) glNamedBufferSubData(c->instances, 0, (GLsizeiptr)(m * sizeof *inst), inst);
}

void gl__pass_state(const spr_pass_state *s)
{
    static const GLenum funcs[SPR_FUNC__COUNT] = {GL_LESS, GL_LEQUAL, GL_ALWAYS};
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(funcs[s->depth_func]);
    glDepthMask(s->depth_write ? GL_TRUE : GL_FALSE);
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        int a = gl__plane_attachment((spr_plane)p);
        if (a < 0) continue; /* the depth attachment, or an image plane */
        GLboolean on = (s->write_mask & SPR_PLANE_BIT(p)) != 0;
        glColorMaski((GLuint)a, on, on, on, on);
        const spr_plane_type type = spr_plane_info_of((spr_plane)p)->type;
        if (p == SPR_PLANE_COLOR) set_blend((GLuint)a, s->blend, s->blend_alpha);
        else if (p == SPR_PLANE_OPACITY) set_blend((GLuint)a, s->blend_alpha, s->blend_alpha);
        else if (p == SPR_PLANE_NORMAL) set_blend((GLuint)a, s->blend, s->blend);
        else if (type == SPR_PLANE_COUNTER) set_blend((GLuint)a, SPR_BLEND_ADD, SPR_BLEND_ADD);
        else set_blend((GLuint)a, SPR_BLEND_REPLACE, SPR_BLEND_REPLACE);
    }
}

void gl__draw_instances(gl_context *c, size_t m, spr_draw_stats *st)
{
    const int keep = c->base.probe ? c->base.probe->n_frags : 0;
    gl__probe_begin(c);
    gl__buffer_fill(c->counters, 0, sizeof(GLuint), 0);
    GLuint q;
    glGenQueries(1, &q);
    glBeginQuery(GL_SAMPLES_PASSED, q);
    glBindVertexArray(c->vao);
    if (m) glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)m);
    glEndQuery(GL_SAMPLES_PASSED);
    GLuint64 passed = 0;
    glGetQueryObjectui64v(q, GL_QUERY_RESULT, &passed);
    glDeleteQueries(1, &q);
    GLuint generated = 0;
    gl__buffer_read(c->counters, 0, sizeof generated, &generated);
    st->generated = generated;
    st->passed = passed;
    gl__probe_end(c, keep);
}

spr_result gl__probe_refused(gl_context *c)
{
    return spr__fail(&c->base.err, SPR_E_ARG, "gl: pixel history needs the programs' probe variant (spr_gl_desc.probe)");
}

void gl__probe_begin(gl_context *c)
{
    const spr_probe *p = c->base.probe;
    if (!p) return;
    if (!c->probe_buf) gl__buffer_alloc(&c->probe_buf, 16 + (size_t)2 * SPR_PROBE_MAX * 64, GL_DYNAMIC_READ);
    gl__buffer_fill(c->probe_buf, 0, 16, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, c->probe_buf);
    GLint prog = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &prog);
    glUniform2i(glGetUniformLocation((GLuint)prog, "u_probe"), p->x, p->y);
}

spr_result gl__probe_end(gl_context *c, int keep)
{
    spr_probe *p = c->base.probe;
    if (!p) return SPR_OK;
    GLuint n = 0;
    gl__buffer_read(c->probe_buf, 0, sizeof n, &n);
    if (n > 2u * SPR_PROBE_MAX) p->overflow = 1, n = 2u * SPR_PROBE_MAX;
    uint32_t *rec = malloc((size_t)(n ? n : 1) * 64);
    if (!rec) return spr__fail(&c->base.err, SPR_E_NOMEM, "gl: out of memory reading the probe");
    gl__buffer_read(c->probe_buf, 16, (size_t)n * 64, rec);
    p->n_frags = keep;
    for (GLuint i = 0; i < n; i++) {
        const uint32_t *r = rec + 16 * (size_t)i;
        float f[8];
        memcpy(f, r + 3, sizeof f);
        if (r[0] == 1u) {
            spr_probe_frag fr = {r[1], r[2], f[0], f[1], f[2], {f[3], f[4], f[5], f[6]}, f[7]};
            spr_probe_add_frag(p, &fr);
        } else if (r[0] == 2u) {
            spr_probe_add_note(p, (int32_t)r[1], (int32_t)r[2], f[0], f[1], f[2], f[3]);
        }
    }
    free(rec);
    return gl__check(&c->base, "probe");
}

/* The composite table's per-pixel function as a full-screen pass over the
 * inputs' layers of the pool (gl_composite.frag). */
static spr_result gl_composite(spr_backend *b, const spr_composite_desc *cd)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    gl_target *out = &c->targets[cd->output];
    glBindFramebuffer(GL_FRAMEBUFFER, out->fbo);
    spr_result pr = gl__comp_program(c, cd->op, &b->err);
    if (pr) return pr;
    if (b->probe && !c->probe_programs) return gl__probe_refused(c);
    glUseProgram(c->prog_comp[cd->op]);
    const GLint *u = c->cu[cd->op];
    glBindTextureUnit(0, c->pool[SPR_PLANE_COLOR]);
    glBindTextureUnit(1, c->pool[SPR_PLANE_DEPTH]);
    glBindTextureUnit(2, c->pool[SPR_PLANE_OPACITY]);
    glBindTextureUnit(3, c->pool[SPR_PLANE_NORMAL]);
    static const float no_params[SPR_PRM_COUNT];
    const float *prm = cd->params ? cd->params : no_params;
    if (prm[SPR_PRM_ENV] != 0.0f) { /* the cube map as a six-layer array, fetched by texel (gl_prelude.glsl) */
        if (c->env) glDeleteTextures(1, &c->env);
        const int S = cd->env->size;
        glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &c->env);
        glTextureStorage3D(c->env, 1, GL_RGBA32F, S, S, 6);
        glTextureSubImage3D(c->env, 0, 0, 0, 0, S, S, 6, GL_RGBA, GL_FLOAT, cd->env->texels);
        glTextureParameteri(c->env, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(c->env, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glBindTextureUnit(4, c->env);
    }
    glUniform1fv(u[GL_CU_PRM], SPR_PRM_COUNT, prm);
    glUniform1iv(u[GL_CU_LAYER], cd->n_inputs, cd->inputs);
    glUniform1i(u[GL_CU_K], cd->n_inputs);
    glUniform1f(u[GL_CU_EPS], cd->eps_t);
    glUniform1fv(u[GL_CU_BG], 3, cd->background);
    if (cd->op == SPR_COMP_PREFIX) {
        spr_result r = gl__bind_lists(c, cd);
        if (r) return r;
    }
    glUniform1i(u[GL_CU_LISTW], b->view.width);
    glUniform1i(u[GL_CU_NBRW], cd->rects ? (int)spr_rects_words(cd->rects->n) : 0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        int a = gl__plane_attachment((spr_plane)p);
        if (a < 0) continue;
        GLboolean on = ((spr_composite_info_of(cd->op)->writes | SPR_PLANE_BIT(SPR_PLANE_NORMAL)) & SPR_PLANE_BIT(p)) != 0;
        glColorMaski((GLuint)a, on, on, on, on);
        glDisablei(GL_BLEND, (GLuint)a);
    }
    glTextureBarrier(); /* the inputs were drawn by earlier passes */
    glBindVertexArray(c->vao);
    gl__probe_begin(c);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    if (b->probe && (pr = gl__probe_end(c, b->probe->n_frags))) return pr;
    return gl__check(b, "composite");
}

static spr_result gl_read_plane(spr_backend *b, int t, spr_plane p, void *out)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    int W = b->view.width, H = b->view.height;
    const spr_plane_info *pi = spr_plane_info_of(p);
    size_t bytes = (size_t)W * H * (size_t)pi->channels * 4;
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    switch (pi->type) {
    case SPR_PLANE_ZTEST:
        glGetTextureSubImage(c->pool[p], 0, 0, 0, t, W, H, 1, GL_DEPTH_COMPONENT, GL_FLOAT, (GLsizei)bytes, out);
        break;
    case SPR_PLANE_U32:
    case SPR_PLANE_U32_IMAGE:
        glGetTextureSubImage(c->pool[p], 0, 0, 0, t, W, H, 1, GL_RED_INTEGER, GL_UNSIGNED_INT, (GLsizei)bytes, out);
        break;
    case SPR_PLANE_COUNTER: {
        glGetTextureSubImage(c->pool[p], 0, 0, 0, t, W, H, 1, GL_RED, GL_FLOAT, (GLsizei)bytes, out);
        float *f = out;
        uint32_t *u = out;
        for (size_t i = 0; i < (size_t)W * H; i++) u[i] = (uint32_t)f[i]; /* exact: counts < 2^24 */
        break;
    }
    case SPR_PLANE_F32:
    case SPR_PLANE_F32_IMAGE:
    default:
        glGetTextureSubImage(c->pool[p], 0, 0, 0, t, W, H, 1, pi->channels == 4 ? GL_RGBA : GL_RED, GL_FLOAT, (GLsizei)bytes, out);
        break;
    }
    return gl__check(b, "read");
}

static void gl_destroy(spr_backend *b)
{
    gl_context *c = gl_ctx(b);
    if (c->ctx != EGL_NO_CONTEXT) {
        gl__make_current(c);
        for (int t = 0; t < c->cap; t++) free_target(&c->targets[t]);
        drop_pool(c);
        if (c->env) glDeleteTextures(1, &c->env);
        gl__rects_free(c);
        gl__gauss_free(c);
        glDeleteBuffers(1, &c->instances);
        glDeleteBuffers(1, &c->counters);
        if (c->probe_buf) glDeleteBuffers(1, &c->probe_buf);
        glDeleteVertexArrays(1, &c->vao);
        glDeleteProgram(c->prog_splat);
        for (int op = 0; op < SPR_COMP__COUNT; op++)
            if (c->prog_comp[op]) glDeleteProgram(c->prog_comp[op]);
        glDeleteProgram(c->prog_rect);
    }
    gl__egl_close(c);
    free(c->targets);
    free(c);
}

static void setup_vao(gl_context *c)
{
    glCreateVertexArrays(1, &c->vao);
    glCreateBuffers(1, &c->instances);
    gl__buffer_alloc(&c->counters, sizeof(GLuint), GL_DYNAMIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GL_SSBO_COUNTER, c->counters);
    glNamedBufferData(c->instances, 1024, NULL, GL_STREAM_DRAW);
    c->instances_cap = 1024;
    GLuint vao = c->vao;
    glVertexArrayVertexBuffer(vao, 0, c->instances, 0, sizeof(gl_instance));
    glVertexArrayBindingDivisor(vao, 0, 1);
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribIFormat(vao, 0, 4, GL_INT, offsetof(gl_instance, rect));
    glEnableVertexArrayAttrib(vao, 1);
    glVertexArrayAttribFormat(vao, 1, 4, GL_FLOAT, GL_FALSE, offsetof(gl_instance, pr));
    glEnableVertexArrayAttrib(vao, 2);
    glVertexArrayAttribFormat(vao, 2, 4, GL_FLOAT, GL_FALSE, offsetof(gl_instance, na));
    glEnableVertexArrayAttrib(vao, 3);
    glVertexArrayAttribFormat(vao, 3, 4, GL_FLOAT, GL_FALSE, offsetof(gl_instance, c));
    glEnableVertexArrayAttrib(vao, 4);
    glVertexArrayAttribIFormat(vao, 4, 1, GL_UNSIGNED_INT, offsetof(gl_instance, id));
    glEnableVertexArrayAttrib(vao, 5);
    glVertexArrayAttribIFormat(vao, 5, 1, GL_UNSIGNED_INT, offsetof(gl_instance, seq));
    glEnableVertexArrayAttrib(vao, 6);
    glVertexArrayAttribFormat(vao, 6, 4, GL_FLOAT, GL_FALSE, offsetof(gl_instance, e));
    for (GLuint a = 0; a < 7; a++) glVertexArrayAttribBinding(vao, a, 0);
}

spr_backend *spr_gl_create(const spr_gl_desc *d, spr_error *err)
{
    spr_gl_desc def;
    if (!d) { spr_gl_defaults(&def); d = &def; }
    gl_context *c = calloc(1, sizeof *c);
    if (!c) { spr__fail(err, SPR_E_NOMEM, "gl: out of memory"); return NULL; }
    c->dpy = EGL_NO_DISPLAY;
    c->list_target = -1;
    c->ctx = EGL_NO_CONTEXT;
    c->probe_programs = d->probe;
    c->gauss_batch = d->gauss_batch;
    c->max_texels = d->max_texels;
    c->gauss_steps = d->gauss_steps;
    spr_backend *b = &c->base;
    b->name = "gl";
    b->set_view = gl_set_view;
    b->target_create = gl_target_create;
    b->target_destroy = gl_target_destroy;
    b->clear = gl_clear;
    b->draw_splats = gl_draw;
    b->composite = gl_composite;
    b->draw_rects = gl__draw_rects;
    b->gauss_preprocess = gl__gauss_preprocess;
    b->gauss_raster = gl__gauss_raster;
    b->gauss_draw = gl__gauss_draw;
    b->gauss_backward = gl__gauss_backward;
    b->fits = gl__gauss_fits;
    b->read_plane = gl_read_plane;
    b->destroy = gl_destroy;
    if (gl__egl_open(c, d, err) || gl__build_programs(c, err)) {
        gl_destroy(b);
        return NULL;
    }
    setup_vao(c);
    glDisable(GL_DITHER);
    glDisable(GL_CULL_FACE);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_MULTISAMPLE);
    glDisable(GL_DEPTH_CLAMP);
    if (gl__check(b, "setup")) {
        *err = b->err;
        gl_destroy(b);
        return NULL;
    }
    return b;
}
