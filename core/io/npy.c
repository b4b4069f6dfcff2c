/* npy.c — NumPy .npy files and .npz archives (spr_npy.h; issue 43).
 *
 * The .npy format (numpy/lib/format.py, NEP 1):
 *   bytes 0–5   \x93NUMPY
 *   bytes 6–7   major, minor version: 1.0 (header length u16 LE), 2.0 or 3.0 (u32 LE; 3.0: the header is UTF-8)
 *   then        the header, a Python dict literal with exactly the keys 'descr' (a dtype string such as '<f4'),
 *               'fortran_order' (True/False) and 'shape' (a tuple of ints), padded with spaces and ended by '\n'
 *               so that the data starts on a multiple of 64 (16 in older files);
 *   then        the elements in C order (or Fortran order, refused here), nothing after them.
 * An .npz is a zip of such files named NAME.npy (np.savez stores them, np.savez_compressed deflates them, both
 * with zip64 fields); libzip reads it, as it reads the SOG zips of io_sog.c, and each member's CRC-32 is compared
 * whole (zlib).  Bytes are assembled into values explicitly by the file's byte order, so nothing here depends on
 * the host's.  The writer makes a stored zip by hand (a few fixed headers): its bytes depend on the arrays only.
 */
#include "spr_npy.h"
#include "spr_io.h"

#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zip.h>
#include <zlib.h>

/* Bytes a deflated zip entry may inflate to, per byte stored: deflate's own limit (1032:1), as io_sog.c. */
#define NPZ_DEFLATE_RATIO 1032u

size_t spr_npy_count(const spr_npy *a)
{
    size_t n = 1;
    for (int d = 0; d < a->ndim; d++) n *= a->shape[d];
    return n;
}

void spr_npy_free(spr_npy *a)
{
    if (!a) return;
    free(a->data);
    memset(a, 0, sizeof *a);
}

void spr_npz_free(spr_npy *arrays, int n)
{
    for (int k = 0; arrays && k < n; k++) spr_npy_free(&arrays[k]);
    free(arrays);
}

/* ---- the header dict ---- */

typedef struct npy_cur {
    const char *path;
    const char *s;   /* the header text */
    size_t n, i;     /* its length, the position */
    size_t base;     /* the file offset of s[0] */
    spr_error *err;
} npy_cur;

static void skip_ws(npy_cur *c)
{
    while (c->i < c->n && (c->s[c->i] == ' ' || c->s[c->i] == '\t' || c->s[c->i] == '\n' || c->s[c->i] == '\r')) c->i++;
}

static spr_result bad(npy_cur *c, const char *what)
{
    const char ch = c->i < c->n ? c->s[c->i] : 0;
    if (c->i >= c->n) return spr__fail(c->err, SPR_E_FORMAT, "%s: byte %zu: the header dict ends early: %s", c->path, c->base + c->i, what);
    return spr__fail(c->err, SPR_E_FORMAT, "%s: byte %zu: %s in the header dict (found '%c')", c->path, c->base + c->i, what,
                     ch > 32 && ch < 127 ? ch : '?');
}

/* A quoted string without escapes into out (cap bytes). */
static spr_result quoted(npy_cur *c, char *out, size_t cap, const char *what)
{
    if (c->i >= c->n || (c->s[c->i] != '\'' && c->s[c->i] != '"')) return bad(c, what);
    const char q = c->s[c->i++];
    size_t k = 0;
    for (; c->i < c->n && c->s[c->i] != q; c->i++) {
        if (c->s[c->i] == '\\' || (unsigned char)c->s[c->i] < 32) return bad(c, "an escape or control character in a string");
        if (k + 1 >= cap) return bad(c, "a string too long");
        out[k++] = c->s[c->i];
    }
    if (c->i >= c->n) return bad(c, "an unterminated string");
    c->i++;
    out[k] = '\0';
    return SPR_OK;
}

static int word(npy_cur *c, const char *w)
{
    const size_t l = strlen(w);
    if (c->n - c->i < l || memcmp(c->s + c->i, w, l)) return 0;
    const char nx = c->i + l < c->n ? c->s[c->i + l] : ' ';
    if ((nx >= 'a' && nx <= 'z') || (nx >= 'A' && nx <= 'Z') || (nx >= '0' && nx <= '9') || nx == '_') return 0;
    c->i += l;
    return 1;
}

/* The shape tuple: "()", "(5,)", "(2, 3)" (Python's repr; "(5)" is an int, not a tuple, and refused as numpy does). */
static spr_result shape_tuple(npy_cur *c, int *ndim, size_t *shape)
{
    if (c->i >= c->n || c->s[c->i] != '(') return bad(c, "'shape' is not a tuple");
    c->i++;
    int nd = 0, comma = 0;
    for (;;) {
        skip_ws(c);
        if (c->i < c->n && c->s[c->i] == ')') break;
        if (nd && !comma) return bad(c, "',' or ')' expected in 'shape'");
        if (c->i >= c->n || c->s[c->i] < '0' || c->s[c->i] > '9') return bad(c, "a non-negative integer expected in 'shape'");
        const size_t at = c->i;
        size_t v = 0;
        while (c->i < c->n && c->s[c->i] >= '0' && c->s[c->i] <= '9') {
            v = v * 10 + (size_t)(c->s[c->i++] - '0');
            if (v > SPR_NPY_MAX_ELEMS) {
                return spr__fail(c->err, SPR_E_TOO_LARGE, "%s: byte %zu: a dimension of 'shape' beyond %zu elements", c->path, c->base + at,
                                 SPR_NPY_MAX_ELEMS);
            }
        }
        if (c->i < c->n && c->s[c->i] == 'L') c->i++; /* Python 2's numpy wrote longs as 3L */
        if (nd == SPR_NPY_MAX_DIMS)
            return spr__fail(c->err, SPR_E_TOO_LARGE, "%s: byte %zu: 'shape' has more than %d dimensions", c->path, c->base + at, SPR_NPY_MAX_DIMS);
        shape[nd++] = v;
        skip_ws(c);
        comma = c->i < c->n && c->s[c->i] == ',';
        if (comma) c->i++;
    }
    if (nd == 1 && !comma) return bad(c, "'shape' (n) is a number, a tuple of one is (n,)");
    c->i++;
    *ndim = nd;
    return SPR_OK;
}

/* What a descr gives: the file's byte order (1: big-endian), the kind ('f', 'i', 'u', 'b') and bytes per element. */
typedef struct npy_dtype { int big; char kind; int size; } npy_dtype;

static int host_big(void)
{
    const uint16_t one = 1;
    return *(const unsigned char *)&one == 0;
}

static int parse_descr(const char *d, npy_dtype *t)
{
    const char o = d[0];
    if (o != '<' && o != '>' && o != '=' && o != '|') return 0;
    t->big = o == '>' || (o == '=' && host_big());
    t->kind = d[1];
    if (!d[2] || d[3]) return 0;
    t->size = d[2] - '0';
    switch (t->kind) {
    case 'f': return (t->size == 4 || t->size == 8) && o != '|';
    case 'i':
    case 'u': return (t->size == 1 || ((t->size == 2 || t->size == 4 || t->size == 8) && o != '|'));
    case 'b': return t->size == 1;
    default: return 0;
    }
}

/* The header at buf (the magic already checked): the dtype, the shape, and where the data starts. */
static spr_result parse_header(const char *path, const unsigned char *b, size_t len, npy_dtype *t, int *ndim, size_t *shape,
                               size_t *data_at, spr_error *err)
{
    const int major = b[6], minor = b[7];
    if ((major != 1 && major != 2 && major != 3) || minor != 0)
        return spr__fail(err, SPR_E_FORMAT, "%s: byte 6: .npy format version %d.%d (1.0, 2.0 and 3.0 are read)", path, major, minor);
    const size_t pre = major == 1 ? 10 : 12;
    if (len < pre) return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: the file ends inside the header length", path, len);
    const size_t hlen = major == 1 ? (size_t)b[8] | (size_t)b[9] << 8
                                   : (size_t)b[8] | (size_t)b[9] << 8 | (size_t)b[10] << 16 | (size_t)b[11] << 24;
    if (hlen > len - pre)
        return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: the header says %zu bytes, %zu follow", path, (size_t)8, hlen,
                         len - pre);
    npy_cur c = {path, (const char *)b + pre, hlen, 0, pre, err};
    char descr[16] = "", key[32];
    int have[3] = {0, 0, 0}, fortran = 0;
    size_t descr_at = 0;
    spr_result r;
    skip_ws(&c);
    if (c.i >= c.n || c.s[c.i] != '{') return bad(&c, "'{' expected");
    c.i++;
    for (;;) {
        skip_ws(&c);
        if (c.i < c.n && c.s[c.i] == '}') break;
        const size_t key_at = c.i;
        if ((r = quoted(&c, key, sizeof key, "a quoted key or '}' expected"))) return r;
        const int k = !strcmp(key, "descr") ? 0 : !strcmp(key, "fortran_order") ? 1 : !strcmp(key, "shape") ? 2 : -1;
        if (k < 0 || have[k]) {
            return spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: %s key '%s' in the header dict (it holds 'descr', 'fortran_order' and 'shape' once each)",
                             path, pre + key_at, k < 0 ? "unknown" : "repeated", key);
        }
        have[k] = 1;
        skip_ws(&c);
        if (c.i >= c.n || c.s[c.i] != ':') return bad(&c, "':' expected");
        c.i++;
        skip_ws(&c);
        if (k == 0) {
            descr_at = c.i;
            if (c.i < c.n && c.s[c.i] == '[')
                return spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: a structured dtype (a list of fields) is not read", path, pre + c.i);
            if ((r = quoted(&c, descr, sizeof descr, "'descr' is not a dtype string"))) return r;
        } else if (k == 1) {
            if (word(&c, "True")) fortran = 1;
            else if (!word(&c, "False")) return bad(&c, "'fortran_order' is neither True nor False");
        } else if ((r = shape_tuple(&c, ndim, shape))) {
            return r;
        }
        skip_ws(&c);
        if (c.i < c.n && c.s[c.i] == ',') c.i++;
        else if (c.i >= c.n || c.s[c.i] != '}') return bad(&c, "',' or '}' expected");
    }
    c.i++;
    skip_ws(&c);
    if (c.i < c.n) return bad(&c, "only spaces may follow the dict");
    if (!have[0] || !have[1] || !have[2]) {
        return spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: the header dict has no '%s'", path, pre,
                         !have[0] ? "descr" : !have[1] ? "fortran_order" : "shape");
    }
    if (fortran)
        return spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: fortran_order is True: only C-order arrays are read (save np.ascontiguousarray(a))",
                         path, pre);
    if (!parse_descr(descr, t)) {
        return spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: dtype '%s' is not read (float32, float64 and integers of 1 to 8 bytes are)", path,
                         pre + descr_at, descr);
    }
    *data_at = pre + hlen;
    return SPR_OK;
}

/* Element i of raw data in the file's byte order, as the integer of its bytes. */
static uint64_t raw_at(const unsigned char *p, size_t i, const npy_dtype *t)
{
    const unsigned char *e = p + i * (size_t)t->size;
    uint64_t v = 0;
    for (int k = 0; k < t->size; k++) v |= (uint64_t)e[t->big ? t->size - 1 - k : k] << (8 * k);
    return v;
}

spr_result spr__parse_npy(const char *path, const void *buf, size_t len, const char *name, spr_npy *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    const unsigned char *b = buf;
    static const unsigned char magic[6] = {0x93, 'N', 'U', 'M', 'P', 'Y'};
    if (!len || memcmp(b, magic, len < 6 ? len : 6))
        return spr__fail(err, SPR_E_FORMAT, "%s: byte 0: not a .npy file (it starts with \\x93NUMPY)", path);
    if (len < 10) return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: the file ends inside the .npy preamble (10 bytes)", path, len);
    npy_dtype t = {0, 0, 1};
    int ndim = 0;
    size_t shape[SPR_NPY_MAX_DIMS] = {0}, at = 0;
    spr_result r = parse_header(path, b, len, &t, &ndim, shape, &at, err);
    if (r) return r;
    size_t count = 1;
    for (int d = 0; d < ndim; d++) count = shape[d] ? count : 0;
    for (int d = 0; d < ndim && count; d++) {
        if (count > SPR_NPY_MAX_ELEMS / shape[d])
            return spr__fail(err, SPR_E_TOO_LARGE, "%s: byte %zu: the shape holds more than %zu elements", path, at, SPR_NPY_MAX_ELEMS);
        count *= shape[d];
    }
    const size_t need = count * (size_t)t.size;
    if (len - at < need) {
        return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: %zu elements of %d bytes need %zu bytes, %zu follow", path, at, count, t.size, need,
                         len - at);
    }
    if (len - at > need) return spr__fail(err, SPR_E_FORMAT, "%s: byte %zu: %zu bytes after the array's data", path, at + need, len - at - need);
    const unsigned char *p = b + at;
    /* int32 only when every value fits: refused before any allocation (only i8, u4 and u8 can miss) */
    const int may_miss = (t.kind == 'i' && t.size == 8) || (t.kind == 'u' && t.size >= 4);
    for (size_t i = 0; may_miss && i < count; i++) {
        const uint64_t v = raw_at(p, i, &t);
        const int neg = t.kind == 'i' && (int64_t)v < 0;
        if (neg ? (int64_t)v < INT32_MIN : v > INT32_MAX) {
            return spr__fail(err, SPR_E_VALUE, "%s: byte %zu: element %zu (%s%llu) does not fit int32", path, at + i * (size_t)t.size, i,
                             neg ? "-" : "", neg ? 0ull - (unsigned long long)v : (unsigned long long)v);
        }
    }
    void *data = malloc(count ? count * 4 : 1);
    if (!data) return spr__fail(err, SPR_E_NOMEM, "%s: out of memory for %zu elements", path, count);
    if (t.kind == 'f') {
        float *f = data;
        if (t.size == 4 && t.big == host_big()) memcpy(f, p, need);
        else
            for (size_t i = 0; i < count; i++) {
                const uint64_t v = raw_at(p, i, &t);
                if (t.size == 4) {
                    const uint32_t u = (uint32_t)v;
                    memcpy(&f[i], &u, 4);
                } else {
                    double d;
                    memcpy(&d, &v, 8);
                    f[i] = (float)d; /* rounded once, to nearest */
                }
            }
    } else {
        int32_t *q = data;
        const int shift = 64 - 8 * t.size;
        for (size_t i = 0; i < count; i++) {
            const uint64_t v = raw_at(p, i, &t);
            q[i] = t.kind == 'b' ? v != 0 : (int32_t)(t.kind == 'i' ? (int64_t)(v << shift) >> shift : (int64_t)v); /* sign-extended */
        }
    }
    out->ndim = ndim;
    for (int d = 0; d < ndim; d++) out->shape[d] = shape[d];
    out->type = t.kind == 'f' ? SPR_NPY_F4 : SPR_NPY_I4;
    out->data = data;
    snprintf(out->name, sizeof out->name, "%s", name ? name : "");
    return SPR_OK;
}

spr_result spr_npy_read(const char *path, spr_npy *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    char *buf;
    size_t len;
    int mapped;
    spr_result r = spr__map_file(path, &buf, &len, &mapped, err);
    if (r) return r;
    r = spr__parse_npy(path, buf, len, "", out, err);
    spr__unmap_file(buf, len, mapped);
    return r;
}

/* ---- .npz: reading through libzip ---- */

/* The bytes of member k (CRC-32 checked) into *out. */
static spr_result npz_member(const char *path, size_t len, zip_t *z, zip_uint64_t k, const zip_stat_t *st, unsigned char **out, spr_error *err)
{
    *out = NULL;
    const int stored = (st->valid & ZIP_STAT_COMP_METHOD) && st->comp_method == ZIP_CM_STORE;
    if (!(st->valid & ZIP_STAT_SIZE) || !(st->valid & ZIP_STAT_COMP_SIZE) || st->comp_size > len ||
        st->size > (stored ? st->comp_size : st->comp_size * NPZ_DEFLATE_RATIO + 64)) {
        return spr__fail(err, SPR_E_FORMAT, "%s: member %s: the zip's directory says %llu bytes from %llu stored, which %s cannot hold", path,
                         st->name, (unsigned long long)st->size, (unsigned long long)st->comp_size, stored ? "a member stored as is" : "deflate");
    }
    unsigned char *b = malloc(st->size ? st->size : 1);
    if (!b) return spr__fail(err, SPR_E_NOMEM, "%s: member %s: out of memory for %llu bytes", path, st->name, (unsigned long long)st->size);
    zip_file_t *f = zip_fopen_index(z, k, 0);
    const zip_int64_t got = f ? zip_fread(f, b, st->size) : -1;
    char why[200] = "";
    if (got < 0) snprintf(why, sizeof why, " (%s)", f ? zip_file_strerror(f) : zip_strerror(z));
    if (f) zip_fclose(f);
    if (got < 0 || (zip_uint64_t)got != st->size) {
        free(b);
        return spr__fail(err, SPR_E_FORMAT, "%s: member %s: %lld of its %llu bytes could be read from the zip%s", path, st->name, (long long)got,
                         (unsigned long long)st->size, why);
    }
    /* libzip checks a member's CRC-32 only when it is read past its end: compared here whole */
    const unsigned long crc = crc32_z(0, b, (z_size_t)st->size);
    if ((st->valid & ZIP_STAT_CRC) && crc != st->crc) {
        free(b);
        return spr__fail(err, SPR_E_FORMAT, "%s: member %s: its bytes have the CRC-32 %08lx, the zip's directory says %08lx (the zip is damaged)", path,
                         st->name, crc, (unsigned long)st->crc);
    }
    *out = b;
    return SPR_OK;
}

spr_result spr__parse_npz(const char *path, const void *buf, size_t len, spr_npy **arrays, int *n, spr_error *err)
{
    *arrays = NULL, *n = 0;
    if (len < 22) /* libzip opens 0 bytes as an empty archive; numpy refuses them, and an archive has at least its 22-byte end record */
        return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: not a zip archive (an .npz zips .npy files; a zip ends with a 22-byte record)", path, len);
    zip_error_t ze;
    zip_error_init(&ze);
    zip_source_t *src = zip_source_buffer_create(buf, len, 0, &ze);
    zip_t *z = src ? zip_open_from_source(src, ZIP_RDONLY | ZIP_CHECKCONS, &ze) : NULL;
    if (!z) {
        spr_result r = zip_error_code_zip(&ze) == ZIP_ER_EXISTS /* libzip's answer to two members of one name */
                           ? spr__fail(err, SPR_E_FORMAT, "%s: two members of the zip have one name (libzip: %s)", path, zip_error_strerror(&ze))
                           : spr__fail(err, SPR_E_FORMAT, "%s: not a zip archive (an .npz zips .npy files): %s", path, zip_error_strerror(&ze));
        if (src) zip_source_free(src);
        zip_error_fini(&ze);
        return r;
    }
    zip_error_fini(&ze);
    const zip_int64_t m = zip_get_num_entries(z, 0);
    spr_result r = SPR_OK;
    spr_npy *a = NULL;
    int got = 0;
    if (m < 0 || m > INT_MAX) {
        r = spr__fail(err, SPR_E_FORMAT, "%s: the zip's directory holds %lld members", path, (long long)m);
        goto done;
    }
    if (m && !(a = calloc((size_t)m, sizeof *a))) {
        r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory for %lld members", path, (long long)m);
        goto done;
    }
    for (zip_int64_t k = 0; k < m; k++) {
        zip_stat_t st;
        zip_stat_init(&st);
        if (zip_stat_index(z, (zip_uint64_t)k, 0, &st) || !(st.valid & ZIP_STAT_NAME)) {
            r = spr__fail(err, SPR_E_FORMAT, "%s: member %lld: its entry cannot be read from the zip's directory (%s)", path, (long long)k,
                          zip_strerror(z));
            goto done;
        }
        const size_t nl = strlen(st.name);
        if (nl < 5 || nl - 4 >= sizeof a[0].name || strcmp(st.name + nl - 4, ".npy")) {
            r = spr__fail(err, SPR_E_FORMAT, "%s: member %s: not named NAME.npy with NAME of 1 to %zu bytes", path, st.name, sizeof a[0].name - 1);
            goto done;
        }
        char base[sizeof a[0].name];
        memcpy(base, st.name, nl - 4);
        base[nl - 4] = '\0';
        for (int j = 0; j < got; j++)
            if (!strcmp(a[j].name, base)) {
                r = spr__fail(err, SPR_E_FORMAT, "%s: member %s: a second member of that name (members %d and %lld)", path, st.name, j, (long long)k);
                goto done;
            }
        unsigned char *b;
        if ((r = npz_member(path, len, z, (zip_uint64_t)k, &st, &b, err))) goto done;
        char label[1024];
        snprintf(label, sizeof label, "%s: member %s", path, st.name);
        r = spr__parse_npy(label, b, (size_t)st.size, base, &a[got], err);
        free(b);
        if (r) goto done;
        got++;
    }
done:
    zip_discard(z); /* frees the source too */
    if (r) {
        spr_npz_free(a, got);
        return r;
    }
    *arrays = a, *n = got;
    return SPR_OK;
}

spr_result spr_npz_read(const char *path, spr_npy **arrays, int *n, spr_error *err)
{
    *arrays = NULL, *n = 0;
    char *buf;
    size_t len;
    int mapped;
    spr_result r = spr__map_file(path, &buf, &len, &mapped, err);
    if (r) return r;
    r = spr__parse_npz(path, buf, len, arrays, n, err);
    spr__unmap_file(buf, len, mapped);
    return r;
}

/* ---- writing ---- */

/* The version 1.0 header of a (its type checked): magic to '\n', padded so the data starts on a multiple of 64. */
static size_t npy_header(const spr_npy *a, char *h, size_t cap)
{
    char shape[128];
    int k = snprintf(shape, sizeof shape, "(");
    for (int d = 0; d < a->ndim; d++) k += snprintf(shape + k, sizeof shape - (size_t)k, "%s%zu", d ? ", " : "", a->shape[d]);
    snprintf(shape + k, sizeof shape - (size_t)k, "%s)", a->ndim == 1 ? "," : "");
    char dict[200];
    int dl = snprintf(dict, sizeof dict, "{'descr': '%s', 'fortran_order': False, 'shape': %s, }", a->type == SPR_NPY_F4 ? "<f4" : "<i4", shape);
    const size_t total = (10 + (size_t)dl + 1 + 63) / 64 * 64, hlen = total - 10;
    if (total > cap) return 0;
    memcpy(h, "\x93NUMPY\x01\x00", 8);
    h[8] = (char)(hlen & 0xff), h[9] = (char)(hlen >> 8);
    memcpy(h + 10, dict, (size_t)dl);
    memset(h + 10 + dl, ' ', hlen - (size_t)dl - 1);
    h[total - 1] = '\n';
    return total;
}

/* The array's data as little-endian bytes, in pieces: fn(user, bytes, n) for each; nonzero from fn stops it. */
static int npy_data_le(const spr_npy *a, int (*fn)(void *user, const unsigned char *p, size_t n), void *user)
{
    const size_t count = spr_npy_count(a);
    const unsigned char *src = a->data;
    if (!host_big()) return count ? fn(user, src, count * 4) : 0;
    unsigned char piece[16384];
    for (size_t i = 0; i < count;) {
        size_t m = 0;
        for (; i < count && m < sizeof piece; i++, m += 4) {
            uint32_t u;
            memcpy(&u, src + 4 * i, 4);
            for (int k = 0; k < 4; k++) piece[m + (size_t)k] = (unsigned char)(u >> (8 * k));
        }
        if (fn(user, piece, m)) return -1;
    }
    return 0;
}

static int put_file(void *user, const unsigned char *p, size_t n) { return fwrite(p, 1, n, user) != n; }
static int put_crc(void *user, const unsigned char *p, size_t n)
{
    *(unsigned long *)user = crc32_z(*(unsigned long *)user, p, (z_size_t)n);
    return 0;
}

/* The arrays a writer accepts: a type, 0..4 dimensions, at most SPR_NPY_MAX_ELEMS elements, data. */
static spr_result check_array(const char *path, const spr_npy *a, int k, spr_error *err)
{
    if (a->type != SPR_NPY_F4 && a->type != SPR_NPY_I4)
        return spr__fail(err, SPR_E_ARG, "%s: array %d: type %d is neither SPR_NPY_F4 nor SPR_NPY_I4", path, k, (int)a->type);
    if (a->ndim < 0 || a->ndim > SPR_NPY_MAX_DIMS) return spr__fail(err, SPR_E_ARG, "%s: array %d: %d dimensions (0 to 4 are written)", path, k, a->ndim);
    size_t count = 1;
    for (int d = 0; d < a->ndim; d++) count = a->shape[d] ? count : 0;
    for (int d = 0; d < a->ndim && count; d++) {
        if (count > SPR_NPY_MAX_ELEMS / a->shape[d])
            return spr__fail(err, SPR_E_TOO_LARGE, "%s: array %d: more than %zu elements", path, k, SPR_NPY_MAX_ELEMS);
        count *= a->shape[d];
    }
    if (count && !a->data) return spr__fail(err, SPR_E_ARG, "%s: array %d: no data", path, k);
    return SPR_OK;
}

static int npy_body(FILE *f, const void *user)
{
    const spr_npy *a = user;
    char h[256];
    const size_t hl = npy_header(a, h, sizeof h);
    if (!hl || fwrite(h, 1, hl, f) != hl) return -1;
    return npy_data_le(a, put_file, f);
}

spr_result spr_npy_write(const char *path, const spr_npy *a, spr_error *err)
{
    spr_result r = check_array(path, a, 0, err);
    return r ? r : spr__write_atomic(path, npy_body, a, err);
}

typedef struct npz_job { const spr_npy *a; int n; } npz_job;

static void le16(unsigned char *p, unsigned v) { p[0] = (unsigned char)v, p[1] = (unsigned char)(v >> 8); }
static void le32(unsigned char *p, unsigned long v) { le16(p, (unsigned)(v & 0xffff)), le16(p + 2, (unsigned)(v >> 16 & 0xffff)); }

/* Local header (30 bytes) or central directory entry (46) of a stored member, dated 1980-01-01 00:00 (DOS time 0,
 * date 0x21).  Version 2.0 needed; made by Unix (3), mode rw-r--r--. */
static size_t zip_entry(unsigned char *p, int central, unsigned long crc, unsigned long size, size_t name_len, unsigned long offset)
{
    unsigned char *q = p;
    le32(q, central ? 0x02014b50ul : 0x04034b50ul), q += 4;
    if (central) le16(q, 0x0314), q += 2;
    le16(q, 20), le16(q + 2, 0), le16(q + 4, 0), le16(q + 6, 0), le16(q + 8, 0x21), q += 10;
    le32(q, crc), le32(q + 4, size), le32(q + 8, size), le16(q + 12, (unsigned)name_len), le16(q + 14, 0), q += 16;
    if (central) le16(q, 0), le16(q + 2, 0), le16(q + 4, 0), le32(q + 6, 0100644ul << 16), le32(q + 10, offset), q += 14;
    return (size_t)(q - p);
}

static int npz_body(FILE *f, const void *user)
{
    const npz_job *J = user;
    unsigned long at = 0;
    unsigned char e[64];
    unsigned long *crc = malloc((size_t)(J->n ? J->n : 1) * sizeof *crc), *off = malloc((size_t)(J->n ? J->n : 1) * sizeof *off);
    int bad = !crc || !off;
    for (int k = 0; !bad && k < J->n; k++) {
        const spr_npy *a = &J->a[k];
        char h[256], name[80];
        const size_t hl = npy_header(a, h, sizeof h), nl = (size_t)snprintf(name, sizeof name, "%s.npy", a->name);
        const unsigned long size = (unsigned long)(hl + spr_npy_count(a) * 4);
        crc[k] = crc32_z(0, (const unsigned char *)h, hl);
        npy_data_le(a, put_crc, &crc[k]);
        off[k] = at;
        const size_t el = zip_entry(e, 0, crc[k], size, nl, 0);
        bad = fwrite(e, 1, el, f) != el || fwrite(name, 1, nl, f) != nl || fwrite(h, 1, hl, f) != hl || npy_data_le(a, put_file, f);
        at += (unsigned long)(el + nl) + size;
    }
    const unsigned long cd = at;
    for (int k = 0; !bad && k < J->n; k++) {
        const spr_npy *a = &J->a[k];
        char h[256], name[80];
        const size_t hl = npy_header(a, h, sizeof h), nl = (size_t)snprintf(name, sizeof name, "%s.npy", a->name);
        const size_t el = zip_entry(e, 1, crc[k], (unsigned long)(hl + spr_npy_count(a) * 4), nl, off[k]);
        bad = fwrite(e, 1, el, f) != el || fwrite(name, 1, nl, f) != nl;
        at += (unsigned long)(el + nl);
    }
    /* end of central directory: this disk, the directory's disk, entries here and in all, its size and offset, no comment */
    le32(e, 0x06054b50ul), le16(e + 4, 0), le16(e + 6, 0), le16(e + 8, (unsigned)J->n), le16(e + 10, (unsigned)J->n);
    le32(e + 12, at - cd), le32(e + 16, cd), le16(e + 20, 0);
    bad = bad || fwrite(e, 1, 22, f) != 22;
    free(crc);
    free(off);
    return bad ? -1 : 0;
}

spr_result spr_npz_write(const char *path, const spr_npy *arrays, int n, spr_error *err)
{
    if (n < 0 || n > 65535 || (n && !arrays)) return spr__fail(err, SPR_E_ARG, "%s: %d arrays (0 to 65535 are written)", path, n);
    unsigned long long bytes = 22;
    for (int k = 0; k < n; k++) {
        const spr_npy *a = &arrays[k];
        spr_result r = check_array(path, a, k, err);
        if (r) return r;
        const size_t nl = strnlen(a->name, sizeof a->name);
        if (!nl || nl == sizeof a->name)
            return spr__fail(err, SPR_E_ARG, "%s: array %d: a member's name has 1 to %zu bytes", path, k, sizeof a->name - 1);
        for (int j = 0; j < k; j++)
            if (!strcmp(arrays[j].name, a->name)) return spr__fail(err, SPR_E_ARG, "%s: arrays %d and %d are both named '%s'", path, j, k, a->name);
        char h[256];
        bytes += 30 + 46 + 2 * (nl + 4) + npy_header(a, h, sizeof h) + 4ull * spr_npy_count(a);
    }
    if (bytes > 0xffffffffull)
        return spr__fail(err, SPR_E_TOO_LARGE, "%s: the archive would take %llu bytes, beyond a zip without zip64 (4 GiB)", path, bytes);
    const npz_job J = {arrays, n};
    return spr__write_atomic(path, npz_body, &J, err);
}
