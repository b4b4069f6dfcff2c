/* gl_rect.c — rectangle draws (domain primitives, SPEC §7.7) on GL.
 *
 * A set of rectangles (spr_rects) goes up once, kept by its serial: the
 * texels, float records, integer records and neighbour bits as shader
 * storage buffers read by gl_rect.frag and by the prefix op.  Each draw
 * sends one instance per rectangle (its pixel rectangle from
 * spr_rect_pixel_rect and its index) through gl_splat.vert.
 *
 * Hardware sampling (Tier B) uses a padded atlas: every texture in its own
 * block with a one-texel border repeating its edge, so GL's bilinear
 * filter at the block's edge reads what clamp-to-edge would.
 *
 * List draws: per-pixel linked lists with GL 4.3 shader storage — a node
 * counter (atomicAdd), each pixel's head (atomicExchange), nodes of
 * (t, rectangle, next) and the colour.  When the nodes do not fit, the
 * buffers grow to the count the draw reached and the draw runs again, so
 * no fragment is lost.  The prefix op sorts each list by (t, rectangle),
 * so the order GL inserted them in does not matter.
 */
#include "gl_internal.h"

#include <stdlib.h>
#include <string.h>

void gl__rects_free(gl_context *c)
{
    glDeleteBuffers(4, c->rect_buf);
    memset(c->rect_buf, 0, sizeof c->rect_buf);
    if (c->atlas) glDeleteTextures(1, &c->atlas);
    if (c->atlas_org) glDeleteBuffers(1, &c->atlas_org);
    if (c->list_meta) glDeleteBuffers(1, &c->list_meta);
    if (c->list_src) glDeleteBuffers(1, &c->list_src);
    if (c->list_head) glDeleteBuffers(1, &c->list_head);
    glDeleteTextures(4, c->list_tex);
    memset(c->list_tex, 0, sizeof c->list_tex);
    c->atlas = c->atlas_org = c->list_meta = c->list_src = c->list_head = 0;
    c->list_head_cap = 0;
    c->rects_serial = 0;
    c->list_cap = 0;
    c->list_target = -1;
}

/* A new rectangle set's data: read-only to the shaders, given its own storage. */
static void buffer_data(GLuint *buf, size_t bytes, const void *data)
{
    gl__buffer_alloc(buf, bytes, GL_STATIC_DRAW);
    if (bytes && data) glNamedBufferSubData(*buf, 0, (GLsizeiptr)bytes, data);
}

/* The set's buffers, when it is not the one uploaded last. */
static void upload(gl_context *c, const spr_rects *r)
{
    if (c->rects_serial == r->serial && r->serial) return;
    buffer_data(&c->rect_buf[0], r->n_texels * 4 * sizeof(float), r->texels);
    buffer_data(&c->rect_buf[1], r->n * SPR_RECT_FLOATS * sizeof(float), r->f);
    buffer_data(&c->rect_buf[2], r->n * SPR_RECTI_COUNT * sizeof(uint32_t), r->i);
    buffer_data(&c->rect_buf[3], r->n * spr_rects_words(r->n) * sizeof(uint32_t), r->nbr);
    if (c->atlas) glDeleteTextures(1, &c->atlas);
    c->atlas = 0;
    c->rects_serial = r->serial;
    c->rects_n = r->n;
}

/* The Tier B atlas (spr_rects_atlas), blocks' corners in shader storage. */
static spr_result make_atlas(gl_context *c, const spr_rects *r)
{
    if (c->atlas) return SPR_OK;
    int32_t *org = malloc((r->n ? r->n : 1) * 2 * sizeof *org);
    if (!org) return spr__fail(&c->base.err, SPR_E_NOMEM, "gl: out of memory for the atlas");
    float *img = NULL;
    int W, H;
    GLint maxs = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxs);
    spr_result res = spr_rects_atlas(r, maxs < 4096 ? maxs : 4096, &img, &W, &H, org, &c->base.err);
    if (!res && (W > maxs || H > maxs))
        res = spr__fail(&c->base.err, SPR_E_TOO_LARGE, "gl: a %dx%d texture atlas exceeds GL_MAX_TEXTURE_SIZE %d", W, H, maxs);
    if (!res) {
        glCreateTextures(GL_TEXTURE_2D, 1, &c->atlas);
        glTextureStorage2D(c->atlas, 1, GL_RGBA32F, W, H);
        glTextureSubImage2D(c->atlas, 0, 0, 0, W, H, GL_RGBA, GL_FLOAT, img);
        glTextureParameteri(c->atlas, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(c->atlas, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(c->atlas, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(c->atlas, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        buffer_data(&c->atlas_org, r->n * 2 * sizeof *org, org);
        c->atlas_w = W;
        c->atlas_h = H;
        res = gl__check(&c->base, "atlas");
    }
    free(img);
    free(org);
    return res;
}

/* Empty lists with room for cap nodes. */
static void reset_lists(gl_context *c, size_t cap)
{
    const size_t np = (size_t)c->base.view.width * c->base.view.height;
    if (cap > c->list_cap || !c->list_meta) {
        gl__buffer_alloc(&c->list_meta, 16 + cap * 16, GL_DYNAMIC_DRAW);
        gl__buffer_alloc(&c->list_src, cap * 16, GL_DYNAMIC_DRAW);
        c->list_cap = cap;
    }
    gl__buffer_reserve(&c->list_head, &c->list_head_cap, np * sizeof(uint32_t), GL_DYNAMIC_DRAW);
    gl__buffer_fill(c->list_head, 0, np * sizeof(uint32_t), 0xffffffffu); /* every list empty */
    gl__buffer_fill(c->list_meta, 0, 4, 0);                               /* nodes used */
    gl__buffer_fill(c->list_meta, 4, 4, (uint32_t)(c->list_cap > 0xffffffffu ? 0xffffffffu : c->list_cap));
}

spr_result gl__draw_rects(spr_backend *b, int target, const spr_rect_draw_desc *d, spr_draw_stats *st)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    const spr_view *v = &b->view;
    const spr_rects *r = d->rects;
    const size_t n = d->indices ? d->count : r->n;
    st->splats = n;
    if (b->probe && !c->probe_programs) return gl__probe_refused(c);
    upload(c, r);
    spr_result res;
    if (d->sampling == SPR_SAMPLE_HARDWARE && (res = make_atlas(c, r))) return res;
    gl_instance *inst = malloc((n ? n : 1) * sizeof *inst);
    if (!inst) return spr__fail(&b->err, SPR_E_NOMEM, "gl: out of memory for %zu instances", n);
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        const uint32_t k = d->indices ? d->indices[i] : (uint32_t)i;
        int x0, y0, x1, y1;
        if (!spr_rect_pixel_rect(v, r->f + (size_t)k * SPR_RECT_FLOATS, &x0, &y0, &x1, &y1)) continue;
        memset(&inst[m], 0, sizeof inst[m]);
        inst[m].rect[0] = x0; inst[m].rect[1] = y0; inst[m].rect[2] = x1; inst[m].rect[3] = y1;
        inst[m].id = k;
        inst[m].seq = (uint32_t)i;
        m++;
    }
    gl__upload_instances(c, inst, m);
    free(inst);

    glBindFramebuffer(GL_FRAMEBUFFER, c->targets[target].fbo);
    glUseProgram(c->prog_rect);
    const GLint *u = c->ru;
    glUniform1fv(u[GL_RU_M], 16, v->M);
    glUniform2f(u[GL_RU_SIZE], (float)v->width, (float)v->height);
    glUniform1f(u[GL_RU_SX], v->ndc_sx);
    glUniform1f(u[GL_RU_SY], v->ndc_sy);
    glUniform1f(u[GL_RU_EPS], d->state.eps_t);
    glUniform1f(u[GL_RU_AREF], d->alpha_ref);
    glUniform1i(u[GL_RU_DEPTH], (int)d->state.depth_value);
    glUniform1i(u[GL_RU_OUTPUT], (int)d->output);
    glUniform1i(u[GL_RU_SAMPLING], (int)d->sampling);
    glUniform1i(u[GL_RU_LIST], d->list != 0);
    glUniform1i(u[GL_RU_LISTW], v->width);
    glUniform2f(u[GL_RU_ATLAS], (float)c->atlas_w, (float)c->atlas_h);
    for (int k = 0; k < 3; k++) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)k, c->rect_buf[k]); /* texels, records */
    if (d->sampling == SPR_SAMPLE_HARDWARE) {
        glBindTextureUnit(5, c->atlas);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, c->atlas_org);
    }
    if (!d->list) {
        gl__pass_state(&d->state);
        gl__draw_instances(c, m, st);
        return gl__check(b, "rects");
    }
    /* a list draw: no plane written, no depth test; grow and redraw until every node fits */
    spr_pass_state none;
    spr_pass_state_defaults(&none);
    none.depth_func = SPR_FUNC_ALWAYS;
    none.write_mask = 0;
    gl__pass_state(&none);
    size_t cap = c->list_cap ? c->list_cap : (size_t)v->width * v->height * 4;
    for (;;) {
        reset_lists(c, cap);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, c->list_meta);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, c->list_src);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, c->list_head);
        gl__draw_instances(c, m, st);
        uint32_t used = 0;
        gl__buffer_read(c->list_meta, 0, sizeof used, &used);
        if ((res = gl__check(b, "list draw"))) return res;
        if (used <= c->list_cap) break;
        if (used >= 0x7fffffffu / 16) return spr__fail(&b->err, SPR_E_TOO_LARGE, "gl: %u list fragments in one draw", used);
        cap = used;
    }
    st->passed = st->generated;
    c->list_target = target;
    return SPR_OK;
}

/* A buffer texture of `fmt` over bytes [off, off + size) of buf on unit. */
static void buffer_texture(GLuint *tex, GLenum fmt, GLuint buf, size_t off, size_t size, GLuint unit)
{
    if (*tex) glDeleteTextures(1, tex);
    glCreateTextures(GL_TEXTURE_BUFFER, 1, tex);
    glTextureBufferRange(*tex, fmt, buf, (GLintptr)off, (GLsizeiptr)size);
    glBindTextureUnit(unit, *tex);
}

spr_result gl__bind_lists(gl_context *c, const spr_composite_desc *cd)
{
    if (cd->inputs[0] != c->list_target || !c->list_head)
        return spr__fail(&c->base.err, SPR_E_ARG, "gl: prefix: target %d has no fragment lists", cd->inputs[0]);
    upload(c, cd->rects);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    const size_t np = (size_t)c->base.view.width * c->base.view.height, cap = c->list_cap ? c->list_cap : 1;
    buffer_texture(&c->list_tex[0], GL_RGBA32UI, c->list_meta, 16, cap * 16, 6);
    buffer_texture(&c->list_tex[1], GL_RGBA32F, c->list_src, 0, cap * 16, 7);
    buffer_texture(&c->list_tex[2], GL_R32UI, c->list_head, 0, np * 4, 8);
    const size_t nb = c->rects_n * spr_rects_words(c->rects_n) * 4;
    buffer_texture(&c->list_tex[3], GL_R32UI, c->rect_buf[3], 0, nb ? nb : 16, 9);
    return gl__check(&c->base, "lists");
}
