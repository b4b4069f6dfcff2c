/* io_ply.c — PLY reader (ascii, binary LE/BE) and binary PLY writer.
 *
 * Written here rather than taken from a library: Debian has no maintained C
 * PLY reader we could depend on (rply is not packaged), and we need byte
 * offsets in every error message and a size check before any allocation.
 */
#include "spr_io.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef enum { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 } ply_type;

typedef struct ply_prop {
    char name[64];
    ply_type type;
    ply_type count_type; /* T_NONE for scalars */
} ply_prop;

typedef struct ply_elem {
    char name[64];
    unsigned long long count;
    ply_prop props[64];
    int nprops;
} ply_elem;

enum { F_ASCII, F_LE, F_BE };

static ply_type type_from(const char *s)
{
    static const struct { const char *n; ply_type t; } tab[] = {
        {"char", T_I8},   {"int8", T_I8},     {"uchar", T_U8},   {"uint8", T_U8},   {"short", T_I16},
        {"int16", T_I16}, {"ushort", T_U16},  {"uint16", T_U16}, {"int", T_I32},    {"int32", T_I32},
        {"uint", T_U32},  {"uint32", T_U32},  {"float", T_F32},  {"float32", T_F32}, {"double", T_F64},
        {"float64", T_F64}};
    for (size_t i = 0; i < sizeof tab / sizeof tab[0]; i++)
        if (strcmp(s, tab[i].n) == 0) return tab[i].t;
    return T_NONE;
}

static int type_size(ply_type t)
{
    static const int sz[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
    return sz[t];
}

/* Decode one binary value at p (size known valid). */
static double bin_value(const unsigned char *p, ply_type t, int big)
{
    unsigned char b[8];
    int n = type_size(t);
    for (int i = 0; i < n; i++) b[i] = big ? p[n - 1 - i] : p[i];
    switch (t) {
    case T_I8: return (double)(int8_t)b[0];
    case T_U8: return (double)b[0];
    case T_I16: { int16_t v; memcpy(&v, b, 2); return v; }
    case T_U16: { uint16_t v; memcpy(&v, b, 2); return v; }
    case T_I32: { int32_t v; memcpy(&v, b, 4); return v; }
    case T_U32: { uint32_t v; memcpy(&v, b, 4); return v; }
    case T_F32: { float v; memcpy(&v, b, 4); return v; }
    case T_F64: { double v; memcpy(&v, b, 8); return v; }
    default: return 0.0;
    }
}

/* Role of a vertex property in the cloud. */
enum { R_NONE, R_X, R_Y, R_Z, R_NX, R_NY, R_NZ, R_R, R_G, R_B, R_A, R_RADIUS };

static int role_of(const char *n)
{
    static const struct { const char *n; int r; } tab[] = {
        {"x", R_X}, {"y", R_Y}, {"z", R_Z}, {"nx", R_NX}, {"ny", R_NY}, {"nz", R_NZ},
        {"normal_x", R_NX}, {"normal_y", R_NY}, {"normal_z", R_NZ},
        {"red", R_R}, {"green", R_G}, {"blue", R_B}, {"alpha", R_A},
        {"diffuse_red", R_R}, {"diffuse_green", R_G}, {"diffuse_blue", R_B}, {"diffuse_alpha", R_A},
        {"radius", R_RADIUS}, {"scale", R_RADIUS}, {"size", R_RADIUS}};
    for (size_t i = 0; i < sizeof tab / sizeof tab[0]; i++)
        if (strcmp(n, tab[i].n) == 0) return tab[i].r;
    return R_NONE;
}

/* Cursor over the body for both encodings. */
typedef struct cursor {
    const char *path;
    const unsigned char *p, *end, *base;
    int fmt;
    size_t line;
    spr_error *err;
    size_t off0;  /* file offset of base (a streamed chunk's bytes start inside the file) */
} cursor;

/* Byte offset in the file of the value just read (n bytes long). */
static size_t cursor_at(const cursor *cu, int n) { return cu->off0 + (size_t)(cu->p - cu->base) - (size_t)n; }

static spr_result read_value(cursor *cu, ply_type t, double *out, const char *what, unsigned long long index)
{
    if (cu->fmt == F_ASCII) {
        while (cu->p < cu->end && (*cu->p == ' ' || *cu->p == '\t' || *cu->p == '\r' || *cu->p == '\n')) {
            if (*cu->p == '\n') cu->line++;
            cu->p++;
        }
        if (cu->p >= cu->end)
            return spr__fail(cu->err, SPR_E_TRUNCATED, "%s:%zu: file ends inside %s %llu", cu->path, cu->line, what, index);
        char tmp[64];
        size_t k = 0;
        while (cu->p < cu->end && k < sizeof tmp - 1 && !(*cu->p == ' ' || *cu->p == '\t' || *cu->p == '\r' || *cu->p == '\n'))
            tmp[k++] = (char)*cu->p++;
        tmp[k] = 0;
        char *e;
        errno = 0;
        double v = strtod(tmp, &e);
        if (e == tmp || *e)
            return spr__fail(cu->err, SPR_E_FORMAT, "%s:%zu: %s %llu: expected a number, found \"%s\"", cu->path, cu->line,
                             what, index, tmp);
        *out = v;
        return SPR_OK;
    }
    int n = type_size(t);
    if ((size_t)(cu->end - cu->p) < (size_t)n)
        return spr__fail(cu->err, SPR_E_TRUNCATED, "%s: byte %zu: file ends inside %s %llu", cu->path,
                         cursor_at(cu, 0), what, index);
    *out = bin_value(cu->p, t, cu->fmt == F_BE);
    cu->p += n;
    return SPR_OK;
}

static double color_scale(ply_type t) { return t == T_U8 || t == T_I8 ? 1.0 / 255.0 : (t == T_U16 || t == T_I16 ? 1.0 / 65535.0 : 1.0); }

static spr_result parse_header(const char *path, const char *buf, size_t len, int *fmt, ply_elem *el, int *nel,
                               size_t *body, const spr_warn *warn, spr_error *err)
{
    size_t pos = 0, line = 0;
    *nel = 0;
    int seen_format = 0;
    while (pos < len) {
        line++;
        size_t eol = pos;
        while (eol < len && buf[eol] != '\n') eol++;
        if (eol == len) break;
        char l[512];
        size_t ll = eol - pos < sizeof l - 1 ? eol - pos : sizeof l - 1;
        memcpy(l, buf + pos, ll);
        l[ll] = 0;
        if (ll && l[ll - 1] == '\r') l[--ll] = 0;
        pos = eol + 1;
        if (line == 1) {
            if (strcmp(l, "ply") != 0) return spr__fail(err, SPR_E_FORMAT, "%s:1: not a PLY file (expected \"ply\")", path);
            continue;
        }
        char w0[64] = "", w1[64] = "", w2[64] = "", w3[64] = "", w4[64] = "";
        int nw = sscanf(l, "%63s %63s %63s %63s %63s", w0, w1, w2, w3, w4);
        if (nw <= 0) continue;
        if (!strcmp(w0, "comment") || !strcmp(w0, "obj_info")) continue;
        if (!strcmp(w0, "end_header")) {
            if (!seen_format) return spr__fail(err, SPR_E_FORMAT, "%s:%zu: header has no format line", path, line);
            *body = pos;
            return SPR_OK;
        }
        if (!strcmp(w0, "format")) {
            if (!strcmp(w1, "ascii")) *fmt = F_ASCII;
            else if (!strcmp(w1, "binary_little_endian")) *fmt = F_LE;
            else if (!strcmp(w1, "binary_big_endian")) *fmt = F_BE;
            else return spr__fail(err, SPR_E_FORMAT, "%s:%zu: unknown format \"%s\"", path, line, w1);
            seen_format = 1;
        } else if (!strcmp(w0, "element")) {
            if (*nel >= 16) return spr__fail(err, SPR_E_FORMAT, "%s:%zu: too many elements", path, line);
            char *e;
            errno = 0;
            unsigned long long cnt = strtoull(w2, &e, 10);
            if (nw < 3 || e == w2 || *e || errno || w2[0] == '-')
                return spr__fail(err, SPR_E_FORMAT, "%s:%zu: element \"%s\" has no valid count", path, line, w1);
            ply_elem *E = &el[(*nel)++];
            memset(E, 0, sizeof *E);
            snprintf(E->name, sizeof E->name, "%s", w1);
            E->count = cnt;
        } else if (!strcmp(w0, "property")) {
            if (!*nel) return spr__fail(err, SPR_E_FORMAT, "%s:%zu: property before any element", path, line);
            ply_elem *E = &el[*nel - 1];
            if (E->nprops >= 64) return spr__fail(err, SPR_E_FORMAT, "%s:%zu: too many properties", path, line);
            ply_prop *P = &E->props[E->nprops++];
            if (!strcmp(w1, "list")) {
                P->count_type = type_from(w2);
                P->type = type_from(w3);
                snprintf(P->name, sizeof P->name, "%s", w4);
                if (nw < 5 || P->count_type == T_NONE || P->type == T_NONE || P->count_type == T_F32 || P->count_type == T_F64)
                    return spr__fail(err, SPR_E_FORMAT, "%s:%zu: malformed list property", path, line);
            } else {
                P->type = type_from(w1);
                P->count_type = T_NONE;
                snprintf(P->name, sizeof P->name, "%s", w2);
                if (nw < 3 || P->type == T_NONE)
                    return spr__fail(err, SPR_E_FORMAT, "%s:%zu: unknown property type \"%s\"", path, line, w1);
            }
        } else {
            /* Outside the grammar but unable to change the layout (only
             * format, element, property and end_header can): exporters write
             * such lines (Blender 2.47: "Created by Blender3D 247 …" without
             * `comment`), other readers skip them, and so do we, saying so. */
            spr_warn_report(warn, "%s:%zu: header line \"%.60s\" is not PLY grammar (not comment, format, element, property): skipped", path,
                            line, l);
        }
    }
    return spr__fail(err, SPR_E_TRUNCATED, "%s: header has no end_header line", path);
}

/* The vertex element's properties as the cloud reads them. */
typedef struct vertex_layout {
    const ply_elem *V;
    int role[64];
    ply_type ctype[64];
    int have;  /* bit R_* set when the role is present */
} vertex_layout;

/* Fill the roles of V's properties; an error for colours of 32-bit integer type. */
static spr_result vertex_layout_make(const char *path, const ply_elem *V, vertex_layout *L, spr_error *err)
{
    L->V = V;
    L->have = 0;
    for (int k = 0; k < V->nprops; k++) {
        L->role[k] = V->props[k].count_type == T_NONE ? role_of(V->props[k].name) : R_NONE;
        L->ctype[k] = V->props[k].type;
        if (L->role[k]) L->have |= 1 << L->role[k];
        if ((L->role[k] >= R_R && L->role[k] <= R_A) && (L->ctype[k] == T_I32 || L->ctype[k] == T_U32))
            return spr__fail(err, SPR_E_FORMAT, "%s: colour property \"%s\" has a 32-bit integer type", path, V->props[k].name);
    }
    if ((L->have & ((1 << R_X) | (1 << R_Y) | (1 << R_Z))) != ((1 << R_X) | (1 << R_Y) | (1 << R_Z)))
        return spr__fail(err, SPR_E_FORMAT, "%s: vertex element lacks x, y or z", path);
    return SPR_OK;
}

/* Read vertex i (file order) at the cursor into splat s of c: every value
 * checked as the float it becomes, radii positive, the normal renormalised.
 * The one decoding of a vertex, for whole files and streamed chunks. */
static spr_result decode_vertex(cursor *cu, const vertex_layout *L, spr_cloud *c, size_t s, unsigned long long i)
{
    const ply_elem *V = L->V;
    const char *path = cu->path;
    spr_error *err = cu->err;
    spr_result r;
    for (int k = 0; k < V->nprops; k++) {
        const ply_prop *P = &V->props[k];
        const int role = L->role[k];
        double v;
        if (P->count_type != T_NONE) { /* a list in the vertex element: read past it */
            double cnt;
            if ((r = read_value(cu, P->count_type, &cnt, V->name, i))) return r;
            if (!(cnt >= 0 && cnt <= 1024) || cnt != floor(cnt))
                return spr__fail(err, SPR_E_FORMAT, "%s: %s %llu: list length %g is not a whole number in 0..1024", path, V->name, i, cnt);
            for (int j = 0; j < (int)cnt; j++)
                if ((r = read_value(cu, P->type, &v, V->name, i))) return r;
            continue;
        }
        if ((r = read_value(cu, P->type, &v, V->name, i))) return r;
        if (role && !spr__finite_float(v)) /* checked as the float it becomes: 1e300 is a finite double */
            return cu->fmt == F_ASCII
                       ? spr__fail(err, SPR_E_VALUE, "%s:%zu: vertex %llu: %s %s (%g) is not a finite 32-bit float", path, cu->line, i,
                                   role <= R_Z ? "coordinate" : "property", P->name, v)
                       : spr__fail(err, SPR_E_VALUE, "%s: byte %zu: vertex %llu: %s %s (%g) is not a finite 32-bit float", path,
                                   cursor_at(cu, type_size(P->type)), i, role <= R_Z ? "coordinate" : "property", P->name, v);
        switch (role) {
        case R_X: case R_Y: case R_Z: c->pos[3 * s + role - R_X] = (float)v; break;
        case R_NX: case R_NY: case R_NZ: c->nrm[3 * s + role - R_NX] = (float)v; break;
        case R_R: case R_G: case R_B: c->color[3 * s + role - R_R] = (float)(v * color_scale(L->ctype[k])); break;
        case R_A: c->alpha[s] = (float)(v * color_scale(L->ctype[k])); break;
        case R_RADIUS:
            if (!(v > 0.0) || !isfinite(v))
                return cu->fmt == F_ASCII
                           ? spr__fail(err, SPR_E_VALUE, "%s:%zu: vertex %llu: radius %g is not positive and finite", path, cu->line, i, v)
                           : spr__fail(err, SPR_E_VALUE, "%s: byte %zu: vertex %llu: radius %g is not positive and finite", path,
                                       cursor_at(cu, type_size(P->type)), i, v);
            c->radius[s] = (float)v;
            break;
        default: break;
        }
    }
    float *n = c->nrm + 3 * s;
    if ((L->have & (1 << R_NX)) && !(n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f) && spr__normalize3(n))
        return spr__fail(err, SPR_E_VALUE, "%s: vertex %llu: zero or non-finite normal", path, i);
    return SPR_OK; /* an all-zero normal stays zero: zero_normals() judges the file */
}

/* Where the vertex data came from, as spr_cloud flags. */
static unsigned vertex_flags(int have)
{
    return ((have & (1 << R_NX)) ? SPR_SRC_NORMALS : 0) | ((have & (1 << R_R)) ? SPR_SRC_COLORS : 0) |
           ((have & (1 << R_RADIUS)) ? SPR_SRC_RADII : 0) | ((have & (1 << R_A)) ? SPR_SRC_ALPHA : 0);
}

/* Bytes of one vertex record when every vertex property is a scalar of a
 * binary file (0: variable-size records, or ascii). */
static size_t fixed_record(int fmt, const ply_elem *V)
{
    if (fmt == F_ASCII) return 0;
    size_t rec = 0;
    for (int k = 0; k < V->nprops; k++) {
        if (V->props[k].count_type != T_NONE) return 0;
        rec += (size_t)type_size(V->props[k].type);
    }
    return rec;
}

/* Vertices first … first+count−1 from fixed-size binary records at `base`
 * (file offset off0, `bytes` long, all present) into splats 0 … count−1 of
 * c: decoded in parallel, and on failure the first bad vertex decoded again
 * alone for its message (the same for any thread count). */
static spr_result decode_block(const char *path, int fmt, const vertex_layout *L, const unsigned char *base, size_t bytes, size_t off0,
                               size_t rec, size_t first, size_t count, spr_cloud *c, spr_error *err)
{
    long bad = -1;
#pragma omp parallel for schedule(static)
    for (long j = 0; j < (long)count; j++) {
        spr_error e = {0};
        cursor cu = {path, base + (size_t)j * rec, base + bytes, base, fmt, 0, &e, off0};
        if (decode_vertex(&cu, L, c, (size_t)j, (unsigned long long)(first + (size_t)j))) {
#pragma omp critical(spr_ply_bad)
            if (bad < 0 || j < bad) bad = j;
        }
    }
    if (bad < 0) return SPR_OK;
    cursor cu = {path, base + (size_t)bad * rec, base + bytes, base, fmt, 0, err, off0};
    return decode_vertex(&cu, L, c, (size_t)bad, (unsigned long long)(first + (size_t)bad));
}

/* Normals read as all zero: when every splat's is, the file has none
 * (exporters write 0 0 0 for "no normal"; they are computed as for a file
 * without them, with a warning); one among real normals is an error naming
 * it (first: the index of splat 0 of c in the file). *none is set. */
static spr_result zero_normals(const char *path, const spr_cloud *c, size_t first, int all_of_file, const spr_warn *warn, int *none,
                               spr_error *err)
{
    size_t zeros = 0, first_zero = SIZE_MAX;
    for (size_t i = 0; i < c->n; i++) {
        const float *n = c->nrm + 3 * i;
        if (n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f) {
            if (!zeros) first_zero = i;
            zeros++;
        }
    }
    *none = all_of_file && zeros == c->n && c->n > 0;
    if (*none) {
        spr_warn_report(warn, "%s: all %zu normals are 0 0 0: read as none (computed from the neighbours)", path, c->n);
        return SPR_OK;
    }
    if (zeros)
        return spr__fail(err, SPR_E_VALUE, "%s: vertex %zu: zero normal (%s)", path, first + first_zero,
                         all_of_file ? "other vertices have normals" : "--stream needs a normal for every splat");
    return SPR_OK;
}

spr_result spr__parse_ply(const char *path, const char *buf, size_t len, spr_cloud *c, spr__mesh *mesh, const spr_progress *prog,
                          const spr_warn *warn, spr_error *err)
{
    spr_result r;
    int fmt = F_ASCII, nel = 0;
    ply_elem el[16];
    size_t body = 0;
    memset(mesh, 0, sizeof *mesh);
    memset(c, 0, sizeof *c);
    r = parse_header(path, buf, len, &fmt, el, &nel, &body, warn, err);
    if (!r) r = spr__check_text(path, buf, 0, fmt == F_ASCII ? len : body, err);
    if (r) goto fail;
    int vi = -1;
    for (int e = 0; e < nel; e++)
        if (!strcmp(el[e].name, "vertex")) { vi = e; break; }
    if (vi < 0) { r = spr__fail(err, SPR_E_FORMAT, "%s: no \"vertex\" element", path); goto fail; }
    ply_elem *V = &el[vi];
    if (V->count > SPR_MAX_SPLATS) {
        r = spr__fail(err, SPR_E_TOO_LARGE, "%s: header declares %llu vertices (limit %u)", path, V->count, SPR_MAX_SPLATS);
        goto fail;
    }
    vertex_layout lay;
    if ((r = vertex_layout_make(path, V, &lay, err))) goto fail;
    const int have = lay.have;
    /* Size check before allocating or reading: every item of every element
     * takes at least its fixed-size values plus the count of each list
     * (binary), or two bytes per value ("0 ", ascii); an element with no
     * properties takes no bytes and is refused if it claims items. */
    for (int e = 0; e < nel; e++) {
        const ply_elem *E = &el[e];
        unsigned long long item = 0;
        for (int k = 0; k < E->nprops; k++)
            item += fmt == F_ASCII ? 2u : (unsigned)type_size(E->props[k].count_type != T_NONE ? E->props[k].count_type : E->props[k].type);
        if (!E->nprops && E->count) {
            r = spr__fail(err, SPR_E_FORMAT, "%s: element \"%s\" declares %llu items but no property", path, E->name, E->count);
            goto fail;
        }
        unsigned long long room = len - body + (fmt == F_ASCII ? 1u : 0u); /* the last ascii value may lack its separator */
        if (E->nprops && E->count > room / item) {
            r = spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: header declares %llu %s items (at least %llu bytes each) but only %zu bytes follow",
                          path, body, E->count, E->name, item, len - body);
            goto fail;
        }
    }
    r = spr_cloud_alloc(c, (size_t)V->count);
    if (r) { spr__fail(err, r, "%s: cannot allocate %llu splats", path, V->count); goto fail; }
    cursor cu = {path, (const unsigned char *)buf + body, (const unsigned char *)buf + len, (const unsigned char *)buf,
                 fmt, 0, err, 0};
    /* header line count for ascii error positions */
    for (size_t i = 0; i < body; i++) cu.line += buf[i] == '\n';
    cu.line++;
    for (int e = 0; e < nel; e++) {
        ply_elem *E = &el[e];
        int is_face = !strcmp(E->name, "face");
        if (is_face) {
            if (E->count > SPR_MAX_SPLATS * 4ull) { r = spr__fail(err, SPR_E_TOO_LARGE, "%s: header declares %llu faces", path, E->count); goto fail; }
        }
        const size_t rec = e == vi ? fixed_record(fmt, V) : 0;
        if (rec && (size_t)(cu.end - cu.p) / rec >= E->count) { /* fixed-size records, all present: in blocks, each in parallel */
            for (size_t first = 0; first < (size_t)E->count; first += (size_t)1 << 20) {
                const size_t m = (size_t)E->count - first < ((size_t)1 << 20) ? (size_t)E->count - first : (size_t)1 << 20;
                spr_progress_report(prog, "reading vertices", first, (size_t)E->count);
                spr_cloud part = *c; /* splats first … first+m−1 */
                part.pos += 3 * first, part.nrm += 3 * first, part.color += 3 * first, part.radius += first, part.alpha += first;
                if ((r = decode_block(path, fmt, &lay, cu.p, m * rec, (size_t)(cu.p - cu.base), rec, first, m, &part, err))) goto fail;
                cu.p += m * rec;
            }
            continue;
        }
        for (unsigned long long i = 0; i < E->count; i++) {
            if (e == vi) {
                if (!(i & 0xfffff)) spr_progress_report(prog, "reading vertices", (size_t)i, (size_t)E->count);
                if ((r = decode_vertex(&cu, &lay, c, (size_t)i, i))) goto fail;
                continue;
            }
            for (int k = 0; k < E->nprops; k++) {
                const ply_prop *P = &E->props[k];
                double v;
                if (P->count_type != T_NONE) {
                    double cnt;
                    if ((r = read_value(&cu, P->count_type, &cnt, E->name, i))) goto fail;
                    if (!(cnt >= 0 && cnt <= 1024) || cnt != floor(cnt)) { /* NaN fails too */
                        r = spr__fail(err, SPR_E_FORMAT, "%s: %s %llu: list length %g is not a whole number in 0..1024", path, E->name, i, cnt);
                        goto fail;
                    }
                    uint32_t idx[1024];
                    for (int j = 0; j < (int)cnt; j++) {
                        if ((r = read_value(&cu, P->type, &v, E->name, i))) goto fail;
                        idx[j] = v >= 0 && v < (double)V->count ? (uint32_t)v : UINT32_MAX;
                    }
                    if (is_face && (!strcmp(P->name, "vertex_indices") || !strcmp(P->name, "vertex_index")) && cnt >= 3) {
                        for (int j = 0; j < (int)cnt; j++)
                            if (idx[j] == UINT32_MAX) { r = spr__fail(err, SPR_E_FORMAT, "%s: face %llu: vertex index out of range", path, i); goto fail; }
                        size_t add = (size_t)cnt - 2;
                        uint32_t *nt = realloc(mesh->tri, (mesh->nt + add) * 3 * sizeof(uint32_t));
                        if (!nt) { r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path); goto fail; }
                        mesh->tri = nt;
                        for (size_t j = 0; j < add; j++) {
                            mesh->tri[3 * mesh->nt] = idx[0];
                            mesh->tri[3 * mesh->nt + 1] = idx[j + 1];
                            mesh->tri[3 * mesh->nt + 2] = idx[j + 2];
                            mesh->nt++;
                        }
                    }
                    continue;
                }
                if ((r = read_value(&cu, P->type, &v, E->name, i))) goto fail;
            }
        }
    }
    mesh->nv = c->n;
    int no_normals = 0;
    if ((have & (1 << R_NX)) && (r = zero_normals(path, c, 0, 1, warn, &no_normals, err))) goto fail;
    c->flags = vertex_flags(no_normals ? have & ~((1 << R_NX) | (1 << R_NY) | (1 << R_NZ)) : have);
    if (!(c->flags & SPR_SRC_NORMALS))
        for (size_t i = 0; i < 3 * c->n; i++) c->nrm[i] = 0.0f;
    return SPR_OK;
fail:
    spr_cloud_free(c);
    spr__mesh_free(mesh);
    return r;
}

static int write_ply_body(FILE *f, const void *user)
{
    const spr_cloud *c = user;
    fprintf(f, "ply\nformat binary_little_endian 1.0\ncomment written by splatref\nelement vertex %zu\n"
               "property float x\nproperty float y\nproperty float z\n"
               "property float nx\nproperty float ny\nproperty float nz\n"
               "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
               "property float radius\nend_header\n", c->n);
    for (size_t i = 0; i < c->n; i++) {
        unsigned char rec[6 * 4 + 4 + 4];
        float fv[6] = {c->pos[3 * i], c->pos[3 * i + 1], c->pos[3 * i + 2], c->nrm[3 * i], c->nrm[3 * i + 1], c->nrm[3 * i + 2]};
        memcpy(rec, fv, 24); /* host is little-endian (checked in CMake) */
        for (int k = 0; k < 3; k++) rec[24 + k] = (unsigned char)lrintf(c->color[3 * i + k] * 255.0f);
        rec[27] = (unsigned char)lrintf(c->alpha[i] * 255.0f);
        memcpy(rec + 28, &c->radius[i], 4);
        if (fwrite(rec, sizeof rec, 1, f) != 1) return -1;
    }
    return 0;
}

spr_result spr_write_ply(const char *path, const spr_cloud *c, spr_error *err)
{
    return spr__write_atomic(path, write_ply_body, c, err);
}

/* ---- a binary PLY read in chunks (render --stream) ---- */

typedef struct ply_source {
    char path[1024];
    FILE *f;
    ply_elem V;            /* the vertex element (lay.V points here) */
    vertex_layout lay;
    int fmt;
    uint64_t body;         /* file offset of vertex 0 */
    size_t rec;            /* bytes per vertex record */
    double opacity;        /* > 0: every splat's α (--opacity) */
    unsigned char *buf;
    size_t cap;
} ply_source;

/* Vertices [first, first + count) into out (room for the source's chunk). */
static spr_result ply_source_read(void *user, size_t first, size_t count, spr_cloud *out, spr_error *err)
{
    ply_source *ps = user;
    const size_t bytes = count * ps->rec;
    if (bytes > ps->cap) {
        unsigned char *nb = realloc(ps->buf, bytes);
        if (!nb) return spr__fail(err, SPR_E_NOMEM, "%s: out of memory for a chunk of %zu splats", ps->path, count);
        ps->buf = nb;
        ps->cap = bytes;
    }
    const uint64_t at = ps->body + (uint64_t)first * ps->rec;
    if (fseeko(ps->f, (off_t)at, SEEK_SET) || fread(ps->buf, 1, bytes, ps->f) != bytes)
        return spr__fail(err, SPR_E_IO, "%s: byte %llu: cannot read %zu vertices (the file changed or ends early)", ps->path,
                         (unsigned long long)at, count);
    out->n = count;
    spr_result r = decode_block(ps->path, ps->fmt, &ps->lay, ps->buf, bytes, (size_t)at, ps->rec, first, count, out, err);
    int none;
    if (r || (r = zero_normals(ps->path, out, first, 0, NULL, &none, err))) return r;
    out->flags = vertex_flags(ps->lay.have);
    return spr__cloud_finish(out, ps->path, first, ps->opacity, err);
}

spr_result spr_ply_source_open(const char *path, const spr_load_desc *d, size_t chunk, spr_cloud_source *src, spr_error *err)
{
    memset(src, 0, sizeof *src);
    ply_source *ps = calloc(1, sizeof *ps);
    if (!ps) return spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path);
    snprintf(ps->path, sizeof ps->path, "%s", path);
    spr_result r = SPR_OK;
    char *head = NULL;
    if (!(ps->f = fopen(path, "rb"))) { r = spr__fail(err, SPR_E_IO, "%s: cannot open: %s", path, strerror(errno)); goto fail; }
    if (fseeko(ps->f, 0, SEEK_END)) { r = spr__fail(err, SPR_E_IO, "%s: cannot seek", path); goto fail; }
    const uint64_t size = (uint64_t)ftello(ps->f);
    rewind(ps->f);
    /* the header: at most 1 MiB */
    size_t hl = size < (1u << 20) ? (size_t)size : (size_t)1 << 20;
    if (!(head = malloc(hl + 1)) || fread(head, 1, hl, ps->f) != hl) { r = spr__fail(err, SPR_E_IO, "%s: cannot read the header", path); goto fail; }
    ply_elem el[16];
    int nel = 0;
    size_t body = 0;
    if ((r = parse_header(path, head, hl, &ps->fmt, el, &nel, &body, d ? &d->warn : NULL, err))) goto fail;
    if (ps->fmt == F_ASCII) {
        r = spr__fail(err, SPR_E_FORMAT, "%s: --stream reads binary PLY files (fixed-size records); this one is ascii", path);
        goto fail;
    }
    uint64_t off = body;
    int vi = -1;
    for (int e = 0; e < nel && vi < 0; e++) {
        size_t item = 0;
        for (int k = 0; k < el[e].nprops; k++) {
            if (el[e].props[k].count_type != T_NONE) {
                r = spr__fail(err, SPR_E_FORMAT, "%s: --stream needs fixed-size records before and in the vertex element; %s has the list \"%s\"",
                              path, el[e].name, el[e].props[k].name);
                goto fail;
            }
            item += (size_t)type_size(el[e].props[k].type);
        }
        if (!strcmp(el[e].name, "vertex")) { vi = e; ps->rec = item; break; }
        off += el[e].count * (uint64_t)item;
    }
    if (vi < 0) { r = spr__fail(err, SPR_E_FORMAT, "%s: no \"vertex\" element", path); goto fail; }
    ps->V = el[vi];
    if ((r = vertex_layout_make(path, &ps->V, &ps->lay, err))) goto fail;
    if (ps->V.count == 0) { r = spr__fail(err, SPR_E_FORMAT, "%s: no points", path); goto fail; }
    if (ps->V.count > SPR_MAX_SPLATS) {
        r = spr__fail(err, SPR_E_TOO_LARGE, "%s: header declares %llu vertices (limit %u)", path, ps->V.count, SPR_MAX_SPLATS);
        goto fail;
    }
    if (off + ps->V.count * (uint64_t)ps->rec > size) {
        r = spr__fail(err, SPR_E_TRUNCATED, "%s: byte %llu: header declares %llu vertices of %zu bytes but only %llu bytes follow", path,
                      (unsigned long long)off, ps->V.count, ps->rec, (unsigned long long)(size - off));
        goto fail;
    }
    if (!(ps->lay.have & (1 << R_NX)) || !(ps->lay.have & (1 << R_RADIUS))) {
        r = spr__fail(err, SPR_E_ARG, "%s: --stream needs normals and radii in the file (this one lacks %s): computing them takes the "
                      "neighbours of every point, the whole cloud; load it without --stream", path,
                      !(ps->lay.have & (1 << R_NX)) ? (!(ps->lay.have & (1 << R_RADIUS)) ? "both" : "normals") : "radii");
        goto fail;
    }
    ps->body = off;
    ps->opacity = d ? d->opacity : 0.0;
    free(head);
    src->n = (size_t)ps->V.count;
    src->chunk = chunk ? chunk : 1u << 20;
    src->flags = vertex_flags(ps->lay.have);
    src->read = ply_source_read;
    src->user = ps;
    return SPR_OK;
fail:
    free(head);
    if (ps->f) fclose(ps->f);
    free(ps);
    return r;
}

void spr_ply_source_close(spr_cloud_source *src)
{
    ply_source *ps = src->user;
    if (ps) {
        if (ps->f) fclose(ps->f);
        free(ps->buf);
        free(ps);
    }
    memset(src, 0, sizeof *src);
}
