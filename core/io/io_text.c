/* io_text.c — OFF meshes and XYZ/PWN point files, and reading a whole file. */
#include "spr_io.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

spr_result spr__read_file(const char *path, char **buf, size_t *len, spr_error *err)
{
    *buf = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) return spr__fail(err, SPR_E_IO, "%s: cannot open: %s", path, strerror(errno));
    if (fseek(f, 0, SEEK_END) != 0) { fclose(f); return spr__fail(err, SPR_E_IO, "%s: cannot seek", path); }
    long sz = ftell(f);
    if (sz < 0) { fclose(f); return spr__fail(err, SPR_E_IO, "%s: not a regular file", path); }
    rewind(f);
    char *b = malloc((size_t)sz + 1);
    if (!b) { fclose(f); return spr__fail(err, SPR_E_NOMEM, "%s: cannot hold %ld bytes", path, sz); }
    size_t got = fread(b, 1, (size_t)sz, f);
    fclose(f);
    if (got != (size_t)sz) { free(b); return spr__fail(err, SPR_E_IO, "%s: read %zu of %ld bytes", path, got, sz); }
    b[sz] = 0;
    *buf = b;
    *len = (size_t)sz;
    return SPR_OK;
}

spr_result spr__check_text(const char *path, const char *buf, size_t from, size_t len, spr_error *err)
{
    const char *z = from < len ? memchr(buf + from, 0, len - from) : NULL;
    if (z) return spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: NUL byte in a text file", path, (size_t)(z - buf));
    return SPR_OK;
}

void spr__mesh_free(spr__mesh *m)
{
    free(m->tri);
    memset(m, 0, sizeof *m);
}

/* Whitespace tokenizer with line numbers; '#' starts a comment. */
typedef struct lexer {
    const char *path, *p, *end;
    size_t line;
} lexer;

static void skip_space(lexer *lx, int stop_at_newline)
{
    while (lx->p < lx->end) {
        char ch = *lx->p;
        if (ch == '#') {
            while (lx->p < lx->end && *lx->p != '\n') lx->p++;
            continue;
        }
        if (ch == '\n') {
            if (stop_at_newline) return;
            lx->line++;
        } else if (!(ch == ' ' || ch == '\t' || ch == '\r')) {
            return;
        }
        lx->p++;
    }
}

static int next_token(lexer *lx, char *tok, size_t cap)
{
    skip_space(lx, 0);
    size_t k = 0;
    while (lx->p < lx->end && !strchr(" \t\r\n#", *lx->p)) {
        if (k < cap - 1) tok[k++] = *lx->p;
        lx->p++;
    }
    tok[k] = 0;
    return k > 0;
}

static spr_result next_double(lexer *lx, double *v, const char *what, size_t index, spr_error *err)
{
    char tok[128];
    if (!next_token(lx, tok, sizeof tok))
        return spr__fail(err, SPR_E_TRUNCATED, "%s:%zu: file ends inside %s %zu", lx->path, lx->line, what, index);
    char *e;
    *v = strtod(tok, &e);
    if (e == tok || *e)
        return spr__fail(err, SPR_E_FORMAT, "%s:%zu: %s %zu: expected a number, found \"%s\"", lx->path, lx->line, what, index, tok);
    return SPR_OK;
}

static spr_result next_count(lexer *lx, unsigned long long *v, const char *what, spr_error *err)
{
    char tok[128];
    if (!next_token(lx, tok, sizeof tok)) return spr__fail(err, SPR_E_TRUNCATED, "%s:%zu: missing %s", lx->path, lx->line, what);
    char *e;
    errno = 0;
    *v = strtoull(tok, &e, 10);
    if (e == tok || *e || errno || tok[0] == '-')
        return spr__fail(err, SPR_E_FORMAT, "%s:%zu: %s: expected a count, found \"%s\"", lx->path, lx->line, what, tok);
    return SPR_OK;
}

/* The n values of point i must be finite floats (checked after the
 * conversion: 1e300 is a finite double). */
static spr_result check_values(const lexer *lx, const double *v, int n, const char *what, size_t i, spr_error *err)
{
    for (int k = 0; k < n; k++)
        if (!spr__finite_float(v[k]))
            return spr__fail(err, SPR_E_VALUE, "%s:%zu: %s %zu: value %d (%g) is not a finite 32-bit float", lx->path, lx->line, what, i,
                             k + 1, v[k]);
    return SPR_OK;
}
static spr_result check_point(const lexer *lx, const double *xyz, size_t i, spr_error *err)
{
    for (int k = 0; k < 3; k++)
        if (!spr__finite_float(xyz[k]))
            return spr__fail(err, SPR_E_VALUE, "%s:%zu: point %zu: coordinate %c (%g) is not a finite 32-bit float", lx->path, lx->line, i,
                             "xyz"[k], xyz[k]);
    return SPR_OK;
}

spr_result spr__parse_off(const char *path, const char *buf, size_t len, spr_cloud *c, spr__mesh *mesh, spr_error *err)
{
    spr_result r;
    memset(c, 0, sizeof *c);
    memset(mesh, 0, sizeof *mesh);
    if ((r = spr__check_text(path, buf, 0, len, err))) goto fail;
    lexer lx = {path, buf, buf + len, 1};
    char tok[64];
    unsigned long long nv, nf, ne;
    if (!next_token(&lx, tok, sizeof tok) || !(strcmp(tok, "OFF") == 0 || strcmp(tok, "COFF") == 0 || strcmp(tok, "NOFF") == 0)) {
        r = spr__fail(err, SPR_E_FORMAT, "%s:%zu: not an OFF file (expected OFF, COFF or NOFF)", path, lx.line);
        goto fail;
    }
    int has_color = tok[0] == 'C', has_normal = tok[0] == 'N';
    if ((r = next_count(&lx, &nv, "vertex count", err)) || (r = next_count(&lx, &nf, "face count", err)) ||
        (r = next_count(&lx, &ne, "edge count", err)))
        goto fail;
    if (nv > SPR_MAX_SPLATS || nv > len / 2 + 1) {
        r = spr__fail(err, nv > SPR_MAX_SPLATS ? SPR_E_TOO_LARGE : SPR_E_TRUNCATED,
                      "%s:%zu: header declares %llu vertices, more than the file can hold", path, lx.line, nv);
        goto fail;
    }
    if (nf > len / 2 + 1) {
        r = spr__fail(err, SPR_E_TRUNCATED, "%s:%zu: header declares %llu faces, more than the file can hold", path, lx.line, nf);
        goto fail;
    }
    if ((r = spr_cloud_alloc(c, (size_t)nv))) { spr__fail(err, r, "%s: cannot allocate %llu splats", path, nv); goto fail; }
    for (size_t i = 0; i < nv; i++) {
        double v[3];
        for (int k = 0; k < 3; k++)
            if ((r = next_double(&lx, &v[k], "vertex", i, err))) goto fail;
        if ((r = check_point(&lx, v, i, err))) goto fail;
        for (int k = 0; k < 3; k++) c->pos[3 * i + k] = (float)v[k];
        if (has_normal) {
            for (int k = 0; k < 3; k++)
                if ((r = next_double(&lx, &v[k], "vertex", i, err))) goto fail;
            if ((r = check_values(&lx, v, 3, "vertex normal", i, err))) goto fail;
            for (int k = 0; k < 3; k++) c->nrm[3 * i + k] = (float)v[k];
            if (spr__normalize3(c->nrm + 3 * i)) { r = spr__fail(err, SPR_E_VALUE, "%s:%zu: vertex %zu: zero normal", path, lx.line, i); goto fail; }
        }
        if (has_color) {
            double col[4];
            for (int k = 0; k < 4; k++)
                if ((r = next_double(&lx, &col[k], "vertex", i, err))) goto fail;
            if ((r = check_values(&lx, col, 4, "vertex colour", i, err))) goto fail;
            double s = (col[0] > 1.0 || col[1] > 1.0 || col[2] > 1.0) ? 1.0 / 255.0 : 1.0;
            for (int k = 0; k < 3; k++) c->color[3 * i + k] = (float)(col[k] * s);
            c->alpha[i] = (float)(col[3] * s);
        }
    }
    for (size_t f = 0; f < nf; f++) {
        double dk;
        if ((r = next_double(&lx, &dk, "face", f, err))) goto fail;
        if (!(dk >= 0 && dk <= 1024) || dk != floor(dk)) { r = spr__fail(err, SPR_E_FORMAT, "%s:%zu: face %zu: bad vertex count", path, lx.line, f); goto fail; }
        int k = (int)dk;
        uint32_t idx[1024];
        for (int j = 0; j < k; j++) {
            double vi;
            if ((r = next_double(&lx, &vi, "face", f, err))) goto fail;
            if (!(vi >= 0 && vi < (double)nv)) { r = spr__fail(err, SPR_E_FORMAT, "%s:%zu: face %zu: vertex index %g out of range", path, lx.line, f, vi); goto fail; }
            idx[j] = (uint32_t)vi;
        }
        skip_space(&lx, 1); /* face colours and the rest of the line are ignored */
        while (lx.p < lx.end && *lx.p != '\n') lx.p++;
        if (k >= 3) {
            uint32_t *nt = realloc(mesh->tri, (mesh->nt + (size_t)k - 2) * 3 * sizeof(uint32_t));
            if (!nt) { r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path); goto fail; }
            mesh->tri = nt;
            for (int j = 0; j + 2 < k; j++) {
                mesh->tri[3 * mesh->nt] = idx[0];
                mesh->tri[3 * mesh->nt + 1] = idx[j + 1];
                mesh->tri[3 * mesh->nt + 2] = idx[j + 2];
                mesh->nt++;
            }
        }
    }
    mesh->nv = c->n;
    c->flags = (has_normal ? SPR_SRC_NORMALS : 0) | (has_color ? SPR_SRC_COLORS | SPR_SRC_ALPHA : 0);
    if (!has_normal)
        for (size_t i = 0; i < 3 * c->n; i++) c->nrm[i] = 0.0f;
    return SPR_OK;
fail:
    spr_cloud_free(c);
    spr__mesh_free(mesh);
    return r;
}

spr_result spr__parse_xyz(const char *path, const char *buf, size_t len, spr_cloud *c, spr_error *err)
{
    spr_result r;
    memset(c, 0, sizeof *c);
    if ((r = spr__check_text(path, buf, 0, len, err))) goto fail;
    /* First pass: count data lines and columns of the first one. */
    size_t lines = 0;
    int cols = -1;
    lexer lx = {path, buf, buf + len, 1};
    while (lx.p < lx.end) {
        skip_space(&lx, 0);
        if (lx.p >= lx.end) break;
        int n = 0;
        size_t line = lx.line;
        while (lx.p < lx.end && *lx.p != '\n') {
            char tok[128];
            skip_space(&lx, 1);
            if (lx.p >= lx.end || *lx.p == '\n') break;
            size_t k = 0;
            while (lx.p < lx.end && !strchr(" \t\r\n#", *lx.p)) { if (k < sizeof tok - 1) tok[k++] = *lx.p; lx.p++; }
            n++;
        }
        if (cols < 0) cols = n;
        if (n != cols || !(n == 3 || n == 6)) {
            r = spr__fail(err, SPR_E_FORMAT, "%s:%zu: expected %s numbers per line, found %d", path, line,
                          cols == 6 ? "6 (x y z nx ny nz)" : "3 or 6", n);
            goto fail;
        }
        lines++;
    }
    if (!lines) { r = spr__fail(err, SPR_E_FORMAT, "%s: no points", path); goto fail; }
    if ((r = spr_cloud_alloc(c, lines))) { spr__fail(err, r, "%s: cannot allocate %zu splats", path, lines); goto fail; }
    lexer l2 = {path, buf, buf + len, 1};
    for (size_t i = 0; i < lines; i++) {
        double v[6];
        for (int k = 0; k < cols; k++)
            if ((r = next_double(&l2, &v[k], "point", i, err))) goto fail;
        if ((r = check_point(&l2, v, i, err)) || (r = check_values(&l2, v, cols, "point", i, err))) goto fail;
        for (int k = 0; k < 3; k++) c->pos[3 * i + k] = (float)v[k];
        if (cols == 6) {
            for (int k = 0; k < 3; k++) c->nrm[3 * i + k] = (float)v[3 + k];
            if (spr__normalize3(c->nrm + 3 * i)) { r = spr__fail(err, SPR_E_VALUE, "%s:%zu: point %zu: zero or non-finite normal", path, l2.line, i); goto fail; }
        } else {
            c->nrm[3 * i] = c->nrm[3 * i + 1] = c->nrm[3 * i + 2] = 0.0f;
        }
    }
    c->flags = cols == 6 ? SPR_SRC_NORMALS : 0;
    return SPR_OK;
fail:
    spr_cloud_free(c);
    return r;
}
