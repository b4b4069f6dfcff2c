/* io_gauss.c — Gaussian-splat captures as elliptical surfels (issue 15):
 * the one mapping from a 3D (or 2D) Gaussian to a splat, and the readers
 * of `.splat`, `.spz` (versions 1–4) and `.glb` (KHR_gaussian_splatting).  The PLY layouts
 * (3DGS, 2DGS, compressed) are read in io_ply.c and mapped here.
 *
 * Written here rather than taken from a library: none of these readers is
 * packaged in Debian; zlib (versions 1–3) and zstd (version 4) inflate
 * `.spz`, and cJSON parses the glTF JSON.
 * The layouts were learnt from their sources (../shared/FORMATS.md) and
 * are described, with the mapping and its reasoning, in docs/formats.md.
 */
#include "spr_io.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>
#include <zstd.h>

void spr__gauss_defaults(spr__gauss_opts *o)
{
    o->cut = 3.0;
    o->sh_degree = 0;
    o->spz_raw = 0;
}

spr_result spr__gauss_alloc(spr_cloud *c, size_t n, int file_k, const spr__gauss_opts *o, const char *path, spr_error *err)
{
    spr_result r = spr_cloud_alloc(c, n);
    if (!r) r = spr_cloud_alloc_ell(c);
    const int want = (o->sh_degree + 1) * (o->sh_degree + 1);
    c->sh_k = file_k < want ? file_k : want; /* the DC term at least: the Gaussian algorithms' colour, unclamped */
    if (c->sh_k < 1) c->sh_k = 1;
    if (!r && !(c->sh = calloc((n ? n : 1) * (size_t)c->sh_k * 3, sizeof(float)))) r = SPR_E_NOMEM;
    if (!r && !(c->gauss = malloc((n ? n : 1) * SPR_GAUSS_FLOATS * sizeof(float)))) r = SPR_E_NOMEM;
    if (r) {
        spr_cloud_free(c);
        return spr__fail(err, r, "%s: cannot allocate %zu Gaussian splats", path, n);
    }
    c->flags = SPR_SRC_NORMALS | SPR_SRC_COLORS | SPR_SRC_RADII | SPR_SRC_ALPHA;
    c->gauss_cut = (float)o->cut;
    return SPR_OK;
}

double spr__sigmoid(double x) { return x >= 0.0 ? 1.0 / (1.0 + exp(-x)) : exp(x) / (1.0 + exp(x)); }

/* A Gaussian given in a frame whose axes are the training frame's with some
 * reversed (f[k] = −1: axis k reversed; a proper rotation, two of them) into
 * the training frame: the centre's coordinates flipped, the quaternion
 * conjugated (x, y, z times f_y·f_z, f_x·f_z, f_x·f_y) and every SH
 * coefficient beyond DC times the sign its basis function takes, the product
 * of f over its factors x, y, z (sh_k coefficients of 3 channels). */
static void gauss_flip(spr__gauss *g, float *sh, int sh_k, const double f[3])
{
    for (int k = 0; k < 3; k++) g->pos[k] *= f[k];
    g->q[1] *= f[1] * f[2], g->q[2] *= f[0] * f[2], g->q[3] *= f[0] * f[1];
    const double x = f[0], y = f[1], z = f[2];
    const double sign[16] = {1, y, z, x, x * y, y * z, 1, x * z, 1, y, x * y * z, y, z, x, z, x};
    for (int k = 1; sh && k < sh_k && k < 16; k++)
        for (int ch = 0; ch < 3; ch++) sh[3 * k + ch] *= (float)sign[k];
}

spr_result spr__gauss_put(const spr__gauss *g, const spr__gauss_opts *o, spr_cloud *c, size_t s, const char *path, size_t index,
                          spr_error *err)
{
    for (int k = 0; k < 3; k++)
        if (!spr__finite_float(g->pos[k]))
            return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: coordinate %c (%g) is not a finite 32-bit float", path, index, "xyz"[k], g->pos[k]);
    const int ns = g->sigma[2] < 0.0 ? 2 : 3;
    for (int k = 0; k < ns; k++)
        if (!(g->sigma[k] > 0.0) || !isfinite(g->sigma[k]))
            return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: scale %d (σ = %g) is not positive and finite", path, index, k, g->sigma[k]);
    double w = g->q[0], x = g->q[1], y = g->q[2], z = g->q[3];
    double l = sqrt(w * w + x * x + y * y + z * z);
    if (!(l > 0.0) || !isfinite(l))
        return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: rotation quaternion is zero or not finite", path, index);
    w /= l, x /= l, y /= l, z /= l;
    /* columns of R: the Gaussian's local axes in the world */
    const double R[3][3] = {{1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y)},
                            {2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x)},
                            {2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)}};
    /* the surfel spans the two largest axes (a 2D Gaussian: its two), largest first; ties by axis */
    int a = 0, b = 1;
    if (ns == 3) {
        int ord[3] = {0, 1, 2};
        for (int i = 1; i < 3; i++)
            for (int j = i; j > 0 && g->sigma[ord[j]] > g->sigma[ord[j - 1]]; j--) {
                int t = ord[j];
                ord[j] = ord[j - 1];
                ord[j - 1] = t;
            }
        a = ord[0], b = ord[1];
    } else if (g->sigma[1] > g->sigma[0]) {
        a = 1, b = 0;
    }
    if (c->gauss) { /* the whole Gaussian (SPEC §10.1), beside the surfel below */
        float *G = c->gauss + SPR_GAUSS_FLOATS * s;
        G[0] = (float)w, G[1] = (float)x, G[2] = (float)y, G[3] = (float)z, G[7] = (float)l;
        for (int k = 0; k < 3; k++) {
            const double sg = k < ns ? g->sigma[k] : 0.0;
            G[4 + k] = (float)sg;
            if (k < ns && (!(G[4 + k] > 0.0f) || !isfinite(G[4 + k])))
                return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: scale %d (σ = %g) does not fit a 32-bit float", path, index, k, sg);
        }
    }
    const double *u = R[a], *v = R[b];
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]}; /* n = u × v */
    const double ru = o->cut * g->sigma[a], rv = o->cut * g->sigma[b];
    if (!((float)ru > 0.0f) || !isfinite((float)ru) || !((float)rv > 0.0f))
        return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: radii %g × %g do not fit a 32-bit float", path, index, ru, rv);
    if (!(g->alpha >= 0.0 && g->alpha <= 1.0))
        return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: opacity %g is outside [0,1]", path, index, g->alpha);
    for (int k = 0; k < 3; k++) {
        if (!isfinite(g->rgb[k])) return spr__fail(err, SPR_E_VALUE, "%s: splat %zu: colour is not finite", path, index);
        c->pos[3 * s + k] = (float)g->pos[k];
        c->nrm[3 * s + k] = (float)n[k];
        c->ell[4 * s + k] = (float)u[k];
        c->color[3 * s + k] = (float)(g->rgb[k] < 0.0 ? 0.0 : g->rgb[k] > 1.0 ? 1.0 : g->rgb[k]);
    }
    spr__normalize3(c->nrm + 3 * s);
    spr__normalize3(c->ell + 4 * s);
    c->radius[s] = (float)ru;
    c->ell[4 * s + 3] = (float)rv;
    c->alpha[s] = (float)g->alpha;
    return SPR_OK;
}

spr_result spr__gauss_fill(spr_cloud *c, const spr__gauss_opts *o, spr__gauss_decode decode, const void *user, const char *path,
                           spr_error *err)
{
    long bad = -1;
    spr_error first = {0};
#pragma omp parallel for schedule(static)
    for (long i = 0; i < (long)c->n; i++) {
        spr__gauss g;
        decode(user, (size_t)i, &g, c->sh ? c->sh + (size_t)i * (size_t)c->sh_k * 3 : NULL);
        spr_error e;
        if (spr__gauss_put(&g, o, c, (size_t)i, path, (size_t)i, &e)) {
#pragma omp critical(spr_gauss_bad)
            if (bad < 0 || i < bad) bad = i, first = e; /* the lowest bad splat's message, for any thread count */
        }
    }
    if (bad < 0) return SPR_OK;
    spr_cloud_free(c);
    return spr__fail(err, SPR_E_VALUE, "%s", first.msg);
}

/* ---- .splat: 32-byte records (antimatter15's viewer, converters) ---- */

static float le_f32(const unsigned char *p)
{
    float f;
    memcpy(&f, p, 4); /* host is little-endian (checked in CMake) */
    return f;
}

/* One 32-byte record: position f32×3, σ f32×3 (linear), RGBA u8×4 (colour
 * and α as they are), rotation u8×4 (w x y z as (b − 128)/128). */
static void splat_record(const void *user, size_t i, spr__gauss *g, float *sh)
{
    const unsigned char *rec = (const unsigned char *)user + 32 * i;
    for (int k = 0; k < 3; k++) {
        g->pos[k] = le_f32(rec + 4 * k);
        g->sigma[k] = le_f32(rec + 12 + 4 * k);
        g->rgb[k] = rec[24 + k] / 255.0;
        if (sh) sh[k] = (float)((g->rgb[k] - 0.5) / SPR__SH_C0); /* colours only: the DC term that gives them */
    }
    g->alpha = rec[27] / 255.0;
    for (int k = 0; k < 4; k++) g->q[k] = ((double)rec[28 + k] - 128.0) / 128.0;
}

spr_result spr__parse_splat(const char *path, const char *buf, size_t len, const spr__gauss_opts *o, spr_cloud *c, spr_error *err)
{
    memset(c, 0, sizeof *c);
    if (len == 0) return spr__fail(err, SPR_E_FORMAT, "%s: no points", path);
    if (len % 32)
        return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: %zu bytes are not whole 32-byte .splat records (the last one ends early)", path,
                         len - len % 32, len);
    const size_t n = len / 32;
    if (n > SPR_MAX_SPLATS) return spr__fail(err, SPR_E_TOO_LARGE, "%s: %zu splats (limit %u)", path, n, SPR_MAX_SPLATS);
    spr_result r = spr__gauss_alloc(c, n, 1, o, path, err); /* one coefficient: colours only */
    return r ? r : spr__gauss_fill(c, o, splat_record, buf, path, err);
}

/* ---- .spz: gzip, fixed point (Niantic's library, converters; versions 1–3) ---- */

/* The uncompressed stream, at most `cap` bytes: SPR_E_FORMAT when it is no gzip stream. */
static spr_result inflate_all(const char *path, const char *buf, size_t len, size_t cap, unsigned char **out, size_t *out_len,
                              spr_error *err)
{
    *out = NULL;
    *out_len = 0;
    z_stream zs;
    memset(&zs, 0, sizeof zs);
    if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) return spr__fail(err, SPR_E_NOMEM, "%s: cannot start inflating", path);
    size_t size = 0, room = len * 4 + 4096;
    if (room > cap) room = cap;
    unsigned char *o = malloc(room ? room : 1);
    spr_result r = SPR_OK;
    zs.next_in = (unsigned char *)buf;
    for (;;) {
        if (!o) { r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory inflating", path); break; }
        if (zs.avail_in == 0) { /* zlib takes at most 4 GiB at a time (uInt): a larger file is fed on */
            const size_t left = len - (size_t)(zs.next_in - (unsigned char *)buf);
            zs.avail_in = (uInt)(left < UINT32_MAX ? left : UINT32_MAX);
        }
        if (size == room) {
            if (room == cap) { r = spr__fail(err, SPR_E_TOO_LARGE, "%s: inflates to more than the %zu bytes its header allows", path, cap); break; }
            size_t nr = room * 2 < cap ? room * 2 : cap;
            unsigned char *no = realloc(o, nr);
            if (!no) { r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory inflating", path); break; }
            o = no, room = nr;
        }
        zs.next_out = o + size;
        zs.avail_out = (uInt)(room - size < UINT32_MAX ? room - size : UINT32_MAX);
        int z = inflate(&zs, Z_NO_FLUSH);
        size = (size_t)(zs.next_out - o);
        if (z == Z_STREAM_END) break;
        if (z == Z_OK || (z == Z_BUF_ERROR && zs.avail_out == 0)) continue;
        r = z == Z_BUF_ERROR ? spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: the gzip stream ends early", path, (size_t)(zs.next_in - (unsigned char *)buf))
                             : spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: not a valid gzip stream (%s)", path,
                                         (size_t)(zs.next_in - (unsigned char *)buf), zs.msg ? zs.msg : "inflate failed");
        break;
    }
    inflateEnd(&zs);
    if (r) { free(o); return r; }
    *out = o;
    *out_len = size;
    return SPR_OK;
}

/* The arrays of an inflated .spz, one after another: positions, alphas,
 * colours, scales, rotations, SH. */
typedef struct spz_layout {
    const unsigned char *P;     /* the first array */
    size_t n;
    uint32_t version;
    int frac;
    size_t qb, dim;             /* rotation bytes, SH coefficients per channel beyond DC */
    int sh_k;
    int antialiased;            /* header flag 1 */
    int raw;                    /* --spz-frame raw: the data taken in the frame it is stored in */
} spz_layout;

static void spz_splat(const void *user, size_t i, spr__gauss *g, float *sh)
{
    const spz_layout *L = user;
    const size_t n = L->n;
    const unsigned char *P = L->P, *A = P + n * (L->version == 1 ? 6 : 9), *C = A + n, *S = C + 3 * n, *Q = S + 3 * n, *H = Q + L->qb * n;
    for (int k = 0; k < 3; k++) {
        if (L->version == 1) { /* half floats */
            uint16_t h = (uint16_t)(P[6 * i + 2 * (size_t)k] | P[6 * i + 2 * (size_t)k + 1] << 8);
            int e = h >> 10 & 31, m = h & 1023;
            double v = e == 0 ? ldexp(m, -24) : e == 31 ? (m ? NAN : INFINITY) : ldexp(m + 1024, e - 25);
            g->pos[k] = h & 0x8000 ? -v : v;
        } else { /* 24-bit fixed point */
            const unsigned char *b = P + 9 * i + 3 * (size_t)k;
            int32_t f = (int32_t)(b[0] | b[1] << 8 | (uint32_t)b[2] << 16);
            if (f & 0x800000) f -= 0x1000000;
            g->pos[k] = ldexp((double)f, -L->frac);
        }
        g->sigma[k] = exp(S[3 * i + (size_t)k] / 16.0 - 10.0);
        g->rgb[k] = 0.5 + SPR__SH_C0 * ((C[3 * i + (size_t)k] / 255.0 - 0.5) / 0.15);
    }
    g->alpha = A[i] / 255.0; /* stored after the sigmoid */
    double q[4]; /* x y z w */
    if (L->qb == 3) {
        double s2 = 0.0;
        for (int k = 0; k < 3; k++) {
            q[k] = Q[3 * i + (size_t)k] / 127.5 - 1.0;
            s2 += q[k] * q[k];
        }
        q[3] = sqrt(s2 < 1.0 ? 1.0 - s2 : 0.0);
    } else { /* smallest three: 2 bits the largest component, 3 × (sign, 9-bit magnitude) */
        const unsigned char *b = Q + 4 * i;
        uint32_t comp = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
        const int big = (int)(comp >> 30);
        double s2 = 0.0;
        for (int k = 3; k >= 0; k--) {
            if (k == big) continue;
            double m = 0.7071067811865476 * (double)(comp & 511u) / 511.0;
            q[k] = (comp >> 9 & 1u) ? -m : m;
            comp >>= 10;
            s2 += q[k] * q[k];
        }
        q[big] = sqrt(s2 < 1.0 ? 1.0 - s2 : 0.0);
    }
    g->q[0] = q[3], g->q[1] = q[0], g->q[2] = q[1], g->q[3] = q[2];
    if (sh) {
        for (int ch = 0; ch < 3; ch++) sh[ch] = (float)((C[3 * i + (size_t)ch] / 255.0 - 0.5) / 0.15);
        for (int k = 1; k < L->sh_k; k++)
            for (int ch = 0; ch < 3; ch++) sh[3 * k + ch] = (float)((H[i * L->dim * 3 + 3 * (size_t)(k - 1) + ch] - 128.0) / 128.0);
    }
    /* the format's frame is RUB (x right, y up, z back: Niantic's README); the training frame is RDF */
    static const double rub_to_training[3] = {1.0, -1.0, -1.0};
    if (!L->raw) gauss_flip(g, sh, L->sh_k, rub_to_training);
}

static int spz_sh_dim(int degree) { return degree == 1 ? 3 : degree == 2 ? 8 : degree == 3 ? 15 : degree == 4 ? 24 : 0; }

/* The fields of a .spz header (16 bytes in versions 1–3, inside the gzip
 * stream; 32 bytes in version 4, at the start of the file), checked alike. */
static spr_result spz_header(const char *path, const char *where, const unsigned char *h, size_t avail, size_t hb, uint32_t *version,
                             uint32_t *n, int *degree, int *frac, int *flags, spr_error *err)
{
    uint32_t magic = 0;
    if (avail < hb) return spr__fail(err, SPR_E_TRUNCATED, "%s: %sbyte %zu: the file ends inside the %zu-byte header", path, where, avail, hb);
    memcpy(&magic, h, 4);
    memcpy(version, h + 4, 4);
    memcpy(n, h + 8, 4);
    *degree = h[12], *frac = h[13], *flags = h[14];
    if (magic != 0x5053474eu) return spr__fail(err, SPR_E_FORMAT, "%s: %sbyte 0: magic is not NGSP", path, where);
    if (hb == 16 && (*version < 1 || *version > 3))
        return spr__fail(err, SPR_E_FORMAT, "%s: %sbyte 4: version %u in a gzip stream (versions 1–3 are gzip; 4 is read without it)", path, where,
                         *version);
    if (hb == 32 && *version != 4)
        return spr__fail(err, SPR_E_FORMAT, "%s: byte 4: version %u after a bare NGSP magic (only version 4 is stored without gzip)", path, *version);
    if (*degree > 4) return spr__fail(err, SPR_E_FORMAT, "%s: %sbyte 12: SH degree %d (at most 4)", path, where, *degree);
    if (*frac > 23) return spr__fail(err, SPR_E_FORMAT, "%s: %sbyte 13: %d fractional bits (at most 23)", path, where, *frac);
    if (*flags & 2) return spr__fail(err, SPR_E_FORMAT, "%s: %sbyte 14: the file carries extensions (flag 2), which are not read", path, where);
    if (*n == 0) return spr__fail(err, SPR_E_FORMAT, "%s: no points", path);
    if (*n > SPR_MAX_SPLATS) return spr__fail(err, SPR_E_TOO_LARGE, "%s: header declares %u splats (limit %u)", path, *n, SPR_MAX_SPLATS);
    return SPR_OK;
}

/* Version 4 (Niantic's current writer, splat-transform's default): the
 * 32-byte header, a table of (compressed, uncompressed) uint64 sizes, then
 * one zstd stream per attribute in the order positions, alphas, colours,
 * scales, rotations, SH (SH absent at degree 0) — inflated here into one
 * buffer laid out as versions 1–3 hold them. */
static spr_result spz_v4(const char *path, const unsigned char *b, size_t len, unsigned char **out, spz_layout *L, spr_error *err)
{
    uint32_t version, n;
    int degree, frac, flags;
    spr_result r = spz_header(path, "", b, len, 32, &version, &n, &degree, &frac, &flags, err);
    if (r) return r;
    const unsigned streams = b[15];
    uint32_t toc;
    memcpy(&toc, b + 16, 4);
    const size_t dim = (size_t)spz_sh_dim(degree), want[6] = {9 * (size_t)n, n, 3 * (size_t)n, 3 * (size_t)n, 4 * (size_t)n, dim * 3 * n};
    const unsigned expect = dim ? 6 : 5;
    if (streams != expect)
        return spr__fail(err, SPR_E_FORMAT, "%s: byte 15: %u attribute streams, SH degree %d needs %u", path, streams, degree, expect);
    if (toc < 32 || toc > len || len - toc < 16 * (size_t)streams)
        return spr__fail(err, SPR_E_TRUNCATED, "%s: byte 16: the stream table at byte %u lies outside the file", path, toc);
    size_t total = 0;
    for (unsigned k = 0; k < expect; k++) total += want[k];
    /* as Niantic's loader bounds it: no real capture compresses past 1024:1, so a small file claiming more splats is refused
     * before anything is allocated for them */
    if (total / 1024 > len)
        return spr__fail(err, SPR_E_FORMAT, "%s: byte 8: %u splats need %zu bytes, more than %zu bytes of zstd streams can hold (1024:1 at most)", path,
                         n, total, len);
    unsigned char *d = malloc(total ? total : 1);
    if (!d) return spr__fail(err, SPR_E_NOMEM, "%s: out of memory for %u splats", path, n);
    size_t at = (size_t)toc + 16 * (size_t)streams, dst = 0;
    for (unsigned k = 0; k < expect && !r; k++) {
        uint64_t csize, usize;
        memcpy(&csize, b + toc + 16 * (size_t)k, 8);
        memcpy(&usize, b + toc + 16 * (size_t)k + 8, 8);
        if (usize != want[k])
            r = spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: stream %u holds %llu bytes, %u splats need %zu", path, (size_t)toc + 16 * k + 8, k,
                          (unsigned long long)usize, n, want[k]);
        else if (csize > len - at)
            r = spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: stream %u (%llu bytes) ends past the end of the file", path, at, k,
                          (unsigned long long)csize);
        else {
            size_t got = ZSTD_decompress(d + dst, want[k], b + at, (size_t)csize);
            if (ZSTD_isError(got) || got != want[k])
                r = spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: stream %u is not a valid zstd frame of %zu bytes (%s)", path, at, k, want[k],
                              ZSTD_isError(got) ? ZSTD_getErrorName(got) : "wrong size");
            at += (size_t)csize, dst += want[k];
        }
    }
    if (!r && at != len) r = spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: %zu bytes follow the last stream", path, at, len - at);
    if (r) { free(d); return r; }
    *out = d;
    *L = (spz_layout){d, n, 4, frac, 4, dim, 0, flags & 1, 0};
    return SPR_OK;
}

spr_result spr__parse_spz(const char *path, const char *buf, size_t len, const spr__gauss_opts *o, spr_cloud *c, spr_error *err)
{
    memset(c, 0, sizeof *c);
    const unsigned char *b = (const unsigned char *)buf;
    unsigned char *d = NULL;
    spz_layout L;
    spr_result r;
    if (len >= 4 && !memcmp(b, "NGSP", 4)) {
        r = spz_v4(path, b, len, &d, &L, err);
    } else if (len < 2 || b[0] != 0x1f || b[1] != 0x8b) {
        return spr__fail(err, SPR_E_FORMAT, "%s: byte 0: neither a version 4 .spz (NGSP) nor a gzip stream (versions 1–3)", path);
    } else { /* versions 1–3: the header inside the gzip stream says how long the rest is */
        size_t dl;
        const size_t max_bytes = 16 + (size_t)SPR_MAX_SPLATS * (9 + 1 + 3 + 3 + 4 + 24 * 3);
        if ((r = inflate_all(path, buf, len, max_bytes, &d, &dl, err))) return r;
        uint32_t version = 0, n = 0;
        int degree = 0, frac = 0, flags = 0;
        r = spz_header(path, "inflated ", d, dl, 16, &version, &n, &degree, &frac, &flags, err);
        const size_t pb = version == 1 ? 6 : 9, qb = version >= 3 ? 4 : 3, dim = (size_t)spz_sh_dim(degree);
        const size_t need = r ? 0 : 16 + (size_t)n * (pb + 1 + 3 + 3 + qb + dim * 3);
        if (!r && dl != need)
            r = spr__fail(err, dl < need ? SPR_E_TRUNCATED : SPR_E_FORMAT, "%s: inflated byte %zu: %u splats of version %u need %zu bytes, the stream has %zu",
                          path, dl < need ? dl : need, n, version, need, dl);
        L = (spz_layout){d + 16, n, version, frac, qb, dim, 0, flags & 1, 0};
    }
    if (!r) r = spr__gauss_alloc(c, L.n, (int)L.dim + 1, o, path, err);
    if (r) { free(d); return r; }
    L.sh_k = c->sh_k;
    L.raw = o->spz_raw;
    c->gauss_aa = L.antialiased;
    r = spr__gauss_fill(c, o, spz_splat, &L, path, err);
    free(d);
    return r;
}

/* ---- .glb: glTF 2.0 binary with KHR_gaussian_splatting ---- */

typedef struct glb_acc {
    const unsigned char *p; /* first element */
    size_t count, stride;
    int ctype, comps, normalized;
} glb_acc;

static int comp_size(int ct) { return ct == 5120 || ct == 5121 ? 1 : ct == 5122 || ct == 5123 ? 2 : ct == 5125 || ct == 5126 ? 4 : 0; }

static double comp_value(const glb_acc *a, size_t i, int k)
{
    const unsigned char *p = a->p + i * a->stride + (size_t)k * (size_t)comp_size(a->ctype);
    switch (a->ctype) {
    case 5126: return le_f32(p);
    case 5120: { double v = (int8_t)p[0]; return a->normalized ? fmax(v / 127.0, -1.0) : v; }
    case 5121: { double v = p[0]; return a->normalized ? v / 255.0 : v; }
    case 5122: { int16_t s; memcpy(&s, p, 2); return a->normalized ? fmax(s / 32767.0, -1.0) : s; }
    case 5123: { uint16_t s; memcpy(&s, p, 2); return a->normalized ? s / 65535.0 : s; }
    default: return NAN;
    }
}

static int json_int(const cJSON *o, const char *key, int dflt)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) && v->valuedouble >= 0 && v->valuedouble <= 2147483647.0 ? (int)v->valuedouble : cJSON_IsNumber(v) || v ? -2 : dflt;
}

/* A byte offset or length into the binary chunk, which reaches 4 GiB (its length is a uint32): past an int from 2 GiB on,
 * where a capture of 9M Gaussians with SH degree 3 puts its last attributes.  -2 when present but not one, dflt when absent. */
static long long json_bytes(const cJSON *o, const char *key, long long dflt)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) && v->valuedouble >= 0 && v->valuedouble <= 4294967295.0 ? (long long)v->valuedouble : cJSON_IsNumber(v) || v ? -2 : dflt;
}

/* Accessor `idx` of the JSON over the binary chunk, checked to lie inside it. */
static spr_result glb_accessor(const char *path, const cJSON *root, int idx, const unsigned char *bin, size_t bin_len, const char *what,
                               int comps, glb_acc *a, spr_error *err)
{
    const cJSON *acc = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "accessors"), idx);
    if (idx < 0 || !cJSON_IsObject(acc)) return spr__fail(err, SPR_E_FORMAT, "%s: attribute %s: accessor %d does not exist", path, what, idx);
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(acc, "type");
    const char *want = comps == 1 ? "SCALAR" : comps == 3 ? "VEC3" : "VEC4";
    if (!cJSON_IsString(type) || strcmp(type->valuestring, want))
        return spr__fail(err, SPR_E_FORMAT, "%s: attribute %s: accessor %d is not %s", path, what, idx, want);
    a->ctype = json_int(acc, "componentType", -1);
    a->normalized = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(acc, "normalized"));
    a->comps = comps;
    int count = json_int(acc, "count", -1), view = json_int(acc, "bufferView", -1);
    long long off = json_bytes(acc, "byteOffset", 0);
    if (!comp_size(a->ctype) || a->ctype == 5125 || (a->ctype != 5126 && !a->normalized))
        return spr__fail(err, SPR_E_FORMAT, "%s: attribute %s: component type %d is not one KHR_gaussian_splatting allows", path, what, a->ctype);
    if (cJSON_GetObjectItemCaseSensitive(acc, "sparse"))
        return spr__fail(err, SPR_E_FORMAT, "%s: attribute %s: sparse accessors are not read", path, what);
    const cJSON *bv = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "bufferViews"), view);
    if (count < 0 || off < 0 || view < 0 || !cJSON_IsObject(bv))
        return spr__fail(err, SPR_E_FORMAT, "%s: attribute %s: accessor %d has no valid count, byteOffset or bufferView", path, what, idx);
    int buffer = json_int(bv, "buffer", -1), stride = json_int(bv, "byteStride", 0);
    long long voff = json_bytes(bv, "byteOffset", 0), vlen = json_bytes(bv, "byteLength", -1);
    if (buffer != 0 || voff < 0 || vlen < 0 || stride < 0)
        return spr__fail(err, SPR_E_FORMAT, "%s: attribute %s: buffer view %d is not in the GLB binary chunk or is malformed", path, what, view);
    const size_t elem = (size_t)comps * (size_t)comp_size(a->ctype);
    a->stride = stride ? (size_t)stride : elem;
    a->count = (size_t)count;
    if (a->stride < elem || (size_t)voff + (size_t)vlen > bin_len ||
        (count && (size_t)off + (a->count - 1) * a->stride + elem > (size_t)vlen))
        return spr__fail(err, SPR_E_TRUNCATED, "%s: attribute %s: accessor %d reaches past its buffer view or the binary chunk", path, what, idx);
    a->p = bin + voff + off;
    return SPR_OK;
}

/* The accessors of a splat primitive: position, rotation, scale, opacity, SH degree 0, then degrees 1–3. */
typedef struct glb_attrs {
    glb_acc a[5];
    glb_acc sh[15];
    int sh_k;
} glb_attrs;

/* One Gaussian of the ratified KHR_gaussian_splatting: scale linear (σ),
 * opacity linear, rotation (x, y, z, w), SH degree 0 the DC coefficients.
 * glTF's world (+y up, +z forward, x left) is turned into the training
 * code's (x right, y down, z forward: the frame of 3DGS PLY files and of
 * cameras.json) by reversing x and y, a half turn about z, as PlayCanvas's
 * converter and viewer do (docs/formats.md). */
static void glb_splat(const void *user, size_t i, spr__gauss *g, float *sh)
{
    const glb_attrs *at = user;
    const glb_acc *acc = at->a;
    for (int k = 0; k < 3; k++) {
        g->pos[k] = comp_value(&acc[0], i, k);
        const double sg = comp_value(&acc[2], i, k);
        g->sigma[k] = sg < 0.0 ? NAN : sg; /* negative scales are invalid (NaN fails the check, never a 2D flag) */
        g->rgb[k] = 0.5 + SPR__SH_C0 * comp_value(&acc[4], i, k);
    }
    g->q[0] = comp_value(&acc[1], i, 3), g->q[1] = comp_value(&acc[1], i, 0), g->q[2] = comp_value(&acc[1], i, 1), g->q[3] = comp_value(&acc[1], i, 2);
    g->alpha = comp_value(&acc[3], i, 0);
    if (sh) {
        for (int ch = 0; ch < 3; ch++) sh[ch] = (float)comp_value(&acc[4], i, ch);
        for (int k = 1; k < at->sh_k; k++)
            for (int ch = 0; ch < 3; ch++) sh[3 * k + ch] = (float)comp_value(&at->sh[k - 1], i, ch);
    }
    static const double gltf_to_training[3] = {-1.0, -1.0, 1.0};
    gauss_flip(g, sh, at->sh_k, gltf_to_training);
}

spr_result spr__parse_glb(const char *path, const char *buf, size_t len, const spr__gauss_opts *o, spr_cloud *c, spr_error *err)
{
    memset(c, 0, sizeof *c);
    const unsigned char *b = (const unsigned char *)buf;
    uint32_t h[5] = {0};
    if (len >= 20) memcpy(h, b, 20);
    if (len < 20 || h[0] != 0x46546C67u) return spr__fail(err, SPR_E_FORMAT, "%s: byte 0: not a binary glTF (magic glTF)", path);
    if (h[1] != 2) return spr__fail(err, SPR_E_FORMAT, "%s: byte 4: glTF version %u (2 is read)", path, h[1]);
    if (h[2] > len) return spr__fail(err, SPR_E_TRUNCATED, "%s: byte 8: declares %u bytes, the file has %zu", path, h[2], len);
    if (h[4] != 0x4E4F534Au || h[3] > len - 20)
        return spr__fail(err, SPR_E_FORMAT, "%s: byte 12: the first chunk is not a JSON chunk inside the file", path);
    const size_t jl = h[3], bo = 20 + ((jl + 3) & ~(size_t)3);
    const unsigned char *bin = NULL;
    size_t bin_len = 0;
    if (bo + 8 <= len) {
        uint32_t ch[2];
        memcpy(ch, b + bo, 8);
        if (ch[1] == 0x004E4942u) {
            if (ch[0] > len - bo - 8) return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: the binary chunk declares %u bytes, fewer follow", path, bo, ch[0]);
            bin = b + bo + 8;
            bin_len = ch[0];
        }
    }
    cJSON *root = cJSON_ParseWithLength(buf + 20, jl);
    if (!root) {
        const char *at = cJSON_GetErrorPtr();
        size_t off = at && at >= buf + 20 && at <= buf + 20 + jl ? (size_t)(at - buf) : 20;
        return spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: the JSON chunk does not parse", path, off);
    }
    spr_result r = SPR_OK;
    /* the first primitive with KHR_gaussian_splatting */
    const cJSON *prim = NULL, *meshes = cJSON_GetObjectItemCaseSensitive(root, "meshes"), *m;
    int mesh_index = -1, mi = 0;
    cJSON_ArrayForEach(m, meshes) {
        const cJSON *p;
        cJSON_ArrayForEach(p, cJSON_GetObjectItemCaseSensitive(m, "primitives")) {
            if (!prim && cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(p, "extensions"), "KHR_gaussian_splatting")) {
                prim = p;
                mesh_index = mi;
            }
        }
        mi++;
    }
    if (!prim) { r = spr__fail(err, SPR_E_FORMAT, "%s: no mesh primitive carries KHR_gaussian_splatting", path); goto done; }
    /* node transforms are not applied: a node placing the mesh must be the identity */
    const cJSON *node;
    cJSON_ArrayForEach(node, cJSON_GetObjectItemCaseSensitive(root, "nodes")) {
        if (json_int(node, "mesh", -1) != mesh_index) continue;
        static const char *const keys[] = {"matrix", "translation", "rotation", "scale"};
        static const double ident[4][16] = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, {0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}};
        for (int k = 0; k < 4; k++) {
            const cJSON *v = cJSON_GetObjectItemCaseSensitive(node, keys[k]), *e;
            int j = 0;
            cJSON_ArrayForEach(e, v) {
                if (!cJSON_IsNumber(e) || j >= 16 || e->valuedouble != ident[k][j]) {
                    r = spr__fail(err, SPR_E_FORMAT, "%s: the node of mesh %d has a %s other than the identity; node transforms are not applied", path,
                                  mesh_index, keys[k]);
                    goto done;
                }
                j++;
            }
        }
    }
    const cJSON *attrs = cJSON_GetObjectItemCaseSensitive(prim, "attributes");
    if (!bin) { r = spr__fail(err, SPR_E_FORMAT, "%s: no binary chunk (external buffers are not read)", path); goto done; }
    static const char *const need[] = {"POSITION", "KHR_gaussian_splatting:ROTATION", "KHR_gaussian_splatting:SCALE",
                                       "KHR_gaussian_splatting:OPACITY", "KHR_gaussian_splatting:SH_DEGREE_0_COEF_0"};
    static const int comps[] = {3, 4, 3, 1, 3};
    glb_acc acc[5], shacc[15];
    for (int k = 0; k < 5; k++) {
        int idx = json_int(attrs, need[k], -1);
        if (idx == -1) { r = spr__fail(err, SPR_E_FORMAT, "%s: the splat primitive lacks the attribute %s", path, need[k]); goto done; }
        if ((r = glb_accessor(path, root, idx, bin, bin_len, need[k], comps[k], &acc[k], err))) goto done;
        if (acc[k].count != acc[0].count) {
            r = spr__fail(err, SPR_E_FORMAT, "%s: attribute %s has %zu elements, POSITION %zu", path, need[k], acc[k].count, acc[0].count);
            goto done;
        }
    }
    int file_k = 1;
    for (int l = 1; l <= 3; l++) { /* whole degrees only */
        int ok = 1;
        for (int j = 0; j < 2 * l + 1 && ok; j++) {
            char name[64];
            snprintf(name, sizeof name, "KHR_gaussian_splatting:SH_DEGREE_%d_COEF_%d", l, j);
            int idx = json_int(attrs, name, -1);
            if (idx == -1) { ok = 0; break; }
            if ((r = glb_accessor(path, root, idx, bin, bin_len, name, 3, &shacc[l * l - 1 + j], err))) goto done;
            if (shacc[l * l - 1 + j].count != acc[0].count) { r = spr__fail(err, SPR_E_FORMAT, "%s: attribute %s has the wrong count", path, name); goto done; }
        }
        if (!ok) break;
        file_k = (l + 1) * (l + 1);
    }
    const size_t n = acc[0].count;
    if (n == 0) { r = spr__fail(err, SPR_E_FORMAT, "%s: no points", path); goto done; }
    if (n > SPR_MAX_SPLATS) { r = spr__fail(err, SPR_E_TOO_LARGE, "%s: %zu splats (limit %u)", path, n, SPR_MAX_SPLATS); goto done; }
    if ((r = spr__gauss_alloc(c, n, file_k, o, path, err))) goto done;
    glb_attrs at = {{acc[0], acc[1], acc[2], acc[3], acc[4]}, {{0}}, c->sh_k};
    memcpy(at.sh, shacc, sizeof at.sh);
    r = spr__gauss_fill(c, o, glb_splat, &at, path, err);
done:
    cJSON_Delete(root);
    return r;
}
