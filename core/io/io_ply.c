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
enum { R_NONE, R_X, R_Y, R_Z, R_NX, R_NY, R_NZ, R_R, R_G, R_B, R_A, R_RADIUS,
       R_UX, R_UY, R_UZ, R_RV,                    /* elliptical splats: major axis u, minor radius (radius = r_u) */
       R_FDC0, R_FDC1, R_FDC2, R_OPAC, R_SC0, R_SC1, R_SC2, R_ROT0, R_ROT1, R_ROT2, R_ROT3,
       R_FREST };                                 /* Gaussian splats (3DGS / 2DGS PLY) */
#define HAVE(r) (1 << (r))

static int role_of(const char *n)
{
    static const struct { const char *n; int r; } gs[] = {
        {"ux", R_UX}, {"uy", R_UY}, {"uz", R_UZ}, {"rv", R_RV}, {"ru", R_RADIUS},
        {"f_dc_0", R_FDC0}, {"f_dc_1", R_FDC1}, {"f_dc_2", R_FDC2}, {"opacity", R_OPAC},
        {"scale_0", R_SC0}, {"scale_1", R_SC1}, {"scale_2", R_SC2},
        {"rot_0", R_ROT0}, {"rot_1", R_ROT1}, {"rot_2", R_ROT2}, {"rot_3", R_ROT3}};
    for (size_t i = 0; i < sizeof gs / sizeof gs[0]; i++)
        if (strcmp(n, gs[i].n) == 0) return gs[i].r;
    if (strncmp(n, "f_rest_", 7) == 0) return R_FREST;
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
    int sub[64];  /* R_FREST: the coefficient's index in the file */
    int skip[64]; /* binary: properties k … k + skip[k] − 1 are scalars not read (0: read k) */
    size_t skip_bytes[64];
    int have;  /* bit R_* set when the role is present */
    int gauss;    /* a Gaussian-splat layout (rot_0..3, scale_0, scale_1): mapped by spr__gauss_put */
    int ellipse;  /* our elliptical splats: ux uy uz rv with radius */
    int rest;     /* f_rest_* per channel */
    spr__gauss_opts go;
} vertex_layout;

/* Fill the roles of V's properties; an error for colours of 32-bit integer type. */
static spr_result vertex_layout_make(const char *path, const ply_elem *V, const spr__gauss_opts *go, vertex_layout *L, spr_error *err)
{
    L->V = V;
    L->have = 0;
    int nrest = 0;
    for (int k = 0; k < V->nprops; k++) {
        L->role[k] = V->props[k].count_type == T_NONE ? role_of(V->props[k].name) : R_NONE;
        L->ctype[k] = V->props[k].type;
        L->sub[k] = 0;
        if (L->role[k] == R_FREST) {
            char *e;
            long j = strtol(V->props[k].name + 7, &e, 10);
            if (*e || j < 0 || j >= 45) L->role[k] = R_NONE;
            else L->sub[k] = (int)j, nrest++;
        }
        if (L->role[k]) L->have |= 1 << L->role[k];
        if ((L->role[k] >= R_R && L->role[k] <= R_A) && (L->ctype[k] == T_I32 || L->ctype[k] == T_U32))
            return spr__fail(err, SPR_E_FORMAT, "%s: colour property \"%s\" has a 32-bit integer type", path, V->props[k].name);
    }
    if ((L->have & ((1 << R_X) | (1 << R_Y) | (1 << R_Z))) != ((1 << R_X) | (1 << R_Y) | (1 << R_Z)))
        return spr__fail(err, SPR_E_FORMAT, "%s: vertex element lacks x, y or z", path);
    const int rot = HAVE(R_ROT0) | HAVE(R_ROT1) | HAVE(R_ROT2) | HAVE(R_ROT3), sc = HAVE(R_SC0) | HAVE(R_SC1);
    L->gauss = (L->have & (rot | sc)) == (rot | sc);
    if (!L->gauss && (L->have & (rot | sc | HAVE(R_SC2))))
        return spr__fail(err, SPR_E_FORMAT, "%s: vertex element has some Gaussian-splat properties but not rot_0..rot_3, scale_0 and scale_1", path);
    const int ell = HAVE(R_UX) | HAVE(R_UY) | HAVE(R_UZ) | HAVE(R_RV);
    L->ellipse = !L->gauss && (L->have & ell) == ell;
    if (L->ellipse && !(L->have & HAVE(R_RADIUS)))
        return spr__fail(err, SPR_E_FORMAT, "%s: elliptical splats (ux uy uz rv) need the major radius (radius or ru)", path);
    if (L->ellipse && !(L->have & HAVE(R_NX)))
        return spr__fail(err, SPR_E_FORMAT, "%s: elliptical splats (ux uy uz rv) need normals", path);
    L->rest = nrest % 3 == 0 && nrest <= 45 ? nrest / 3 : 0;
    if (go) L->go = *go; else spr__gauss_defaults(&L->go);
    /* runs of scalars nobody reads (f_rest_* too without --sh-degree), skipped at once in binary files */
    for (int k = V->nprops - 1; k >= 0; k--) {
        const int unread = V->props[k].count_type == T_NONE &&
                           (L->role[k] == R_NONE || (L->role[k] == R_FREST && !(L->gauss && L->go.sh_degree > 0)));
        L->skip[k] = unread ? 1 + (k + 1 < V->nprops ? L->skip[k + 1] : 0) : 0;
        L->skip_bytes[k] = unread ? (size_t)type_size(V->props[k].type) + (k + 1 < V->nprops ? L->skip_bytes[k + 1] : 0) : 0;
    }
    return SPR_OK;
}

/* The one decoding of a Gaussian-splat vertex's values (3DGS: f_dc, opacity
 * before the sigmoid, log scales, rot = w x y z), then the one mapping. */
static spr_result gauss_vertex(const char *path, const vertex_layout *L, const double *val, spr_cloud *c, size_t s, unsigned long long i,
                               spr_error *err)
{
    spr__gauss g;
    const int have = L->have;
    for (int k = 0; k < 3; k++) {
        g.pos[k] = val[R_X + k];
        g.sigma[k] = k == 2 && !(have & HAVE(R_SC2)) ? -1.0 : exp(val[R_SC0 + k]);
        g.rgb[k] = have & HAVE(R_FDC0 + k) ? 0.5 + SPR__SH_C0 * val[R_FDC0 + k]
                   : have & HAVE(R_R + k)  ? val[R_R + k]
                                           : 0.5;
    }
    for (int k = 0; k < 4; k++) g.q[k] = val[R_ROT0 + k];
    g.alpha = have & HAVE(R_OPAC) ? spr__sigmoid(val[R_OPAC]) : have & HAVE(R_A) ? val[R_A] : 1.0;
    if (c->sh) {
        float *sh = c->sh + s * (size_t)c->sh_k * 3;
        for (int ch = 0; ch < 3; ch++) sh[ch] = have & HAVE(R_FDC0 + ch) ? (float)val[R_FDC0 + ch] : (float)((g.rgb[ch] - 0.5) / SPR__SH_C0);
    }
    spr_error e;
    if (spr__gauss_put(&g, &L->go, c, s, path, (size_t)i, &e)) return spr__fail(err, SPR_E_VALUE, "%s", e.msg);
    return SPR_OK;
}

/* Our elliptical splats: u renormalised; r_v > r_u swaps the axes (u ← n × u). */
static spr_result ellipse_vertex(const char *path, const double *val, spr_cloud *c, size_t s, unsigned long long i, spr_error *err)
{
    float *e = c->ell + 4 * s;
    double u[3] = {val[R_UX], val[R_UY], val[R_UZ]}, rv = val[R_RV], r = c->radius[s];
    if (!(rv > 0.0) || !isfinite(rv)) return spr__fail(err, SPR_E_VALUE, "%s: vertex %llu: rv %g is not positive and finite", path, i, rv);
    const float *n = c->nrm + 3 * s;
    if (rv > r) {
        double t[3] = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
        memcpy(u, t, sizeof u);
        c->radius[s] = (float)rv;
        rv = r;
    }
    if (rv == r) { /* a circle */
        e[0] = e[1] = e[2] = 0.0f;
        e[3] = c->radius[s];
        return SPR_OK;
    }
    const double un = u[0] * n[0] + u[1] * n[1] + u[2] * n[2]; /* into the splat's plane */
    for (int k = 0; k < 3; k++) u[k] -= un * n[k];
    double l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (!(l > 1e-6) || !isfinite(l))
        return spr__fail(err, SPR_E_VALUE, "%s: vertex %llu: axis ux uy uz is zero, not finite or along the normal", path, i);
    for (int k = 0; k < 3; k++) e[k] = (float)(u[k] / l);
    e[3] = (float)rv;
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
    double val[R_FREST + 1] = {0};
    for (int k = 0; k < V->nprops; k++) {
        const ply_prop *P = &V->props[k];
        const int role = L->role[k];
        double v;
        if (cu->fmt != F_ASCII && L->skip[k]) { /* a run of unread scalars: skipped at once */
            if ((size_t)(cu->end - cu->p) < L->skip_bytes[k])
                return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: file ends inside %s %llu", path, cursor_at(cu, 0), V->name, i);
            cu->p += L->skip_bytes[k];
            k += L->skip[k] - 1;
            continue;
        }
        if (P->count_type != T_NONE) { /* a list in the vertex element: read past it */
            double cnt;
            if ((r = read_value(cu, P->count_type, &cnt, V->name, i))) return r;
            if (!(cnt >= 0 && cnt <= 1024) || cnt != floor(cnt))
                return spr__fail(err, SPR_E_FORMAT, "%s: %s %llu: list length %g is not a whole number in 0..1024", path, V->name, i, cnt);
            for (int j = 0; j < (int)cnt; j++)
                if ((r = read_value(cu, P->type, &v, V->name, i))) return r;
            continue;
        }
        if (cu->fmt == F_LE && P->type == T_F32 && cu->end - cu->p >= 4) { /* the common case inline: read_value's value (host little-endian) */
            float f;
            memcpy(&f, cu->p, 4);
            cu->p += 4;
            v = f;
        } else if ((r = read_value(cu, P->type, &v, V->name, i))) {
            return r;
        }
        if (role && !spr__finite_float(v)) /* checked as the float it becomes: 1e300 is a finite double */
            return cu->fmt == F_ASCII
                       ? spr__fail(err, SPR_E_VALUE, "%s:%zu: vertex %llu: %s %s (%g) is not a finite 32-bit float", path, cu->line, i,
                                   role <= R_Z ? "coordinate" : "property", P->name, v)
                       : spr__fail(err, SPR_E_VALUE, "%s: byte %zu: vertex %llu: %s %s (%g) is not a finite 32-bit float", path,
                                   cursor_at(cu, type_size(P->type)), i, role <= R_Z ? "coordinate" : "property", P->name, v);
        if (role >= R_UX) {
            if (role == R_FREST) {
                const int ch = L->rest ? L->sub[k] / L->rest : 3, kk = L->rest ? 1 + L->sub[k] % L->rest : 0;
                if (c->sh && ch < 3 && kk < c->sh_k) c->sh[(s * (size_t)c->sh_k + (size_t)kk) * 3 + (size_t)ch] = (float)v;
            } else {
                val[role] = v;
            }
            continue;
        }
        if (L->gauss) { /* positions and colours go through the mapping */
            val[role] = role >= R_R && role <= R_A ? v * color_scale(L->ctype[k]) : v;
            continue;
        }
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
    if (L->gauss) return gauss_vertex(path, L, val, c, s, i, err);
    float *n = c->nrm + 3 * s;
    if ((L->have & (1 << R_NX)) && !(n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f) && spr__normalize3(n))
        return spr__fail(err, SPR_E_VALUE, "%s: vertex %llu: zero or non-finite normal", path, i);
    if (L->ellipse) {
        if (n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f)
            return spr__fail(err, SPR_E_VALUE, "%s: vertex %llu: an elliptical splat needs a normal", path, i);
        return ellipse_vertex(path, val, c, s, i, err);
    }
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
static size_t item_bytes(const ply_elem *E);
static size_t fixed_record(int fmt, const ply_elem *V) { return fmt == F_ASCII ? 0 : item_bytes(V); }

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

/* Index of property `name` in E, −1 when absent or not of type t. */
static int prop_index(const ply_elem *E, const char *name, ply_type t)
{
    for (int k = 0; k < E->nprops; k++)
        if (!strcmp(E->props[k].name, name)) return E->props[k].type == t && E->props[k].count_type == T_NONE ? k : -1;
    return -1;
}

/* Byte offset of property k in an item of E (binary, scalars before k). */
static size_t prop_offset(const ply_elem *E, int k)
{
    size_t b = 0;
    for (int j = 0; j < k; j++) b += (size_t)type_size(E->props[j].type);
    return b;
}

/* Bytes of one item of E (binary, scalars only); 0 when E has a list. */
static size_t item_bytes(const ply_elem *E)
{
    for (int k = 0; k < E->nprops; k++)
        if (E->props[k].count_type != T_NONE) return 0;
    return prop_offset(E, E->nprops);
}

static double unorm(uint32_t v, int shift, int bits) { return (double)((v >> shift) & ((1u << bits) - 1u)) / (double)((1u << bits) - 1u); }
static double lerp(double a, double b, double t) { return a * (1.0 - t) + b * t; }

/* Where a compressed PLY's values are: element starts, item sizes, and
 * the byte offsets of the properties read in chunk, vertex and sh items. */
typedef struct cply_layout {
    const unsigned char *chunk, *vertex, *sh;
    size_t cb, vb, sb;
    size_t cofs[18], vofs[4], sofs[45];
    int have_c[18];
    int colour_bounds, per, sh_k;  /* colour lerped by the chunk's bounds; f_rest per channel; SH kept */
} cply_layout;

static void cply_splat(const void *user, size_t i, spr__gauss *g, float *sh)
{
    const cply_layout *L = user;
    const unsigned char *ch = L->chunk + (i / 256) * L->cb, *vx = L->vertex + i * L->vb;
    float cf[18];
    uint32_t pv[4];
    for (int k = 0; k < 18; k++) {
        if (L->have_c[k]) memcpy(&cf[k], ch + L->cofs[k], 4); else cf[k] = 0.0f;
    }
    for (int k = 0; k < 4; k++) memcpy(&pv[k], vx + L->vofs[k], 4);
    for (int k = 0; k < 3; k++) {
        const int shift = k == 0 ? 21 : k == 1 ? 11 : 0, bits = k == 1 ? 10 : 11;
        g->pos[k] = lerp(cf[k], cf[3 + k], unorm(pv[0], shift, bits));
        g->sigma[k] = exp(lerp(cf[6 + k], cf[9 + k], unorm(pv[2], shift, bits)));
        const double t = unorm(pv[3], 24 - 8 * k, 8);
        g->rgb[k] = L->colour_bounds ? lerp(cf[12 + k], cf[15 + k], t) : t;
    }
    g->alpha = unorm(pv[3], 0, 8);
    const int big = (int)(pv[1] >> 30);
    const double norm = 1.0 / (sqrt(2.0) * 0.5);
    double o3[3] = {(unorm(pv[1], 20, 10) - 0.5) * norm, (unorm(pv[1], 10, 10) - 0.5) * norm, (unorm(pv[1], 0, 10) - 0.5) * norm};
    double s2 = o3[0] * o3[0] + o3[1] * o3[1] + o3[2] * o3[2];
    for (int k = 0, j = 0; k < 4; k++) g->q[k] = k == big ? sqrt(s2 < 1.0 ? 1.0 - s2 : 0.0) : o3[j++]; /* rot_0..3 = w x y z */
    if (sh) {
        for (int chn = 0; chn < 3; chn++) sh[chn] = (float)((g->rgb[chn] - 0.5) / SPR__SH_C0);
        const unsigned char *sv = L->sh_k > 1 ? L->sh + i * L->sb : NULL; /* no sh element: DC only */
        for (int k = 1; k < L->sh_k; k++)
            for (int chn = 0; chn < 3; chn++) {
                const unsigned v = sv[L->sofs[chn * L->per + k - 1]];
                const double t = v == 0 ? 0.0 : v == 255 ? 1.0 : (v + 0.5) / 256.0;
                sh[3 * k + chn] = (float)((t - 0.5) * 8.0);
            }
    }
}

/* The compressed PLY of PlayCanvas SuperSplat / splat-transform: `element
 * chunk` (per 256 splats: float bounds of position, log scale and colour),
 * `element vertex` of packed uint32 position (11-10-11 bits), rotation
 * (2-bit index of the largest component, three 10-bit others), scale
 * (11-10-11) and colour (RGBA 8888), optional `element sh` of uchar
 * f_rest_*.  Binary little-endian only, as its writer writes it. */
static spr_result spr__parse_compressed_ply(const char *path, const char *buf, size_t len, size_t body, int fmt, const ply_elem *el, int nel,
                                   const spr__gauss_opts *go, spr_cloud *c, spr_error *err)
{
    static const char *const cn[] = {"min_x", "min_y", "min_z", "max_x", "max_y", "max_z", "min_scale_x", "min_scale_y", "min_scale_z",
                                     "max_scale_x", "max_scale_y", "max_scale_z", "min_r", "min_g", "min_b", "max_r", "max_g", "max_b"};
    static const char *const vn[] = {"packed_position", "packed_rotation", "packed_scale", "packed_color"};
    if (fmt != F_LE) return spr__fail(err, SPR_E_FORMAT, "%s: a compressed PLY (element chunk) must be binary_little_endian", path);
    const ply_elem *C = NULL, *V = NULL, *S = NULL;
    size_t off[16], at = body;
    for (int e = 0; e < nel; e++) {
        const size_t ib = item_bytes(&el[e]);
        if (!ib && el[e].count) return spr__fail(err, SPR_E_FORMAT, "%s: compressed PLY element \"%s\" has a list property", path, el[e].name);
        off[e] = at;
        if (el[e].count > (len - at) / (ib ? ib : 1))
            return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: element \"%s\" declares %llu items of %zu bytes but only %zu bytes follow", path, at,
                             el[e].name, el[e].count, ib, len - at);
        at += (size_t)el[e].count * ib;
        if (!strcmp(el[e].name, "chunk")) C = &el[e];
        else if (!strcmp(el[e].name, "vertex")) V = &el[e];
        else if (!strcmp(el[e].name, "sh")) S = &el[e];
    }
    int ci[18], vi[4], si[45] = {0};
    const int colour_bounds = prop_index(C, "min_r", T_F32) >= 0;
    for (int k = 0; k < 18; k++)
        if ((ci[k] = prop_index(C, cn[k], T_F32)) < 0 && (k < 12 || colour_bounds))
            return spr__fail(err, SPR_E_FORMAT, "%s: compressed PLY: element chunk lacks float %s", path, cn[k]);
    for (int k = 0; k < 4; k++)
        if ((vi[k] = prop_index(V, vn[k], T_U32)) < 0)
            return spr__fail(err, SPR_E_FORMAT, "%s: compressed PLY: element vertex lacks uint %s", path, vn[k]);
    int nsh = 0;
    if (S) {
        nsh = S->nprops;
        if (S->count != V->count || (nsh != 9 && nsh != 24 && nsh != 45))
            return spr__fail(err, SPR_E_FORMAT, "%s: compressed PLY: element sh needs one item per vertex and 9, 24 or 45 properties", path);
        for (int k = 0; k < nsh; k++) {
            char nm[24];
            snprintf(nm, sizeof nm, "f_rest_%d", k);
            if ((si[k] = prop_index(S, nm, T_U8)) < 0) return spr__fail(err, SPR_E_FORMAT, "%s: compressed PLY: element sh lacks uchar %s", path, nm);
        }
    }
    const size_t n = (size_t)V->count;
    if (n == 0) return spr__fail(err, SPR_E_FORMAT, "%s: no points", path);
    if (n > SPR_MAX_SPLATS) return spr__fail(err, SPR_E_TOO_LARGE, "%s: header declares %zu vertices (limit %u)", path, n, SPR_MAX_SPLATS);
    if (C->count < (n + 255) / 256)
        return spr__fail(err, SPR_E_FORMAT, "%s: compressed PLY: %llu chunks for %zu vertices (256 per chunk)", path, C->count, n);
    spr_result r = spr__gauss_alloc(c, n, 1 + nsh / 3, go, path, err);
    if (r) return r;
    const int Ci = (int)(C - el), Vi = (int)(V - el), Si = S ? (int)(S - el) : 0;
    cply_layout L = {(const unsigned char *)buf + off[Ci], (const unsigned char *)buf + off[Vi], S ? (const unsigned char *)buf + off[Si] : NULL,
                     item_bytes(C), item_bytes(V), S ? item_bytes(S) : 0, {0}, {0}, {0}, {0}, colour_bounds, nsh / 3, c->sh_k};
    for (int k = 0; k < 18; k++) L.cofs[k] = ci[k] >= 0 ? prop_offset(C, ci[k]) : 0, L.have_c[k] = ci[k] >= 0;
    for (int k = 0; k < 4; k++) L.vofs[k] = prop_offset(V, vi[k]);
    for (int k = 0; k < nsh; k++) L.sofs[k] = prop_offset(S, si[k]);
    return spr__gauss_fill(c, go, cply_splat, &L, path, err);
}

spr_result spr__parse_ply(const char *path, const char *buf, size_t len, spr_cloud *c, spr__mesh *mesh, const spr_progress *prog,
                          const spr_warn *warn, const spr__gauss_opts *go, spr_error *err)
{
    return spr__parse_ply_blocks(path, buf, len, c, mesh, prog, warn, go, SPR__PLY_BLOCK, err);
}

spr_result spr__parse_ply_blocks(const char *path, const char *buf, size_t len, spr_cloud *c, spr__mesh *mesh, const spr_progress *prog,
                                 const spr_warn *warn, const spr__gauss_opts *go, size_t block, spr_error *err)
{
    if (!block) block = SPR__PLY_BLOCK;
    spr_result r;
    int fmt = F_ASCII, nel = 0;
    ply_elem el[16];
    size_t body = 0;
    spr__gauss_opts go_default;
    if (!go) spr__gauss_defaults(&go_default), go = &go_default;
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
    for (int e = 0; e < nel; e++)
        if (!strcmp(el[e].name, "chunk") && prop_index(V, "packed_position", T_U32) >= 0)
            return spr__parse_compressed_ply(path, buf, len, body, fmt, el, nel, go, c, err);
    vertex_layout lay;
    if ((r = vertex_layout_make(path, V, go, &lay, err))) goto fail;
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
    if (lay.gauss) {
        if ((r = spr__gauss_alloc(c, (size_t)V->count, 1 + lay.rest, &lay.go, path, err))) goto fail;
    } else {
        r = spr_cloud_alloc(c, (size_t)V->count);
        if (!r && lay.ellipse) r = spr_cloud_alloc_ell(c);
        if (r) { spr__fail(err, r, "%s: cannot allocate %llu splats", path, V->count); goto fail; }
    }
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
            for (size_t first = 0; first < (size_t)E->count; first += block) {
                const size_t m = (size_t)E->count - first < block ? (size_t)E->count - first : block;
                spr_progress_report(prog, "reading vertices", first, (size_t)E->count);
                spr_cloud part = spr_cloud_view(c, first, m);
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
                        if (spr__mesh_fan(mesh, idx, (int)cnt)) { r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path); goto fail; }
                    }
                    continue;
                }
                if ((r = read_value(&cu, P->type, &v, E->name, i))) goto fail;
            }
        }
    }
    mesh->nv = c->n;
    int no_normals = 0;
    if (lay.gauss) return SPR_OK; /* flags set by spr__gauss_alloc */
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
               "property float radius\n%send_header\n", c->n,
            c->ell ? "property float ux\nproperty float uy\nproperty float uz\nproperty float rv\n" : "");
    for (size_t i = 0; i < c->n; i++) {
        unsigned char rec[6 * 4 + 4 + 4 + 16];
        const size_t rl = c->ell ? sizeof rec : sizeof rec - 16;
        if (c->ell) memcpy(rec + 32, c->ell + 4 * i, 16); /* ellipses: u, r_v (a circle: 0 0 0 radius) */
        float fv[6] = {c->pos[3 * i], c->pos[3 * i + 1], c->pos[3 * i + 2], c->nrm[3 * i], c->nrm[3 * i + 1], c->nrm[3 * i + 2]};
        memcpy(rec, fv, 24); /* host is little-endian (checked in CMake) */
        for (int k = 0; k < 3; k++) rec[24 + k] = (unsigned char)lrintf(c->color[3 * i + k] * 255.0f);
        rec[27] = (unsigned char)lrintf(c->alpha[i] * 255.0f);
        memcpy(rec + 28, &c->radius[i], 4);
        if (fwrite(rec, rl, 1, f) != 1) return -1;
    }
    return 0;
}

spr_result spr_write_ply(const char *path, const spr_cloud *c, spr_error *err)
{
    return spr__write_atomic(path, write_ply_body, c, err);
}

/* The 3DGS layout of the training code's save_ply (FORMATS.md): x y z, nx ny nz (zero),
 * f_dc_0..2, f_rest_* channel-major (all of red, then green, then blue), opacity (logit),
 * scale_0..2 (log), rot_0..3 (w x y z); every value written as given. */
static int write_gauss_body(FILE *f, const void *user)
{
    const spr_gauss_file *g = user;
    const int rest = g->sh_k > 1 ? g->sh_k - 1 : 0;
    fprintf(f, "ply\nformat binary_little_endian 1.0\ncomment written by splatref (3D Gaussian splatting layout)\nelement vertex %zu\n"
               "property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
               "property float f_dc_0\nproperty float f_dc_1\nproperty float f_dc_2\n", g->n);
    for (int k = 0; k < 3 * rest; k++) fprintf(f, "property float f_rest_%d\n", k);
    fprintf(f, "property float opacity\nproperty float scale_0\nproperty float scale_1\nproperty float scale_2\n"
               "property float rot_0\nproperty float rot_1\nproperty float rot_2\nproperty float rot_3\nend_header\n");
    float *rec = malloc((size_t)(17 + 3 * rest) * sizeof *rec);
    if (!rec) return -1;
    int bad = 0;
    for (size_t i = 0; i < g->n && !bad; i++) {
        int k = 0;
        for (int a = 0; a < 3; a++) rec[k++] = g->pos[3 * i + a];
        for (int a = 0; a < 3; a++) rec[k++] = 0.0f;
        const float *sh = g->sh + i * (size_t)g->sh_k * 3;
        for (int ch = 0; ch < 3; ch++) rec[k++] = sh[ch];
        for (int ch = 0; ch < 3; ch++)
            for (int j = 1; j <= rest; j++) rec[k++] = sh[3 * j + ch];
        rec[k++] = g->opacity_logit[i];
        for (int a = 0; a < 3; a++) rec[k++] = g->log_scale[3 * i + a];
        for (int a = 0; a < 4; a++) rec[k++] = g->rot[4 * i + a];
        bad = fwrite(rec, sizeof *rec, (size_t)k, f) != (size_t)k;
    }
    free(rec);
    return bad ? -1 : 0;
}

spr_result spr_write_gauss_ply(const char *path, const spr_gauss_file *g, spr_error *err)
{
    if (g->sh_k < 1 || g->sh_k > 16) return spr__fail(err, SPR_E_ARG, "%s: %d SH coefficients a channel (1 … 16)", path, g->sh_k);
    return spr__write_atomic(path, write_gauss_body, g, err);
}

spr_result spr_write_gauss_ply_of_cloud(const char *path, const spr_cloud *c, uint64_t seed, spr_error *err)
{
    const size_t n = c->n ? c->n : 1;
    float *sh = malloc(n * 16 * 3 * sizeof *sh), *lg = malloc(n * sizeof *lg), *ls = malloc(n * 3 * sizeof *ls), *rt = malloc(n * 4 * sizeof *rt);
    spr_result r = sh && lg && ls && rt ? SPR_OK : spr__fail(err, SPR_E_NOMEM, "%s: out of memory for %zu Gaussians", path, c->n);
    for (size_t i = 0; !r && i < c->n; i++) {
        double q[4], ru, rv;
        spr__surfel_frame(c, i, q, &ru, &rv);
        for (int k = 0; k < 4; k++) rt[4 * i + k] = (float)q[k];
        ls[3 * i] = (float)log(ru / 3.0), ls[3 * i + 1] = (float)log(rv / 3.0), ls[3 * i + 2] = (float)log(ru / 300.0);
        const double a = c->alpha[i] < 0.999 ? c->alpha[i] : 0.999;
        lg[i] = (float)log(a / (1.0 - a));
        float *s = sh + 48 * i;
        for (int ch = 0; ch < 3; ch++) s[ch] = (float)((c->color[3 * i + ch] - 0.5) / SPR__SH_C0);
        for (int k = 3; k < 48; k++) s[k] = seed ? (float)(0.4 * (spr__uniform01(&seed) - 0.5)) : 0.0f;
    }
    const spr_gauss_file g = {c->n, c->pos, sh, lg, ls, rt, 16};
    if (!r) r = spr_write_gauss_ply(path, &g, err);
    free(sh), free(lg), free(ls), free(rt);
    return r;
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
    if ((r = vertex_layout_make(path, &ps->V, NULL, &ps->lay, err))) goto fail;
    if (ps->lay.gauss || ps->lay.ellipse) {
        r = spr__fail(err, SPR_E_ARG, "%s: --stream reads circular splats; this file holds %s: load it without --stream", path,
                      ps->lay.gauss ? "Gaussian splats" : "elliptical splats");
        goto fail;
    }
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
