/* gl_backend.c — the GL backend: targets as framebuffers, splat draws as
 * instanced quads, compositing as a full-screen pass.
 *
 * Target attachments (SPEC §3.2):
 *   COLOR_ATTACHMENT0  RGBA32F  Σ w·c, Σ w     blended as the pass says
 *   COLOR_ATTACHMENT1  R32F     stored depth   never blended (replace)
 *   COLOR_ATTACHMENT2  R32UI    splat id       integer: never blended
 *   COLOR_ATTACHMENT3  R32F     count          blended (ONE, ONE), exact below 2^24
 *   DEPTH_ATTACHMENT   DEPTH_COMPONENT32F      the test depth z (gl_FragDepth)
 * Fragments generated are counted by an atomic counter, fragments passed by a
 * GL_SAMPLES_PASSED query.
 */
#include "gl_internal.h"
#include "spr_fragment.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

void spr_gl_defaults(spr_gl_desc *d) { d->device = -1; }

const char *spr_gl_renderer(const spr_backend *b) { return ((const gl_context *)b)->renderer; }

spr_result gl__check(spr_backend *b, const char *what)
{
    GLenum e = glGetError();
    if (e == GL_NO_ERROR) return SPR_OK;
    while (glGetError() != GL_NO_ERROR) {}
    return spr__fail(&b->err, SPR_E_BACKEND, "gl: %s: GL error 0x%x", what, (unsigned)e);
}

/* One instance per submitted splat with a non-empty pixel rectangle. */
typedef struct gl_instance {
    int32_t rect[4];
    float pr[4];
    float na[4];
    float c[4];
    uint32_t id;
} gl_instance;

static void free_target(gl_target *t)
{
    GLuint tex[5] = {t->color, t->depth_value, t->id, t->count, t->ztest};
    if (t->fbo) glDeleteFramebuffers(1, &t->fbo);
    glDeleteTextures(5, tex);
    memset(t, 0, sizeof *t);
}

static GLuint make_tex(GLenum fmt, int w, int h)
{
    GLuint t;
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, 1, fmt, w, h);
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
}

static spr_result gl_set_view(spr_backend *b, const spr_view *v)
{
    glViewport(0, 0, v->width, v->height);
    return gl__check(b, "viewport");
}

static spr_result gl_clear(spr_backend *b, int t, const float color[4])
{
    gl_target *tg = &gl_ctx(b)->targets[t];
    static const float one = 1.0f, zero[4] = {0, 0, 0, 0};
    static const GLuint none[4] = {0xFFFFFFFFu, 0, 0, 0};
    glBindFramebuffer(GL_FRAMEBUFFER, tg->fbo);
    for (int i = 0; i < 4; i++) glColorMaski((GLuint)i, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glClearBufferfv(GL_COLOR, 0, color);
    glClearBufferfv(GL_COLOR, 1, &one);
    glClearBufferuiv(GL_COLOR, 2, none);
    glClearBufferfv(GL_COLOR, 3, zero);
    glClearBufferfv(GL_DEPTH, 0, &one);
    return gl__check(b, "clear");
}

static spr_result gl_target_create(spr_backend *b, int *out)
{
    gl_context *c = gl_ctx(b);
    int t;
    spr_result r = spr__backend_add_target(b, &t, (void **)&c->targets, &c->cap, sizeof *c->targets);
    if (r) return r;
    int W = b->view.width, H = b->view.height;
    gl_target *tg = &c->targets[t];
    free_target(tg);
    tg->color = make_tex(GL_RGBA32F, W, H);
    tg->depth_value = make_tex(GL_R32F, W, H);
    tg->id = make_tex(GL_R32UI, W, H);
    tg->count = make_tex(GL_R32F, W, H);
    tg->ztest = make_tex(GL_DEPTH_COMPONENT32F, W, H);
    glCreateFramebuffers(1, &tg->fbo);
    glNamedFramebufferTexture(tg->fbo, GL_COLOR_ATTACHMENT0, tg->color, 0);
    glNamedFramebufferTexture(tg->fbo, GL_COLOR_ATTACHMENT1, tg->depth_value, 0);
    glNamedFramebufferTexture(tg->fbo, GL_COLOR_ATTACHMENT2, tg->id, 0);
    glNamedFramebufferTexture(tg->fbo, GL_COLOR_ATTACHMENT3, tg->count, 0);
    glNamedFramebufferTexture(tg->fbo, GL_DEPTH_ATTACHMENT, tg->ztest, 0);
    static const GLenum bufs[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
    glNamedFramebufferDrawBuffers(tg->fbo, 4, bufs);
    if (glCheckNamedFramebufferStatus(tg->fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        free_target(tg);
        b->target_live[t] = 0;
        return spr__fail(&b->err, SPR_E_BACKEND, "gl: incomplete framebuffer for a %dx%d target", W, H);
    }
    if ((r = gl__check(b, "target"))) return r;
    *out = t;
    static const float zero[4] = {0, 0, 0, 0};
    return gl_clear(b, t, zero);
}

static void gl_target_destroy(spr_backend *b, int t) { free_target(&gl_ctx(b)->targets[t]); }

static void set_blend(GLuint buf, spr_blend mode)
{
    switch (mode) {
    case SPR_BLEND_ADD:
        glEnablei(GL_BLEND, buf);
        glBlendEquationi(buf, GL_FUNC_ADD);
        glBlendFunci(buf, GL_ONE, GL_ONE);
        break;
    case SPR_BLEND_OVER:
        glEnablei(GL_BLEND, buf);
        glBlendEquationi(buf, GL_FUNC_ADD);
        glBlendFunci(buf, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        break;
    default: glDisablei(GL_BLEND, buf); break;
    }
}

static spr_result gl_draw(spr_backend *b, int target, const spr_draw_desc *d, spr_draw_stats *st)
{
    gl_context *c = gl_ctx(b);
    const spr_pass_state *s = &d->state;
    const spr_view *v = &b->view;
    const size_t n = d->indices ? d->count : d->cloud->n;
    st->splats = n;
    if (n == 0) return SPR_OK;
    gl_instance *inst = malloc(n * sizeof *inst);
    if (!inst) return spr__fail(&b->err, SPR_E_NOMEM, "gl: out of memory for %zu instances", n);
    size_t m = 0;
    const spr_cloud *cl = d->cloud;
    for (size_t i = 0; i < n; i++) { /* submission order; off-screen splats have no fragment to draw */
        uint32_t sid = d->indices ? d->indices[i] : (uint32_t)i;
        float r = d->radius_override ? d->radius_override[sid] : cl->radius[sid];
        gl_instance *g = &inst[m];
        int x0, y0, x1, y1;
        if (!spr_splat_pixel_rect(v, cl->pos + 3 * (size_t)sid, cl->nrm + 3 * (size_t)sid, r, &x0, &y0, &x1, &y1)) continue;
        g->rect[0] = x0; g->rect[1] = y0; g->rect[2] = x1; g->rect[3] = y1;
        for (int k = 0; k < 3; k++) {
            g->pr[k] = cl->pos[3 * (size_t)sid + k];
            g->na[k] = cl->nrm[3 * (size_t)sid + k];
            g->c[k] = cl->color[3 * (size_t)sid + k];
        }
        g->pr[3] = r;
        g->na[3] = cl->alpha[sid];
        g->c[3] = 0.0f;
        g->id = sid;
        m++;
    }
    if (m * sizeof *inst > c->instances_cap) {
        c->instances_cap = m * sizeof *inst;
        glNamedBufferData(c->instances, (GLsizeiptr)c->instances_cap, NULL, GL_STREAM_DRAW);
    }
    glNamedBufferSubData(c->instances, 0, (GLsizeiptr)(m * sizeof *inst), inst);
    free(inst);

    gl_target *tg = &c->targets[target];
    glBindFramebuffer(GL_FRAMEBUFFER, tg->fbo);
    glUseProgram(c->prog_splat);
    GLuint p = c->prog_splat;
    glUniform1fv(glGetUniformLocation(p, "u_M"), 16, v->M);
    glUniform2f(glGetUniformLocation(p, "u_size"), (float)v->width, (float)v->height);
    glUniform1f(glGetUniformLocation(p, "u_sx"), v->ndc_sx);
    glUniform1f(glGetUniformLocation(p, "u_sy"), v->ndc_sy);
    glUniform1f(glGetUniformLocation(p, "u_eps"), s->eps_t);
    glUniform1f(glGetUniformLocation(p, "u_dmin"), s->lowres.d_min);
    glUniform1f(glGetUniformLocation(p, "u_dmax"), s->lowres.d_max);
    glUniform1f(glGetUniformLocation(p, "u_n"), s->lowres.n);
    glUniform1f(glGetUniformLocation(p, "u_invn"), s->lowres.inv_n);
    glUniform1i(glGetUniformLocation(p, "u_kernel"), (int)s->kernel);
    glUniform1i(glGetUniformLocation(p, "u_depth"), (int)s->depth_value);
    glUniform1i(glGetUniformLocation(p, "u_output"), (int)s->output);
    glUniform1i(glGetUniformLocation(p, "u_cull"), s->cull_backfaces);

    static const GLenum funcs[SPR_FUNC__COUNT] = {GL_LESS, GL_LEQUAL, GL_ALWAYS};
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(funcs[s->depth_func]);
    glDepthMask(s->depth_write ? GL_TRUE : GL_FALSE);
    unsigned wm = s->write_mask;
    GLboolean col = (wm & SPR_WRITE_COLOR) != 0, dep = (wm & SPR_WRITE_DEPTH) != 0, idw = (wm & SPR_WRITE_ID) != 0,
              cnt = (wm & SPR_WRITE_COUNT) != 0;
    glColorMaski(0, col, col, col, col);
    glColorMaski(1, dep, dep, dep, dep);
    glColorMaski(2, idw, idw, idw, idw);
    glColorMaski(3, cnt, cnt, cnt, cnt);
    set_blend(0, s->blend);
    set_blend(1, SPR_BLEND_REPLACE);
    glDisablei(GL_BLEND, 2);
    set_blend(3, SPR_BLEND_ADD);

    static const GLuint zero = 0;
    glNamedBufferSubData(c->counters, 0, sizeof zero, &zero);
    GLuint q;
    glGenQueries(1, &q);
    glBeginQuery(GL_SAMPLES_PASSED, q);
    glBindVertexArray(c->vao);
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)m);
    glEndQuery(GL_SAMPLES_PASSED);
    GLuint64 passed = 0;
    glGetQueryObjectui64v(q, GL_QUERY_RESULT, &passed);
    glDeleteQueries(1, &q);
    GLuint generated = 0;
    glGetNamedBufferSubData(c->counters, 0, sizeof generated, &generated);
    st->generated = generated;
    st->passed = passed;
    return gl__check(b, "draw");
}

static spr_result ensure_layers(gl_context *c, int K, int W, int H)
{
    if (c->arr_color && c->arr_layers >= K && c->arr_w == W && c->arr_h == H) return SPR_OK;
    if (c->arr_color) {
        glDeleteTextures(1, &c->arr_color);
        glDeleteTextures(1, &c->arr_depth);
    }
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &c->arr_color);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &c->arr_depth);
    glTextureStorage3D(c->arr_color, 1, GL_RGBA32F, W, H, K);
    glTextureStorage3D(c->arr_depth, 1, GL_R32F, W, H, K);
    c->arr_layers = K;
    c->arr_w = W;
    c->arr_h = H;
    return gl__check(&c->base, "composite inputs");
}

static spr_result gl_composite(spr_backend *b, const spr_composite_desc *cd)
{
    gl_context *c = gl_ctx(b);
    int W = b->view.width, H = b->view.height, K = cd->n_inputs;
    spr_result r = ensure_layers(c, K, W, H);
    if (r) return r;
    for (int k = 0; k < K; k++) { /* bit copies: the inputs as array layers */
        gl_target *in = &c->targets[cd->inputs[k]];
        glCopyImageSubData(in->color, GL_TEXTURE_2D, 0, 0, 0, 0, c->arr_color, GL_TEXTURE_2D_ARRAY, 0, 0, 0, k, W, H, 1);
        glCopyImageSubData(in->depth_value, GL_TEXTURE_2D, 0, 0, 0, 0, c->arr_depth, GL_TEXTURE_2D_ARRAY, 0, 0, 0, k, W, H, 1);
    }
    gl_target *out = &c->targets[cd->output];
    glBindFramebuffer(GL_FRAMEBUFFER, out->fbo);
    glUseProgram(c->prog_comp);
    GLuint p = c->prog_comp;
    glBindTextureUnit(0, c->arr_color);
    glBindTextureUnit(1, c->arr_depth);
    glUniform1i(glGetUniformLocation(p, "u_col"), 0);
    glUniform1i(glGetUniformLocation(p, "u_dep"), 1);
    glUniform1i(glGetUniformLocation(p, "u_K"), K);
    glUniform1i(glGetUniformLocation(p, "u_op"), (int)cd->op);
    glUniform1f(glGetUniformLocation(p, "u_eps"), cd->eps_t);
    glUniform3f(glGetUniformLocation(p, "u_bg"), cd->background[0], cd->background[1], cd->background[2]);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glColorMaski(2, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glColorMaski(3, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    for (GLuint i = 0; i < 4; i++) glDisablei(GL_BLEND, i);
    glBindVertexArray(c->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    return gl__check(b, "composite");
}

static spr_result gl_read_plane(spr_backend *b, int t, spr_plane p, void *out)
{
    gl_target *tg = &gl_ctx(b)->targets[t];
    int W = b->view.width, H = b->view.height;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, tg->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    switch (p) {
    case SPR_PLANE_COLOR:
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glReadPixels(0, 0, W, H, GL_RGBA, GL_FLOAT, out);
        break;
    case SPR_PLANE_DEPTH:
        glReadBuffer(GL_COLOR_ATTACHMENT1);
        glReadPixels(0, 0, W, H, GL_RED, GL_FLOAT, out);
        break;
    case SPR_PLANE_TEST: glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_FLOAT, out); break;
    case SPR_PLANE_ID:
        glReadBuffer(GL_COLOR_ATTACHMENT2);
        glReadPixels(0, 0, W, H, GL_RED_INTEGER, GL_UNSIGNED_INT, out);
        break;
    case SPR_PLANE_COUNT: {
        glReadBuffer(GL_COLOR_ATTACHMENT3);
        glReadPixels(0, 0, W, H, GL_RED, GL_FLOAT, out);
        float *f = out;
        uint32_t *u = out;
        for (size_t i = 0; i < (size_t)W * H; i++) u[i] = (uint32_t)f[i]; /* exact: counts < 2^24 */
        break;
    }
    default: return spr__fail(&b->err, SPR_E_ARG, "gl: unknown plane");
    }
    return gl__check(b, "read");
}

static void gl_destroy(spr_backend *b)
{
    gl_context *c = gl_ctx(b);
    if (c->ctx != EGL_NO_CONTEXT) {
        for (int t = 0; t < c->cap; t++) free_target(&c->targets[t]);
        if (c->arr_color) { glDeleteTextures(1, &c->arr_color); glDeleteTextures(1, &c->arr_depth); }
        glDeleteBuffers(1, &c->instances);
        glDeleteBuffers(1, &c->counters);
        glDeleteVertexArrays(1, &c->vao);
        glDeleteProgram(c->prog_splat);
        glDeleteProgram(c->prog_comp);
    }
    gl__egl_close(c);
    free(c->targets);
    free(c);
}

static void setup_vao(gl_context *c)
{
    glCreateVertexArrays(1, &c->vao);
    glCreateBuffers(1, &c->instances);
    glCreateBuffers(1, &c->counters);
    glNamedBufferData(c->counters, sizeof(GLuint), NULL, GL_DYNAMIC_DRAW);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, c->counters);
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
    for (GLuint a = 0; a < 5; a++) glVertexArrayAttribBinding(vao, a, 0);
}

spr_backend *spr_gl_create(const spr_gl_desc *d, spr_error *err)
{
    spr_gl_desc def;
    if (!d) { spr_gl_defaults(&def); d = &def; }
    gl_context *c = calloc(1, sizeof *c);
    if (!c) { spr__fail(err, SPR_E_NOMEM, "gl: out of memory"); return NULL; }
    c->dpy = EGL_NO_DISPLAY;
    c->ctx = EGL_NO_CONTEXT;
    spr_backend *b = &c->base;
    b->name = "gl";
    b->set_view = gl_set_view;
    b->target_create = gl_target_create;
    b->target_destroy = gl_target_destroy;
    b->clear = gl_clear;
    b->draw_splats = gl_draw;
    b->composite = gl_composite;
    b->read_plane = gl_read_plane;
    b->destroy = gl_destroy;
    if (gl__egl_open(c, d->device, err) || gl__build_programs(c, err)) {
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
