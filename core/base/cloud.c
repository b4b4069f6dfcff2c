/* cloud.c — allocation, validation and bounds of splat clouds. */
#include "spr_cloud.h"
#include "spr_util.h"
#include <omp.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

spr_result spr_cloud_alloc(spr_cloud *c, size_t n)
{
    memset(c, 0, sizeof *c);
    if (n > SPR_MAX_SPLATS) return SPR_E_TOO_LARGE;
    size_t m = n ? n : 1;
    c->pos = malloc(3 * m * sizeof(float));
    c->nrm = malloc(3 * m * sizeof(float));
    c->radius = malloc(m * sizeof(float));
    c->color = malloc(3 * m * sizeof(float));
    c->alpha = malloc(m * sizeof(float));
    if (!c->pos || !c->nrm || !c->radius || !c->color || !c->alpha) {
        spr_cloud_free(c);
        return SPR_E_NOMEM;
    }
    c->n = n;
    for (size_t i = 0; i < n; i++) {
        c->pos[3 * i] = c->pos[3 * i + 1] = c->pos[3 * i + 2] = 0.0f;
        c->nrm[3 * i] = c->nrm[3 * i + 1] = 0.0f;
        c->nrm[3 * i + 2] = 1.0f;
        c->color[3 * i] = c->color[3 * i + 1] = c->color[3 * i + 2] = 0.8f;
        c->radius[i] = 0.0f;
        c->alpha[i] = 1.0f;
    }
    return SPR_OK;
}

void spr_cloud_free(spr_cloud *c)
{
    free(c->pos);
    free(c->nrm);
    free(c->radius);
    free(c->color);
    free(c->alpha);
    memset(c, 0, sizeof *c);
}

spr_result spr__normalize3(float *n)
{
    double x = n[0], y = n[1], z = n[2];
    double l = sqrt(x * x + y * y + z * z);
    if (!(l > 0.0) || !isfinite(l)) return SPR_E_VALUE;
    n[0] = (float)(x / l);
    n[1] = (float)(y / l);
    n[2] = (float)(z / l);
    return SPR_OK;
}

spr_result spr_cloud_validate(const spr_cloud *c, const char *what, spr_error *err)
{
    return spr__cloud_validate_from(c, what, 0, err);
}

spr_result spr__cloud_validate_from(const spr_cloud *c, const char *what, size_t first, spr_error *err)
{
    for (size_t i = 0; i < c->n; i++) {
        const float *p = c->pos + 3 * i, *nv = c->nrm + 3 * i, *col = c->color + 3 * i;
        for (int k = 0; k < 3; k++) {
            if (!isfinite(p[k]))
                return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: non-finite coordinate %c", what, first + i, "xyz"[k]);
            if (!isfinite(nv[k]))
                return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: non-finite normal", what, first + i);
            if (!(col[k] >= 0.0f && col[k] <= 1.0f))
                return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: colour outside [0,1]", what, first + i);
        }
        double l2 = (double)nv[0] * nv[0] + (double)nv[1] * nv[1] + (double)nv[2] * nv[2];
        if (fabs(l2 - 1.0) > 1e-5)
            return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: normal is not unit length", what, first + i);
        if (!isfinite(c->radius[i]) || !(c->radius[i] > 0.0f))
            return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: radius %g is not positive and finite", what, first + i,
                             (double)c->radius[i]);
        if (!(c->alpha[i] >= 0.0f && c->alpha[i] <= 1.0f))
            return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: opacity outside [0,1]", what, first + i);
    }
    return SPR_OK;
}

void spr_bounds_begin(spr_bounds_acc *a)
{
    for (int k = 0; k < 3; k++) { a->b.lo[k] = INFINITY; a->b.hi[k] = -INFINITY; }
    a->b.max_radius = 0.0;
    a->b.min_radius = INFINITY;
    a->b.mean_radius = 0.0;
    a->sum = 0.0;
    a->n = 0;
}

void spr_bounds_add(spr_bounds_acc *a, const spr_cloud *c)
{
    spr_bounds *b = &a->b;
    double sum = a->sum;
    for (size_t i = 0; i < c->n; i++) {
        for (int k = 0; k < 3; k++) {
            double v = c->pos[3 * i + k];
            if (v < b->lo[k]) b->lo[k] = v;
            if (v > b->hi[k]) b->hi[k] = v;
        }
        double r = c->radius[i];
        if (r > b->max_radius) b->max_radius = r;
        if (r < b->min_radius) b->min_radius = r;
        sum += r;
    }
    a->sum = sum;
    a->n += c->n;
}

void spr_bounds_end(const spr_bounds_acc *a, spr_bounds *b)
{
    *b = a->b;
    if (!a->n) {
        for (int k = 0; k < 3; k++) b->lo[k] = b->hi[k] = 0.0;
        b->min_radius = 0.0;
    }
    b->mean_radius = a->n ? a->sum / (double)a->n : 0.0;
}

void spr_cloud_bounds(const spr_cloud *c, spr_bounds *b)
{
    spr_bounds_acc a;
    spr_bounds_begin(&a);
    spr_bounds_add(&a, c);
    spr_bounds_end(&a, b);
}

spr_result spr_cloud_source_scan(spr_cloud_source *src, spr_cloud *keep, const spr_progress *prog, spr_error *err)
{
    spr_cloud chunk;
    spr_result r = spr_cloud_alloc(&chunk, src->chunk);
    if (r) return spr__fail(err, r, "stream: cannot allocate a chunk of %zu splats", src->chunk);
    if (keep) {
        memset(keep, 0, sizeof *keep);
        keep->pos = malloc(3 * src->n * sizeof(float));
        keep->nrm = malloc(3 * src->n * sizeof(float));
        keep->radius = malloc(src->n * sizeof(float));
        if (!keep->pos || !keep->nrm || !keep->radius) {
            spr_cloud_free(keep);
            spr_cloud_free(&chunk);
            return spr__fail(err, SPR_E_NOMEM, "stream: out of memory for the centres, normals and radii of %zu splats", src->n);
        }
        keep->n = src->n;
        keep->flags = src->flags;
    }
    spr_bounds_acc acc;
    spr_bounds_begin(&acc);
    for (size_t first = 0; first < src->n && !r; first += src->chunk) {
        size_t m = src->n - first < src->chunk ? src->n - first : src->chunk;
        spr_progress_report(prog, "reading", first, src->n);
        if ((r = src->read(src->user, first, m, &chunk, err))) break;
        spr_bounds_add(&acc, &chunk);
        if (keep) {
            memcpy(keep->pos + 3 * first, chunk.pos, 3 * m * sizeof(float));
            memcpy(keep->nrm + 3 * first, chunk.nrm, 3 * m * sizeof(float));
            memcpy(keep->radius + first, chunk.radius, m * sizeof(float));
        }
    }
    spr_progress_report(prog, "reading", src->n, src->n);
    spr_cloud_free(&chunk);
    if (r) {
        if (keep) spr_cloud_free(keep);
        return r;
    }
    spr_bounds_end(&acc, &src->bounds);
    return SPR_OK;
}

void spr_cloud_color_by_normal(spr_cloud *c)
{
    for (size_t i = 0; i < 3 * c->n; i++) c->color[i] = 0.5f * c->nrm[i] + 0.5f;
}

double spr_cloud_default_eps(const spr_cloud *c)
{
    spr_bounds b;
    spr_cloud_bounds(c, &b);
    return spr_bounds_default_eps(&b);
}

double spr_bounds_default_eps(const spr_bounds *b) { return 2.0 * b->mean_radius; }

double spr_cloud_stream_ms(const spr_cloud *c, int threads, double *sum)
{
    const double t0 = spr_now_ms();
    const long n = (long)c->n;
    double acc = 0.0;
#pragma omp parallel for num_threads(threads > 0 ? threads : omp_get_num_procs()) schedule(static) reduction(+ : acc)
    for (long i = 0; i < n; i++) {
        const size_t k = (size_t)i;
        float s = c->pos[3 * k] + c->pos[3 * k + 1] + c->pos[3 * k + 2];
        s += c->nrm[3 * k] + c->nrm[3 * k + 1] + c->nrm[3 * k + 2];
        s += c->color[3 * k] + c->color[3 * k + 1] + c->color[3 * k + 2];
        s += c->radius[k] + c->alpha[k];
        acc += s;
    }
    *sum = acc;
    return spr_now_ms() - t0;
}

spr_result spr__cloud_finish(spr_cloud *c, const char *path, size_t first, double opacity, spr_error *err)
{
    if (!(c->flags & SPR_SRC_COLORS)) spr_cloud_color_by_normal(c);
    if (opacity > 0.0) {
        if (!(opacity <= 1.0)) return spr__fail(err, SPR_E_ARG, "%s: opacity %g outside (0, 1]", path, opacity);
        for (size_t i = 0; i < c->n; i++) c->alpha[i] = (float)opacity;
    }
    return spr__cloud_validate_from(c, path, first, err);
}
