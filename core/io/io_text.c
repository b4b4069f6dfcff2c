/* io_text.c — OFF meshes and XYZ/PWN point files, and reading a whole file. */
#include "spr_io.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
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

spr_result spr__map_file(const char *path, char **buf, size_t *len, int *mapped, spr_error *err)
{
    *mapped = 0;
    struct stat st;
    int fd = open(path, O_RDONLY);
    if (fd >= 0 && fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size >= (off_t)SPR__MAP_MIN) {
        void *p = mmap(NULL, (size_t)st.st_size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
        close(fd);
        if (p != MAP_FAILED) {
            *buf = p;
            *len = (size_t)st.st_size;
            *mapped = 1;
            return SPR_OK;
        }
    } else if (fd >= 0) {
        close(fd);
    }
    return spr__read_file(path, buf, len, err); /* small files, pipes, or mmap refused: read */
}

void spr__unmap_file(char *buf, size_t len, int mapped)
{
    if (mapped) munmap(buf, len);
    else free(buf);
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

int spr__mesh_fan(spr__mesh *m, const uint32_t *idx, int k)
{
    size_t need = m->nt + (size_t)k - 2;
    if (need > m->cap) {
        size_t cap = m->cap ? 2 * m->cap : 1024;
        while (cap < need) cap *= 2;
        uint32_t *nt = realloc(m->tri, cap * 3 * sizeof *nt);
        if (!nt) return -1;
        m->tri = nt;
        m->cap = cap;
    }
    for (int j = 0; j + 2 < k; j++) {
        uint32_t *t = m->tri + 3 * m->nt++;
        t[0] = idx[0], t[1] = idx[j + 1], t[2] = idx[j + 2];
    }
    return 0;
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
        if (k >= 3 && spr__mesh_fan(mesh, idx, k)) { r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path); goto fail; }
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

/* ---- point files by column name ---- */

enum { C_SKIP = -1, C_X, C_Y, C_Z, C_NX, C_NY, C_NZ, C_R, C_G, C_B, C_A, C_RADIUS, C__N };

/* Role of a column name, case-insensitive; C_SKIP for names we do not read. */
static int column_role(const char *name, size_t len)
{
    static const struct { const char *n; int r; } tab[] = {
        {"x", C_X}, {"y", C_Y}, {"z", C_Z}, {"nx", C_NX}, {"ny", C_NY}, {"nz", C_NZ}, {"normal_x", C_NX}, {"normal_y", C_NY},
        {"normal_z", C_NZ}, {"r", C_R}, {"g", C_G}, {"b", C_B}, {"red", C_R}, {"green", C_G}, {"blue", C_B}, {"a", C_A},
        {"alpha", C_A}, {"radius", C_RADIUS}};
    for (size_t k = 0; k < sizeof tab / sizeof tab[0]; k++) {
        size_t L = strlen(tab[k].n);
        if (L != len) continue;
        size_t j = 0;
        while (j < L && (name[j] | 32) == tab[k].n[j]) j++;
        if (j == L) return tab[k].r;
    }
    return C_SKIP;
}

static int is_sep(char ch) { return ch == ' ' || ch == '\t' || ch == ',' || ch == ';' || ch == '\r'; }

/* The fields of the line [p, e): starts and lengths, at most max (the count, even past max, is returned). */
static int split_fields(const char *p, const char *e, const char **f, size_t *fl, int max)
{
    int n = 0;
    while (p < e) {
        while (p < e && is_sep(*p)) p++;
        if (p >= e) break;
        const char *q = p;
        while (q < e && !is_sep(*q)) q++;
        if (n < max) f[n] = p, fl[n] = (size_t)(q - p);
        n++;
        p = q;
    }
    return n;
}

/* The line [q, e) without a trailing `# comment`. */
static const char *cut_comment(const char *q, const char *e)
{
    const char *h = memchr(q, '#', (size_t)(e - q));
    return h ? h : e;
}

/* A field that reads as a number. */
static int numeric(const char *f, size_t l, double *v)
{
    char tmp[64];
    if (l == 0 || l >= sizeof tmp) return 0;
    memcpy(tmp, f, l);
    tmp[l] = 0;
    char *end;
    *v = strtod(tmp, &end);
    return *end == 0;
}

#define MAX_COLS 64

/* The next line of [*p, end): its fields (at most MAX_COLS kept, all
 * counted) after a leading comment marker (`#`, `//`: *comment set) or up to
 * a trailing `# comment`; *p moves past the line. */
static int next_line(const char **p, const char *end, const char **f, size_t *fl, int *comment)
{
    const char *e = memchr(*p, '\n', (size_t)(end - *p));
    if (!e) e = end;
    const char *q = *p;
    *p = e < end ? e + 1 : end;
    while (q < e && is_sep(*q)) q++;
    *comment = q < e && (*q == '#' || (q + 1 < e && q[0] == '/' && q[1] == '/'));
    if (*comment) q += *q == '#' ? 1 : 2;
    else e = cut_comment(q, e);
    return split_fields(q, e, f, fl, MAX_COLS);
}

spr_result spr__parse_xyz(const char *path, const char *buf, size_t len, const char *columns, spr_cloud *c, spr_error *err)
{
    spr_result r;
    memset(c, 0, sizeof *c);
    if ((r = spr__check_text(path, buf, 0, len, err))) return r;
    int role[MAX_COLS], ncols = -1, header_line = 0;
    const char *f[MAX_COLS];
    size_t fl[MAX_COLS];
    if (columns) { /* --columns x,y,z,… */
        ncols = split_fields(columns, columns + strlen(columns), f, fl, MAX_COLS);
        if (ncols > MAX_COLS) return spr__fail(err, SPR_E_ARG, "%s: --columns names %d columns (at most %d)", path, ncols, MAX_COLS);
        for (int k = 0; k < ncols; k++) {
            role[k] = fl[k] == 1 && f[k][0] == '_' ? C_SKIP : column_role(f[k], fl[k]);
            if (role[k] == C_SKIP && !(fl[k] == 1 && f[k][0] == '_'))
                return spr__fail(err, SPR_E_ARG, "%s: --columns: unknown column \"%.*s\" (x y z nx ny nz r g b a radius, _ to skip one)", path,
                                 (int)(fl[k] < 40 ? fl[k] : 40), f[k]);
        }
    }
    /* first pass: the header, then count the data lines and check their width */
    size_t lines = 0, line = 0;
    double cmax = 0.0;
    for (const char *p = buf, *end = buf + len; p < end;) {
        line++;
        int comment;
        const int n = next_line(&p, end, f, fl, &comment);
        double v;
        int names = n > 0 && n <= MAX_COLS && !numeric(f[0], fl[0], &v);
        if (!lines && !header_line && names && !columns) { /* a header line: `//X Y Z …`, `# x y z …` or CSV `x,y,z,…` */
            int have = 0;
            for (int k = 0; k < n; k++) {
                role[k] = column_role(f[k], fl[k]);
                if (role[k] >= 0) have |= 1 << role[k];
            }
            if ((have & 7) == 7 || !comment) {
                if ((have & 7) != 7)
                    return spr__fail(err, SPR_E_FORMAT, "%s:%zu: the header line does not name columns x, y and z", path, line);
                ncols = n;
                header_line = (int)line;
                continue;
            }
        }
        if (comment || n == 0) continue; /* comments and blank lines */
        if (ncols < 0) { /* no header, no --columns: x y z [nx ny nz] */
            if (n != 3 && n != 6)
                return spr__fail(err, SPR_E_FORMAT, "%s:%zu: expected 3 or 6 numbers per line (x y z [nx ny nz]), found %d: name the columns with a "
                                 "header line (//X Y Z R G B Nx Ny Nz) or --columns (e.g. x,y,z,r,g,b,_,nx,ny,nz)", path, line, n);
            ncols = n;
            for (int k = 0; k < n; k++) role[k] = k;
        }
        if (n != ncols)
            return spr__fail(err, SPR_E_FORMAT, "%s:%zu: expected %d %s per line, found %d", path, line, ncols,
                             header_line ? "columns (as the header names)" : columns ? "columns (as --columns names)" : "numbers", n);
        for (int k = 0; k < n; k++) {
            if (!numeric(f[k], fl[k], &v))
                return spr__fail(err, SPR_E_FORMAT, "%s:%zu: column %d: expected a number, found \"%.*s\"", path, line, k + 1,
                                 (int)(fl[k] < 40 ? fl[k] : 40), f[k]);
            if (role[k] >= C_R && role[k] <= C_A && v > cmax) cmax = v;
        }
        lines++;
    }
    if (!lines) return spr__fail(err, SPR_E_FORMAT, "%s: no points", path);
    int have = 0;
    for (int k = 0; k < ncols; k++)
        if (role[k] >= 0) have |= 1 << role[k];
    if ((have & 7) != 7) return spr__fail(err, SPR_E_FORMAT, "%s: the columns do not include x, y and z", path);
    const int nrm = (have & 0x38) == 0x38, col = (have & 0x1c0) == 0x1c0;
    if ((have & 0x38) && !nrm) return spr__fail(err, SPR_E_FORMAT, "%s: the columns name some of nx ny nz but not all three", path);
    if ((r = spr_cloud_alloc(c, lines))) return spr__fail(err, r, "%s: cannot allocate %zu splats", path, lines);
    /* colours: integers 0..255 when any exceeds 1 (CloudCompare writes 0..255), else [0,1] */
    const double cs = cmax > 1.0 ? 1.0 / 255.0 : 1.0;
    size_t i = 0;
    line = 0;
    for (const char *p = buf, *end = buf + len; p < end && i < lines;) {
        line++;
        int comment;
        const int n = next_line(&p, end, f, fl, &comment);
        if (comment || (int)line == header_line || !n) continue;
        double v[C__N] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0};
        for (int k = 0; k < n; k++) {
            double x = 0.0;
            numeric(f[k], fl[k], &x);
            if (role[k] < 0) continue;
            if (!spr__finite_float(x) && role[k] <= C_Z)
                return spr_cloud_free(c), spr__fail(err, SPR_E_VALUE, "%s:%zu: point %zu: coordinate %c (%g) is not a finite 32-bit float", path,
                                                    line, i, "xyz"[role[k]], x);
            if (!spr__finite_float(x))
                return spr_cloud_free(c), spr__fail(err, SPR_E_VALUE, "%s:%zu: point %zu: column %d (%g) is not a finite 32-bit float", path, line,
                                                    i, k + 1, x);
            v[role[k]] = x;
        }
        for (int k = 0; k < 3; k++) c->pos[3 * i + k] = (float)v[C_X + k];
        if (nrm) {
            for (int k = 0; k < 3; k++) c->nrm[3 * i + k] = (float)v[C_NX + k];
            if (spr__normalize3(c->nrm + 3 * i))
                return spr_cloud_free(c), spr__fail(err, SPR_E_VALUE, "%s:%zu: point %zu: zero or non-finite normal", path, line, i);
        } else {
            c->nrm[3 * i] = c->nrm[3 * i + 1] = c->nrm[3 * i + 2] = 0.0f;
        }
        if (col) {
            for (int k = 0; k < 3; k++) c->color[3 * i + k] = (float)(v[C_R + k] * cs);
            if (have & (1 << C_A)) c->alpha[i] = (float)(v[C_A] * cs);
        }
        if (have & (1 << C_RADIUS)) {
            if (!(v[C_RADIUS] > 0.0))
                return spr_cloud_free(c), spr__fail(err, SPR_E_VALUE, "%s:%zu: point %zu: radius %g is not positive", path, line, i, v[C_RADIUS]);
            c->radius[i] = (float)v[C_RADIUS];
        }
        i++;
    }
    c->flags = (nrm ? SPR_SRC_NORMALS : 0) | (col ? SPR_SRC_COLORS : 0) | ((have & (1 << C_A)) ? SPR_SRC_ALPHA : 0) |
               ((have & (1 << C_RADIUS)) ? SPR_SRC_RADII : 0);
    return SPR_OK;
}
