/* gl_gauss.c — the Gaussian splatting references on GL (SPEC §10), every
 * float operation in the shared arithmetic run on the GPU:
 *
 *   preprocess  a fragment program (gl_gauss_pre.frag), one fragment per
 *               Gaussian over shader storage; the records read back for the
 *               host's sorting (core/algo/gauss.c);
 *   raster      a fragment program (gl_gauss_raster.frag), one fragment per
 *               pixel walking its 16×16 tile's list, storing the target's
 *               planes as images (the Gaussian planes are never colour
 *               attachments: llvmpipe has 8, the fragment-written planes
 *               use 6);
 *   draw        gauss-blend: instanced quads over the Gaussians' boxes in the
 *               host's order (gl_splat.vert, gl_gauss_blend.frag), blended
 *               by GL (ONE, ONE_MINUS_SRC_ALPHA) — measured to round as the
 *               reference's spr_blend1 does (PARITY.md, tests/test_gl.c).
 * The first two draw one triangle over an attachment-less framebuffer
 * rather than dispatching compute work: llvmpipe 22.3 runs fragments with
 * denormals flushed to zero (FTZ/DAZ), as the reference's threads do, but
 * compute invocations with denormals kept (measured: 1e-30/1e10 is
 * 1.0e-40 in a compute shader, 0 in a fragment), so a compute program
 * differs from the reference wherever a value falls below 2^-126 (a
 * 10^12-scale scene's opacity compensation, parity --random seed
 * 20261205 scene 481).
 * Records, tile ranges and lists reach the programs through buffer
 * textures (the reason: gl_prelude.glsl), records and lists four values a
 * texel; the preprocessing runs a batch of Gaussians at a time, each batch
 * with buffers of its own within GL_MAX_SHADER_STORAGE_BLOCK_SIZE, its
 * records read back right after its draw.  Measured on Mesa 22.3.6's zink
 * (test gauss_records_in_batches_and_the_limit): read back once after the
 * last batch, every batch's records but the first's were wrong, whether the
 * batches were ranges of one buffer or buffers of their own; llvmpipe was
 * right either way.  So the
 * one limit on a capture's size is the records' texture: 4 ×
 * GL_MAX_TEXTURE_BUFFER_SIZE values, checked before a frame starts
 * (gl__gauss_fits).  Programs are linked on first use.
 */
#include "gl_internal.h"

#include <stdlib.h>
#include <string.h>

/* The forward's list entries a pixel a draw (spr_gauss_pixel_run, one loop iteration each) for a frame whose longest list
 * is longer: then the loop is resumed draw after draw, its state in an image; shorter lists are drawn in one draw. */
#define GL_FWD_STEPS 32768

/* `bytes` of data into buffer *buf (made or grown as needed, to whole 16-byte texels); the shaders only read it. */
static void upload(GLuint *buf, size_t *cap, size_t bytes, const void *data)
{
    gl__buffer_reserve(buf, cap, (bytes + 15) & ~(size_t)15, GL_DYNAMIC_DRAW);
    if (bytes && data) glNamedBufferSubData(*buf, 0, (GLsizeiptr)bytes, data);
}

static size_t max_texels(const gl_context *c)
{
    GLint max = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &max);
    const size_t m = max > 0 ? (size_t)max : 0;
    return c->max_texels && c->max_texels < m ? c->max_texels : m;
}

/* A buffer texture of format fmt (`per` 32-bit values a texel) over the first `values` of buf, on unit. */
static spr_result texture_of(gl_context *c, GLuint *tex, GLenum fmt, int per, GLuint buf, size_t values, GLuint unit, const char *what)
{
    const size_t texels = (values + (size_t)per - 1) / (size_t)per, max = max_texels(c);
    if (texels > max)
        return spr__fail(&c->base.err, SPR_E_TOO_LARGE, "gl: %s of %zu values (%zu texels of %d) exceed GL_MAX_TEXTURE_BUFFER_SIZE (%zu texels)",
                         what, values, texels, per, max);
    if (*tex) glDeleteTextures(1, tex);
    glCreateTextures(GL_TEXTURE_BUFFER, 1, tex);
    glTextureBufferRange(*tex, fmt, buf, 0, (GLsizeiptr)(texels ? texels * (size_t)per * 4 : 16));
    glBindTextureUnit(unit, *tex);
    return SPR_OK;
}

spr_result gl__gauss_fits(spr_backend *b, const spr_fit_desc *d)
{
    gl_context *c = gl_ctx(b);
    if (!d->gauss) return SPR_OK;
    gl__make_current(c);
    const size_t max = max_texels(c), most = 4 * max / SPR_GREC_FLOATS;
    if (d->splats > most)
        return spr__fail(&b->err, SPR_E_TOO_LARGE,
                         "gl: %zu Gaussians exceed what this driver takes, %zu: their records (%d floats each, 4 a texel) must fit one "
                         "buffer texture of GL_MAX_TEXTURE_BUFFER_SIZE (%zu texels)", d->splats, most, SPR_GREC_FLOATS, max);
    return SPR_OK;
}

/* One triangle over an attachment-less framebuffer of w × h pixels (no
 * depth, stencil or blending applies: the programs only store), then the
 * view's viewport again. */
static void draw_bare(gl_context *c, int w, int h)
{
    if (!c->gfbo) glCreateFramebuffers(1, &c->gfbo);
    glNamedFramebufferParameteri(c->gfbo, GL_FRAMEBUFFER_DEFAULT_WIDTH, w);
    glNamedFramebufferParameteri(c->gfbo, GL_FRAMEBUFFER_DEFAULT_HEIGHT, h);
    glBindFramebuffer(GL_FRAMEBUFFER, c->gfbo);
    glViewport(0, 0, w, h);
    glBindVertexArray(c->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glViewport(0, 0, c->base.view.width, c->base.view.height);
}

/* At least 2·batches preprocessing buffers (new ones 0: made on first use). */
static spr_result pre_buffers(gl_context *c, size_t batches)
{
    if (2 * batches <= c->n_gpre) return SPR_OK;
    GLuint *nb = realloc(c->gpre, 2 * batches * sizeof *nb);
    if (nb) c->gpre = nb;
    size_t *nc = nb ? realloc(c->gpre_cap, 2 * batches * sizeof *nc) : NULL;
    if (!nc) return spr__fail(&c->base.err, SPR_E_NOMEM, "gl: out of memory for %zu batches", batches);
    c->gpre_cap = nc;
    for (size_t k = c->n_gpre; k < 2 * batches; k++) c->gpre[k] = 0, c->gpre_cap[k] = 0;
    c->n_gpre = 2 * batches;
    return SPR_OK;
}

/* Gaussians a preprocessing batch: whole rows of `width`, its two buffers (14 and SPR_GREC_FLOATS floats a
 * Gaussian) within GL_MAX_SHADER_STORAGE_BLOCK_SIZE; spr_gl_desc.gauss_batch when smaller. */
static size_t pre_batch(const gl_context *c, size_t width)
{
    GLint maxh = 0;
    GLint64 maxblock = 0;
    glGetIntegerv(GL_MAX_FRAMEBUFFER_HEIGHT, &maxh);
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxblock);
    size_t batch = width * (size_t)maxh;
    while (batch > width && batch * SPR_GREC_FLOATS * sizeof(float) > (size_t)maxblock) batch /= 2;
    return c->gauss_batch && c->gauss_batch < batch ? c->gauss_batch : batch;
}

spr_result gl__gauss_preprocess(spr_backend *b, const spr_gauss_desc *d, float *rec)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    spr_result r = gl__gauss_program(c, GL_GPROG_PRE, &b->err);
    if (r) return r;
    if (d->n == 0) return SPR_OK;
    GLint maxw = 0;
    glGetIntegerv(GL_MAX_FRAMEBUFFER_WIDTH, &maxw);
    const size_t width = maxw < 4096 ? (size_t)maxw : 4096; /* Gaussian base + y·width + x of a batch */
    const size_t batch = pre_batch(c, width), batches = (d->n + batch - 1) / batch;
    if ((r = pre_buffers(c, batches))) return r;
    float *in = malloc((d->n < batch ? d->n : batch) * 14 * sizeof *in);
    if (!in) return spr__fail(&b->err, SPR_E_NOMEM, "gl: out of memory for %zu Gaussians", d->n);
    const GLuint p = c->gprog[GL_GPROG_PRE];
    glUseProgram(p);
    glUniform1fv(glGetUniformLocation(p, "u_g"), SPR_GPRM_COUNT, d->prm);
    glUniform1ui(glGetUniformLocation(p, "u_width"), (GLuint)width);
    glUniform1ui(glGetUniformLocation(p, "u_base"), 0u); /* a batch's buffers start at its first Gaussian */
    for (size_t k = 0; k < batches; k++) {
        const size_t base = k * batch, m = d->n - base < batch ? d->n - base : batch;
        for (size_t j = 0; j < m; j++) { /* the inputs packed: μ, q, σ, o, c (no arithmetic) */
            const size_t i = base + j;
            float *o = in + 14 * j;
            memcpy(o, d->mu + 3 * i, 3 * sizeof *o);
            memcpy(o + 3, d->q + 4 * i, 4 * sizeof *o);
            memcpy(o + 7, d->s + 3 * i, 3 * sizeof *o);
            o[10] = d->opacity[i];
            memcpy(o + 11, d->color + 3 * i, 3 * sizeof *o);
        }
        upload(&c->gpre[2 * k], &c->gpre_cap[2 * k], m * 14 * sizeof *in, in);
        gl__buffer_reserve(&c->gpre[2 * k + 1], &c->gpre_cap[2 * k + 1], m * SPR_GREC_FLOATS * sizeof(float), GL_DYNAMIC_DRAW); /* written */
        glUniform1ui(glGetUniformLocation(p, "u_n"), (GLuint)m);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, c->gpre[2 * k]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, c->gpre[2 * k + 1]);
        draw_bare(c, (int)(m < width ? m : width), (int)((m + width - 1) / width));
        gl__buffer_read(c->gpre[2 * k + 1], 0, m * SPR_GREC_FLOATS * sizeof(float), rec + base * SPR_GREC_FLOATS);
    }
    free(in);
    return gl__check(b, "gauss preprocess");
}

spr_result gl__gauss_raster(spr_backend *b, int target, const spr_gauss_raster_desc *d, spr_draw_stats *st)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    if (b->probe && !c->probe_programs) return gl__probe_refused(c);
    spr_result r = gl__gauss_program(c, GL_GPROG_RASTER, &b->err);
    if (r) return r;
    const int gx = (int)d->prm[SPR_GPRM_GX], gy = (int)d->prm[SPR_GPRM_GY];
    const size_t tiles = (size_t)gx * gy, entries = d->range[tiles];
    upload(&c->gbuf[GL_GBUF_RECTEX], &c->gcap[GL_GBUF_RECTEX], d->n * SPR_GREC_FLOATS * sizeof(float), d->rec);
    upload(&c->gbuf[GL_GBUF_RANGE], &c->gcap[GL_GBUF_RANGE], (tiles + 1) * sizeof(uint32_t), d->range);
    upload(&c->gbuf[GL_GBUF_LIST], &c->gcap[GL_GBUF_LIST], entries * sizeof(uint32_t), d->list);
    uint32_t *counts = malloc((2 * tiles + 1) * sizeof *counts);
    if (!counts) return spr__fail(&b->err, SPR_E_NOMEM, "gl: out of memory for %zu tiles", tiles);
    /* a list longer than a fragment may walk in one draw: the loop resumed, its state kept between draws */
    uint32_t L = 0;
    for (size_t t = 0; t < tiles; t++)
        if (d->range[t + 1] - d->range[t] > L) L = d->range[t + 1] - d->range[t];
    const int steps = c->gauss_steps > 0 ? c->gauss_steps : GL_FWD_STEPS;
    const int resume = L > (uint32_t)(steps < GL_FWD_STEPS ? steps : GL_FWD_STEPS); /* a list past the budget: never one draw */
    const int W = (int)d->prm[SPR_GPRM_W], H = (int)d->prm[SPR_GPRM_H];
    if (resume) {
        const size_t bytes = (size_t)W * H * SPR_GFS_FLOATS * sizeof(float);
        gl__buffer_reserve(&c->gbuf[GL_GBUF_GFS], &c->gcap[GL_GBUF_GFS], bytes, GL_DYNAMIC_DRAW);
        if ((r = texture_of(c, &c->gtex[9], GL_RGBA32F, 4, c->gbuf[GL_GBUF_GFS], (size_t)W * H * SPR_GFS_FLOATS, 19, "the pixels' loop state"))) {
            free(counts);
            return r;
        }
        glBindImageTexture(6, c->gtex[9], 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    }
    /* per tile the Gaussians visited and blended, then the pixels not done (a draw of a resumed loop) */
    gl__buffer_reserve(&c->gbuf[GL_GBUF_COUNT], &c->gcap[GL_GBUF_COUNT], (2 * tiles + 1) * sizeof *counts, GL_DYNAMIC_DRAW);
    gl__buffer_fill(c->gbuf[GL_GBUF_COUNT], 0, (2 * tiles + 1) * sizeof *counts, 0);
    if ((r = texture_of(c, &c->gtex[0], GL_RGBA32F, 4, c->gbuf[GL_GBUF_RECTEX], d->n * SPR_GREC_FLOATS, 10, "Gaussian records")) ||
        (r = texture_of(c, &c->gtex[1], GL_R32UI, 1, c->gbuf[GL_GBUF_RANGE], tiles + 1, 11, "tile ranges")) ||
        (r = texture_of(c, &c->gtex[2], GL_RGBA32UI, 4, c->gbuf[GL_GBUF_LIST], entries, 12, "tile lists"))) {
        free(counts);
        return r;
    }
    const unsigned planes = b->target_planes[target];
    const int two = d->prm[SPR_GPRM_MODE] == SPR_GMODE_2D;
    const spr_plane depth_plane = two ? SPR_PLANE_SURFDEPTH : SPR_PLANE_INVDEPTH;
    static const struct { spr_plane p; GLenum fmt; } img[5] = {
        {SPR_PLANE_COLOR, GL_RGBA32F}, {SPR_PLANE_TRANS, GL_R32F}, {SPR_PLANE_CONTRIB, GL_R32UI}, {SPR_PLANE__COUNT, GL_R32F}, {SPR_PLANE_NORMAL, GL_RGBA32F}};
    int has = 0;
    for (int k = 0; k < 5; k++) {
        const spr_plane p = k == 3 ? depth_plane : img[k].p;
        const int on = (planes & SPR_PLANE_BIT(p)) != 0 && (k != 4 || two);
        if (k) has |= on << (k - 1);
        if (on || k == 0) glBindImageTexture((GLuint)k, c->pool[p], 0, GL_TRUE, 0, GL_WRITE_ONLY, img[k].fmt);
    }
    const GLuint p = c->gprog[GL_GPROG_RASTER];
    glUseProgram(p);
    glUniform1fv(glGetUniformLocation(p, "u_g"), SPR_GPRM_COUNT, d->prm);
    glUniform1fv(glGetUniformLocation(p, "u_bg"), 3, d->background);
    glUniform1i(glGetUniformLocation(p, "u_layer"), target);
    glUniform1i(glGetUniformLocation(p, "u_has"), has);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, c->gbuf[GL_GBUF_COUNT]);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    glUniform1i(glGetUniformLocation(p, "u_steps"), resume ? steps : 0);
    gl__probe_begin(c);
    for (int round = 0;; round++) {
        glUniform1i(glGetUniformLocation(p, "u_round"), round);
        draw_bare(c, W, H);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                        GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
        if (resume) glFinish(); /* zink: stores read back through their buffer need it (gl__gauss_backward) */
        uint32_t left = 0;
        gl__buffer_read(c->gbuf[GL_GBUF_COUNT], 2 * tiles * sizeof *counts, sizeof left, &left);
        if (!left) break;
        if (!resume) { /* cannot be: every list fits a draw; said rather than drawn wrong */
            free(counts);
            return spr__fail(&b->err, SPR_E_BACKEND, "gl: gauss raster: %u pixels' loops did not finish in one draw (lists up to %u entries)", left, L);
        }
        gl__buffer_fill(c->gbuf[GL_GBUF_COUNT], 2 * tiles * sizeof *counts, sizeof left, 0);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    }
    if (b->probe && (r = gl__probe_end(c, b->probe->n_frags))) {
        free(counts);
        return r;
    }
    gl__buffer_read(c->gbuf[GL_GBUF_COUNT], 0, 2 * tiles * sizeof *counts, counts);
    st->splats = d->n;
    for (size_t t = 0; t < tiles; t++) st->generated += counts[2 * t], st->passed += counts[2 * t + 1];
    free(counts);
    return gl__check(b, "gauss raster");
}

spr_result gl__gauss_draw(spr_backend *b, int target, const spr_gauss_draw_desc *d, spr_draw_stats *st)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    if (b->probe && !c->probe_programs) return gl__probe_refused(c);
    spr_result r = gl__gauss_program(c, GL_GPROG_BLEND, &b->err);
    if (r) return r;
    st->splats = d->count;
    const int H = b->view.height;
    gl_instance *inst = malloc((d->count ? d->count : 1) * sizeof *inst);
    if (!inst) return spr__fail(&b->err, SPR_E_NOMEM, "gl: out of memory for %zu instances", d->count);
    size_t m = 0;
    for (size_t e = 0; e < d->count; e++) { /* the order; a box is pixel-index rows, the quad plane rows */
        const float *R = d->rec + (size_t)d->order[e] * SPR_GREC_FLOATS;
        const int i0 = (int)R[SPR_GREC_BOX], j0 = (int)R[SPR_GREC_BOX + 1], i1 = (int)R[SPR_GREC_BOX + 2], j1 = (int)R[SPR_GREC_BOX + 3];
        if (i1 < i0 || j1 < j0) continue;
        gl_instance *g = &inst[m++];
        memset(g, 0, sizeof *g);
        g->rect[0] = i0, g->rect[1] = H - 1 - j1, g->rect[2] = i1, g->rect[3] = H - 1 - j0;
        g->pr[0] = R[SPR_GREC_M], g->pr[1] = R[SPR_GREC_M + 1], g->pr[2] = R[SPR_GREC_CONIC], g->pr[3] = R[SPR_GREC_CONIC + 1];
        g->na[0] = R[SPR_GREC_CONIC + 2], g->na[1] = R[SPR_GREC_OPACITY];
        for (int k = 0; k < 3; k++) g->c[k] = R[SPR_GREC_COLOR + k];
        g->id = d->order[e];
        g->seq = (uint32_t)e;
    }
    gl__upload_instances(c, inst, m);
    free(inst);
    glBindFramebuffer(GL_FRAMEBUFFER, c->targets[target].fbo);
    const GLuint p = c->gprog[GL_GPROG_BLEND];
    glUseProgram(p);
    glUniform2f(glGetUniformLocation(p, "u_size"), (float)b->view.width, (float)H);
    glUniform1fv(glGetUniformLocation(p, "u_g"), SPR_GPRM_COUNT, d->prm);
    gl__pass_state(&d->state);
    gl__draw_instances(c, m, st);
    st->splats = d->count;
    return gl__check(b, "gauss draw");
}

/* The backward's steps a tile a draw (spr_gauss_tile_bwd, one loop iteration each: its inner loops have constant trip
 * counts, unrolled): half of llvmpipe's 65,535 loop iterations an invocation, the rest left to the loops around them.
 * A walk that gallivm cuts anyway resumes from its state (test loops_resume_across_draws: a million steps a draw). */
#define GL_BWD_STEPS 32768
/* The backward's tiles a batch at most: their walks' state, SPR_GBS_FLOATS values (30 KB) a tile, 31 MB */
#define GL_BWD_TILES 1024

/* gauss3d's backward (SPEC 10.10; sw__gauss_backward is the same on the CPU): the tiles in batches whose list
 * entries' partials fit one buffer texture and spr_gauss_bwd_desc.batch; per batch the partials zeroed, draws of one
 * fragment per tile, each running a run of each tile's pixels (gl_gauss_bwd_tile.frag: a tile's pixels in the CPU's
 * order; runs of 16 down to 1 by the batch's longest list, within llvmpipe's loop budget), then one fragment per Gaussian adds its entries' partials of
 * the batch to its sums in entry order (gl_gauss_bwd_gauss.frag, stage 0); after the last batch the chain, one
 * fragment per Gaussian in the preprocessing's batches, each batch's values read back right after its draw (the zink
 * finding of gl__gauss_preprocess).  Partials and sums are images of four floats a texel, SPR_GPART_FLOATS (16) a
 * list entry or Gaussian: no texel holds two tiles' entries, so no two fragments write one texel. */
spr_result gl__gauss_backward(spr_backend *b, const spr_gauss_bwd_desc *d, float *sums, float *out)
{
    gl_context *c = gl_ctx(b);
    gl__make_current(c);
    spr_result r;
    if ((r = gl__gauss_program(c, GL_GPROG_BWD_TILE, &b->err)) || (r = gl__gauss_program(c, GL_GPROG_BWD_GAUSS, &b->err))) return r;
    const int gx = (int)d->prm[SPR_GPRM_GX], nt = gx * (int)d->prm[SPR_GPRM_GY], W = b->view.width, H = b->view.height;
    const size_t n = d->n, entries = d->range[nt], per = SPR_GPART_FLOATS / 4;
    size_t cap = max_texels(c) / per;
    if (d->batch && d->batch < cap) cap = d->batch;
    upload(&c->gbuf[GL_GBUF_RECTEX], &c->gcap[GL_GBUF_RECTEX], n * SPR_GREC_FLOATS * sizeof(float), d->rec);
    upload(&c->gbuf[GL_GBUF_RANGE], &c->gcap[GL_GBUF_RANGE], ((size_t)nt + 1) * sizeof(uint32_t), d->range);
    upload(&c->gbuf[GL_GBUF_LIST], &c->gcap[GL_GBUF_LIST], entries * sizeof(uint32_t), d->list);
    upload(&c->gbuf[GL_GBUF_UP], &c->gcap[GL_GBUF_UP], (size_t)W * H * 5 * sizeof(float), d->up);
    upload(&c->gbuf[GL_GBUF_CSR], &c->gcap[GL_GBUF_CSR], entries * sizeof(uint32_t), d->csr);
    upload(&c->gbuf[GL_GBUF_CSR_START], &c->gcap[GL_GBUF_CSR_START], (n + 1) * sizeof(uint32_t), d->csr_start);
    const size_t most = spr_gauss_bwd_batch_most(d->range, nt, cap);
    gl__buffer_reserve(&c->gbuf[GL_GBUF_PART], &c->gcap[GL_GBUF_PART], (most ? most : 1) * SPR_GPART_FLOATS * sizeof(float), GL_DYNAMIC_DRAW);
    gl__buffer_reserve(&c->gbuf[GL_GBUF_SUMS], &c->gcap[GL_GBUF_SUMS], (n ? n : 1) * SPR_GPART_FLOATS * sizeof(float), GL_DYNAMIC_DRAW);
    gl__buffer_fill(c->gbuf[GL_GBUF_SUMS], 0, (n ? n : 1) * SPR_GPART_FLOATS * sizeof(float), 0);
    if ((r = texture_of(c, &c->gtex[0], GL_RGBA32F, 4, c->gbuf[GL_GBUF_RECTEX], n * SPR_GREC_FLOATS, 10, "Gaussian records")) ||
        (r = texture_of(c, &c->gtex[1], GL_R32UI, 1, c->gbuf[GL_GBUF_RANGE], (size_t)nt + 1, 11, "tile ranges")) ||
        (r = texture_of(c, &c->gtex[2], GL_RGBA32UI, 4, c->gbuf[GL_GBUF_LIST], entries, 12, "tile lists")) ||
        (r = texture_of(c, &c->gtex[3], GL_R32F, 1, c->gbuf[GL_GBUF_UP], (size_t)W * H * 5, 13, "the upstream gradient")) ||
        (r = texture_of(c, &c->gtex[4], GL_R32UI, 1, c->gbuf[GL_GBUF_CSR], entries, 14, "the Gaussians' list entries")) ||
        (r = texture_of(c, &c->gtex[5], GL_R32UI, 1, c->gbuf[GL_GBUF_CSR_START], n + 1, 15, "the Gaussians' first entries")) ||
        (r = texture_of(c, &c->gtex[6], GL_RGBA32F, 4, c->gbuf[GL_GBUF_PART], (most ? most : 1) * SPR_GPART_FLOATS, 16, "the entries' partials")) ||
        (r = texture_of(c, &c->gtex[7], GL_RGBA32F, 4, c->gbuf[GL_GBUF_SUMS], (n ? n : 1) * SPR_GPART_FLOATS, 17, "the Gaussians' sums")))
        return r;
    glBindImageTexture(5, c->gtex[6], 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(6, c->gtex[7], 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    GLint maxw = 0;
    glGetIntegerv(GL_MAX_FRAMEBUFFER_WIDTH, &maxw);
    const size_t width = maxw < 4096 ? (size_t)maxw : 4096;
    const GLuint pt = c->gprog[GL_GPROG_BWD_TILE], pg = c->gprog[GL_GPROG_BWD_GAUSS];
    const int steps = c->gauss_steps > 0 ? c->gauss_steps : GL_BWD_STEPS;
    uint32_t *done = malloc(((size_t)nt + 1) * sizeof *done);
    if (!done) return spr__fail(&b->err, SPR_E_NOMEM, "gl: out of memory for %d tiles", nt);
    glUseProgram(pt);
    glUniform1fv(glGetUniformLocation(pt, "u_g"), SPR_GPRM_COUNT, d->prm);
    glUniform1fv(glGetUniformLocation(pt, "u_bg"), 3, d->background);
    glUseProgram(pg);
    glUniform1fv(glGetUniformLocation(pg, "u_g"), SPR_GPRM_COUNT, d->prm);
    glUniform1ui(glGetUniformLocation(pg, "u_n"), (GLuint)n);
    glUniform1ui(glGetUniformLocation(pg, "u_base"), 0u);
    glUniform1ui(glGetUniformLocation(pg, "u_width"), (GLuint)width);
    glUniform1i(glGetUniformLocation(pg, "u_stage"), 0);
    for (int t0 = 0, t1; t0 < nt && n; t0 = t1) {
        t1 = spr_gauss_bwd_batch_end(d->range, nt, t0, cap);
        if (t1 - t0 > GL_BWD_TILES) t1 = t0 + GL_BWD_TILES; /* the walks' state: SPR_GBS_FLOATS values a tile */
        const uint32_t base = d->range[t0], end = d->range[t1];
        if (end == base) continue;
        gl__buffer_fill(c->gbuf[GL_GBUF_PART], 0, (size_t)(end - base) * SPR_GPART_FLOATS * sizeof(float), 0);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        const size_t m = (size_t)(t1 - t0);
        /* each tile's walk state, fresh (its first pixel, not begun), and its done flag */
        gl__buffer_reserve(&c->gbuf[GL_GBUF_GBS], &c->gcap[GL_GBUF_GBS], m * SPR_GBS_FLOATS * sizeof(uint32_t), GL_DYNAMIC_DRAW);
        gl__buffer_fill(c->gbuf[GL_GBUF_GBS], 0, m * SPR_GBS_FLOATS * sizeof(uint32_t), 0);
        gl__buffer_reserve(&c->gbuf[GL_GBUF_DONE], &c->gcap[GL_GBUF_DONE], m * sizeof(uint32_t), GL_DYNAMIC_DRAW);
        if ((r = texture_of(c, &c->gtex[8], GL_R32UI, 1, c->gbuf[GL_GBUF_GBS], m * SPR_GBS_FLOATS, 18, "the tiles' walk state"))) {
            free(done);
            return r;
        }
        glBindImageTexture(7, c->gtex[8], 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, c->gbuf[GL_GBUF_DONE]);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        glUseProgram(pt);
        glUniform1i(glGetUniformLocation(pt, "u_t0"), t0);
        glUniform1i(glGetUniformLocation(pt, "u_t1"), t1);
        glUniform1i(glGetUniformLocation(pt, "u_gpart_base"), (GLint)base);
        glUniform1i(glGetUniformLocation(pt, "u_budget"), steps);
        /* the batch's tiles as a near-square block of fragments: llvmpipe shades 4×4 blocks, so one row of fragments
         * would leave three quarters of its lanes idle */
        size_t tw = 4;
        while (tw * tw < m && tw < width) tw += 4;
        glUniform1i(glGetUniformLocation(pt, "u_width"), (GLint)tw);
        /* draws of at most `steps` steps a tile until every tile is done (each draw advances every tile that is
         * not: the loop ends) */
        for (int more = 1; more;) {
            draw_bare(c, (int)(m < tw ? m : tw), (int)((m + tw - 1) / tw));
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
            glFinish(); /* zink: stores read back through their buffer need it (below) */
            gl__buffer_read(c->gbuf[GL_GBUF_DONE], 0, m * sizeof(uint32_t), done);
            more = 0;
            for (size_t k = 0; k < m; k++) {
                if (done[k] >> 1) { /* bit 0 done, the rest SPR_GBS_OVER */
                    free(done);
                    return spr_gauss_bwd_over(&b->err, "gl", gx, t0 + (int)k, (int)(done[k] >> 1) - 1);
                }
                if (!(done[k] & 1)) more = 1;
            }
        }
        glUseProgram(pg);
        glUniform1i(glGetUniformLocation(pg, "u_gpart_base"), (GLint)base);
        glUniform1i(glGetUniformLocation(pg, "u_ebase"), (GLint)base);
        glUniform1i(glGetUniformLocation(pg, "u_eend"), (GLint)end);
        draw_bare(c, (int)(n < width ? n : width), (int)((n + width - 1) / width));
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    free(done);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    /* zink (Mesa 22.3.6): the sums, written by image stores through a buffer texture, read back through their buffer
     * came back zero (all 256 Gaussians of a capture, from a context's third backward on, not every run) after the
     * barrier alone; glFinish first (test gradients_bit_exact_and_batched, CTest gl_zink_gradients) */
    glFinish();
    gl__buffer_read(c->gbuf[GL_GBUF_SUMS], 0, n * SPR_GPART_FLOATS * sizeof(float), sums);
    /* the chain, in the preprocessing's batches */
    const size_t batch = pre_batch(c, width);
    float *in = malloc((n < batch ? (n ? n : 1) : batch) * 14 * sizeof *in);
    if (!in) return spr__fail(&b->err, SPR_E_NOMEM, "gl: out of memory for %zu Gaussians", n);
    glUseProgram(pg);
    glUniform1i(glGetUniformLocation(pg, "u_stage"), 1);
    for (size_t base = 0; base < n; base += batch) {
        const size_t m = n - base < batch ? n - base : batch;
        for (size_t j = 0; j < m; j++) { /* μ, q, σ packed as the preprocessing's (no arithmetic) */
            const size_t i = base + j;
            float *o = in + 14 * j;
            memset(o, 0, 14 * sizeof *o);
            memcpy(o, d->mu + 3 * i, 3 * sizeof *o);
            memcpy(o + 3, d->q + 4 * i, 4 * sizeof *o);
            memcpy(o + 7, d->s + 3 * i, 3 * sizeof *o);
        }
        upload(&c->gbuf[GL_GBUF_GIN], &c->gcap[GL_GBUF_GIN], m * 14 * sizeof *in, in);
        gl__buffer_reserve(&c->gbuf[GL_GBUF_GOUT], &c->gcap[GL_GBUF_GOUT], m * SPR_GOUT_FLOATS * sizeof(float), GL_DYNAMIC_DRAW);
        glUniform1ui(glGetUniformLocation(pg, "u_base"), (GLuint)base);
        glUniform1ui(glGetUniformLocation(pg, "u_n"), (GLuint)(base + m));
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, c->gbuf[GL_GBUF_GIN]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, c->gbuf[GL_GBUF_GOUT]);
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
        draw_bare(c, (int)(m < width ? m : width), (int)((m + width - 1) / width));
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
        gl__buffer_read(c->gbuf[GL_GBUF_GOUT], 0, m * SPR_GOUT_FLOATS * sizeof(float), out + base * SPR_GOUT_FLOATS);
    }
    free(in);
    return gl__check(b, "gauss backward");
}

void gl__gauss_free(gl_context *c)
{
    glDeleteBuffers(GL_GBUF__COUNT, c->gbuf);
    if (c->n_gpre) glDeleteBuffers((GLsizei)c->n_gpre, c->gpre);
    free(c->gpre);
    free(c->gpre_cap);
    c->gpre = NULL, c->gpre_cap = NULL, c->n_gpre = 0;
    glDeleteTextures(10, c->gtex);
    if (c->gfbo) glDeleteFramebuffers(1, &c->gfbo);
    c->gfbo = 0;
    for (int k = 0; k < GL_GPROG__COUNT; k++)
        if (c->gprog[k]) glDeleteProgram(c->gprog[k]);
    memset(c->gbuf, 0, sizeof c->gbuf);
    memset(c->gcap, 0, sizeof c->gcap);
    memset(c->gtex, 0, sizeof c->gtex);
    memset(c->gprog, 0, sizeof c->gprog);
}
