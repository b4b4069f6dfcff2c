/* image.c — PNG through libpng, PFM by hand (a two-line header and raw floats). */
#include "spr_image.h"
#include "spr_io.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

uint8_t spr_to_u8(float v)
{
    float c = v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
    if (c != c) c = 0.0f;
    return (uint8_t)lrintf(c * 255.0f);
}

/* libpng's default handlers print "libpng error: …" / "libpng warning: …" on stderr themselves, a line before
 * ours.  Every png_struct here gets these instead: the error's text is kept in the PNG_WHY-byte buffer given as
 * error_ptr, for the one line the caller makes of it (naming the file), and control goes back to the setjmp;
 * warnings are dropped, as they neither stop a read or a write nor change what it gives. */
#define PNG_WHY 160
static void png_kept_error(png_structp png, png_const_charp msg)
{
    snprintf(png_get_error_ptr(png), PNG_WHY, "%s", msg);
    png_longjmp(png, 1);
}
static void png_dropped_warning(png_structp png, png_const_charp msg) { (void)png, (void)msg; }

/* why: where png_body keeps libpng's error (PNG_WHY bytes) */
typedef struct { const float *img; int w, h, ch, alpha; char *why; } img_ref;

static int png_body(FILE *f, const void *user)
{
    const img_ref *im = user;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, im->why, png_kept_error, png_dropped_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    const int oc = im->alpha ? 4 : 3;
    uint8_t *row = malloc((size_t)im->w * oc);
    if (!png || !info || !row) { png_destroy_write_struct(&png, &info); free(row); return -1; }
    if (setjmp(png_jmpbuf(png))) { png_destroy_write_struct(&png, &info); free(row); return -1; }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)im->w, (png_uint_32)im->h, 8, im->alpha ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = im->h - 1; y >= 0; y--) {
        const float *src = im->img + (size_t)y * im->w * im->ch;
        for (int x = 0; x < im->w; x++)
            for (int c = 0; c < oc; c++) row[(size_t)oc * x + c] = spr_to_u8(src[(size_t)x * im->ch + (im->ch == 1 ? 0 : c)]);
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(row);
    return 0;
}

/* Through a temporary file; a failure is spr__write_atomic's line ("PATH: write failed: strerror") with what libpng said. */
static spr_result write_png(const char *path, img_ref *r, spr_error *err)
{
    char why[PNG_WHY] = "";
    spr_error e = {0};
    r->why = why;
    spr_result res = spr__write_atomic(path, png_body, r, &e);
    if (res) spr__fail(err, res, "%s%s%s%s", e.msg, why[0] ? " (libpng: " : "", why, why[0] ? ")" : "");
    return res;
}

spr_result spr_write_png(const char *path, const float *img, int w, int h, int channels, spr_error *err)
{
    img_ref r = {img, w, h, channels, 0, NULL};
    return write_png(path, &r, err);
}

spr_result spr_write_png_rgba(const char *path, const float *img, int w, int h, spr_error *err)
{
    img_ref r = {img, w, h, 4, 1, NULL};
    return write_png(path, &r, err);
}

static int pfm_body(FILE *f, const void *user)
{
    const img_ref *im = user;
    int out_ch = im->ch == 1 ? 1 : 3;
    fprintf(f, "%s\n%d %d\n-1.0\n", out_ch == 1 ? "Pf" : "PF", im->w, im->h);
    float *row = malloc((size_t)im->w * out_ch * sizeof(float));
    if (!row) return -1;
    for (int y = 0; y < im->h; y++) { /* PFM stores the bottom row first */
        const float *src = im->img + (size_t)y * im->w * im->ch;
        for (int x = 0; x < im->w; x++)
            for (int c = 0; c < out_ch; c++) row[x * out_ch + c] = src[(size_t)x * im->ch + c];
        if (fwrite(row, sizeof(float), (size_t)im->w * out_ch, f) != (size_t)im->w * out_ch) { free(row); return -1; }
    }
    free(row);
    return 0;
}

spr_result spr_write_pfm(const char *path, const float *img, int w, int h, int channels, spr_error *err)
{
    img_ref r = {img, w, h, channels, 0, NULL};
    return spr__write_atomic(path, pfm_body, &r, err);
}

spr_result spr_read_pfm(const char *path, float **img, int *w, int *h, int *channels, spr_error *err)
{
    char *buf;
    size_t len;
    *img = NULL;
    spr_result r = spr__read_file(path, &buf, &len, err);
    if (r) return r;
    char tag[3] = {0};
    double scale;
    int consumed = 0;
    if (sscanf(buf, "%2s %d %d %lf%n", tag, w, h, &scale, &consumed) != 4 || (strcmp(tag, "PF") && strcmp(tag, "Pf")) ||
        *w < 1 || *h < 1 || *w > 65536 || *h > 65536 || scale == 0.0) {
        free(buf);
        return spr__fail(err, SPR_E_FORMAT, "%s: byte 0: not a PFM header", path);
    }
    *channels = tag[1] == 'F' ? 3 : 1;
    size_t off = (size_t)consumed + 1, need = (size_t)*w * *h * *channels * sizeof(float);
    if (len < off || len - off < need) {
        free(buf);
        return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %zu: %zu bytes of pixels expected, %zu present", path, off, need,
                         len > off ? len - off : 0);
    }
    float *im = malloc(need);
    if (!im) { free(buf); return spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path); }
    memcpy(im, buf + off, need);
    if (scale > 0.0) /* big-endian data */
        for (size_t i = 0; i < need / 4; i++) {
            uint32_t u;
            memcpy(&u, im + i, 4);
            u = __builtin_bswap32(u);
            memcpy(im + i, &u, 4);
        }
    free(buf);
    *img = im;
    return SPR_OK;
}

uint64_t spr_hash64(const void *data, size_t n) { return spr_hash64_continue(SPR_HASH64_INIT, data, n); }

uint64_t spr_hash64_continue(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

/* PNG through libpng's classic interface, so 16-bit samples keep their
 * bits (the simplified interface would treat them as linear light and
 * convert): palette and low-bit grey expanded, tRNS to alpha, grey to RGB. */
typedef struct png_in { FILE *f; png_structp png; png_infop info; png_bytep *rows; float *img; char why[PNG_WHY]; } png_in;

static void png_in_free(png_in *s)
{
    png_destroy_read_struct(&s->png, &s->info, NULL);
    if (s->f) fclose(s->f);
    free(s->rows ? s->rows[0] : NULL);
    free(s->rows);
}

static spr_result read_png(const char *path, float **img, int *w, int *h, int *channels, int *bits_out, spr_error *err)
{
    *img = NULL;
    png_in s = {0};
    unsigned char sig[8];
    if (!(s.f = fopen(path, "rb"))) return spr__fail(err, SPR_E_IO, "%s: cannot open", path);
    if (fread(sig, 1, 8, s.f) != 8 || png_sig_cmp(sig, 0, 8)) {
        fclose(s.f);
        return spr__fail(err, SPR_E_FORMAT, "%s: byte 0: not a PNG signature", path);
    }
    /* libpng allocates a chunk's stated length before reading it: walk the chunks
     * first, so a damaged length is a line naming its byte, not gigabytes allocated.
     * Every chunk up to IEND must lie whole in the file: a header of 8 bytes, its data,
     * a CRC of 4 (a header at the end with fewer than its data and CRC after it was let
     * through before, and libpng then allocated the 2 GB it claimed); the image data's
     * compressed bytes are summed for the bound below. */
    unsigned long long idat = 0;
    if (fseek(s.f, 0, SEEK_END) == 0) {
        const long size = ftell(s.f);
        long at = 8;
        int iend = 0;
        while (!iend && at < size) {
            unsigned char hd[8];
            if (size - at < 12 || fseek(s.f, at, SEEK_SET) || fread(hd, 1, 8, s.f) != 8) {
                fclose(s.f);
                return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %ld: %ld bytes that are not a chunk (a chunk takes at least 12) before the end of the file",
                                 path, at, size - at);
            }
            const unsigned long len = (unsigned long)hd[0] << 24 | (unsigned long)hd[1] << 16 | (unsigned long)hd[2] << 8 | hd[3];
            if (len > 0x7fffffffUL || (long)len > size - at - 12) {
                fclose(s.f);
                return spr__fail(err, SPR_E_TRUNCATED, "%s: byte %ld: chunk '%c%c%c%c' of %lu bytes runs past the end of the file (%ld bytes)", path, at,
                                 hd[4] >= 32 && hd[4] < 127 ? hd[4] : '?', hd[5] >= 32 && hd[5] < 127 ? hd[5] : '?',
                                 hd[6] >= 32 && hd[6] < 127 ? hd[6] : '?', hd[7] >= 32 && hd[7] < 127 ? hd[7] : '?', len, size);
            }
            if (!memcmp(hd + 4, "IDAT", 4)) idat += len;
            iend = !memcmp(hd + 4, "IEND", 4);
            at += 12 + (long)len;
        }
    }
    if (fseek(s.f, 8, SEEK_SET)) { fclose(s.f); return spr__fail(err, SPR_E_IO, "%s: cannot read", path); }
    s.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, s.why, png_kept_error, png_dropped_warning);
    s.info = s.png ? png_create_info_struct(s.png) : NULL;
    if (!s.png || !s.info) { png_in_free(&s); return spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path); }
    if (setjmp(png_jmpbuf(s.png))) {
        free(s.img);
        png_in_free(&s);
        char why[160];
        snprintf(why, sizeof why, "%s", s.why);
        return spr__fail(err, SPR_E_FORMAT, "%s: malformed or truncated PNG data%s%s%s", path, why[0] ? " (libpng: " : "", why, why[0] ? ")" : "");
    }
    png_set_user_limits(s.png, 65536, 65536);
    /* what libpng may allocate for one ancillary chunk (text, ICC profile, their decompression): 8 MiB */
    png_set_chunk_malloc_max(s.png, 8u << 20);
    png_init_io(s.png, s.f);
    png_set_sig_bytes(s.png, 8);
    png_read_info(s.png, s.info);
    png_uint_32 W = png_get_image_width(s.png, s.info), H = png_get_image_height(s.png, s.info);
    int type = png_get_color_type(s.png, s.info), depth = png_get_bit_depth(s.png, s.info);
    if (W < 1 || H < 1 || W > 65536 || H > 65536) {
        png_in_free(&s);
        return spr__fail(err, SPR_E_FORMAT, "%s: byte 16: image size %ux%u outside 1..65536", path, (unsigned)W, (unsigned)H);
    }
    if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(s.png);
    if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(s.png);
    if (png_get_valid(s.png, s.info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(s.png);
    if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(s.png);
    /* deflate gives at most 1032 bytes for one (zlib's bound): image data that cannot hold W×H is refused before any
     * row is allocated, so a small file cannot claim a large image */
    {
        const unsigned long long raw = (unsigned long long)H * (1ull + ((unsigned long long)W * png_get_channels(s.png, s.info) * (unsigned)depth + 7ull) / 8ull);
        if (raw > 1032ull * idat + 1032ull) {
            png_in_free(&s);
            return spr__fail(err, SPR_E_TRUNCATED, "%s: byte 16: %ux%u pixels need %llu bytes of image data, more than its %llu compressed bytes can hold", path,
                             (unsigned)W, (unsigned)H, raw, idat);
        }
    }
    png_read_update_info(s.png, s.info);
    const int ch = png_get_channels(s.png, s.info), bits = png_get_bit_depth(s.png, s.info);
    const size_t rowbytes = png_get_rowbytes(s.png, s.info);
    s.rows = malloc(H * sizeof *s.rows);
    unsigned char *data = s.rows ? malloc(rowbytes * H) : NULL;
    s.img = malloc((size_t)W * H * (size_t)ch * sizeof(float));
    if (!s.rows || !data || !s.img) {
        free(data);
        free(s.img);
        if (s.rows) s.rows[0] = NULL;
        png_in_free(&s);
        return spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path);
    }
    for (png_uint_32 y = 0; y < H; y++) s.rows[y] = data + y * rowbytes;
    png_read_image(s.png, s.rows);
    png_read_end(s.png, NULL);
    const float full = bits == 16 ? 65535.0f : 255.0f; /* divided, not multiplied by a reciprocal: v/255 correctly rounded */
    for (png_uint_32 y = 0; y < H; y++) { /* row 0 of the image = the bottom row, as every plane */
        const unsigned char *src = s.rows[H - 1 - y];
        float *dst = s.img + (size_t)y * W * ch;
        for (size_t i = 0; i < (size_t)W * ch; i++)
            dst[i] = (float)(bits == 16 ? (unsigned)(src[2 * i] << 8 | src[2 * i + 1]) : src[i]) / full;
    }
    *img = s.img;
    *w = (int)W;
    *h = (int)H;
    *channels = ch;
    if (bits_out) *bits_out = bits;
    s.img = NULL;
    png_in_free(&s);
    return SPR_OK;
}

spr_result spr_read_png(const char *path, float **img, int *w, int *h, int *channels, spr_error *err)
{
    return read_png(path, img, w, h, channels, NULL, err);
}

spr_result spr_read_image_bits(const char *path, float **img, int *w, int *h, int *channels, int *bits, spr_error *err)
{
    size_t n = strlen(path);
    int b = 32;
    spr_result r;
    if (n >= 4 && !strcasecmp(path + n - 4, ".png")) r = read_png(path, img, w, h, channels, &b, err);
    else if (n >= 4 && !strcasecmp(path + n - 4, ".pfm")) r = spr_read_pfm(path, img, w, h, channels, err);
    else {
        *img = NULL;
        return spr__fail(err, SPR_E_ARG, "%s: unknown image type (expected .png or .pfm)", path);
    }
    if (bits) *bits = b;
    return r;
}

spr_result spr_image_size(const char *path, int *w, int *h, int *bits, spr_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) return spr__fail(err, SPR_E_IO, "%s: cannot open", path);
    unsigned char b[25];
    int ok = 0, nb = 32;
    long W = 0, H = 0;
    const size_t n = fread(b, 1, sizeof b, f);
    if (n == 25 && !png_sig_cmp(b, 0, 8) && !memcmp(b + 12, "IHDR", 4)) {
        nb = b[24] == 16 ? 16 : 8; /* what read_png gives: 16-bit stays, every other depth becomes 8 */
        W = (long)((unsigned long)b[16] << 24 | (unsigned long)b[17] << 16 | (unsigned long)b[18] << 8 | b[19]);
        H = (long)((unsigned long)b[20] << 24 | (unsigned long)b[21] << 16 | (unsigned long)b[22] << 8 | b[23]);
        ok = 1;
    } else if (n >= 3 && b[0] == 'P' && (b[1] == 'F' || b[1] == 'f') && !fseek(f, 2, SEEK_SET)) {
        ok = fscanf(f, "%ld %ld", &W, &H) == 2;
    }
    fclose(f);
    if (!ok || W < 1 || H < 1 || W > 1 << 20 || H > 1 << 20) return spr__fail(err, SPR_E_FORMAT, "%s: no image header", path);
    *w = (int)W, *h = (int)H;
    if (bits) *bits = nb;
    return SPR_OK;
}

spr_result spr_read_image(const char *path, float **img, int *w, int *h, int *channels, spr_error *err)
{
    return spr_read_image_bits(path, img, w, h, channels, NULL, err);
}

/* 8-bit value of channel c of pixel p (grey images repeat their channel). */
static int u8_at(const float *im, int ch, size_t p, int c)
{
    return spr_to_u8(im[p * (size_t)ch + (size_t)(ch < 3 ? 0 : c)]);
}

spr_result spr_image_diff(const float *a, int ch_a, const float *b, int ch_b, int w, int h, const float *bg,
                          spr_image_diff_stats *st, float *heat)
{
    memset(st, 0, sizeof *st);
    const size_t np = (size_t)w * h;
    uint64_t total = 0, total_bg = 0;
    int bg8[3];
    for (int c = 0; c < 3; c++) bg8[c] = bg ? spr_to_u8(bg[c]) : 0;
    for (size_t p = 0; p < np; p++) {
        int sum = 0, on_bg = 1;
        for (int c = 0; c < 3; c++) {
            const int vb = u8_at(b, ch_b, p, c), d = abs(u8_at(a, ch_a, p, c) - vb);
            sum += d;
            on_bg &= vb == bg8[c];
            if (d > st->max_abs) st->max_abs = d;
        }
        total += (uint64_t)sum;
        if (on_bg) st->bg_pixels++, total_bg += (uint64_t)sum;
        st->differing += sum != 0;
        if (heat) heat[p] = (float)sum;
    }
    st->pixels = np;
    st->zp_eps = np ? (double)total / (double)np : 0.0;
    st->zp_eps_bg = np ? (double)total_bg / (double)np : 0.0;
    st->mean_abs = np ? (double)total / (3.0 * (double)np) : 0.0;
    if (heat) { /* sum of |Δ| mapped through black → red → yellow → white over 0 … max (≥ 1) */
        double hi = 1.0;
        for (size_t p = 0; p < np; p++)
            if (heat[p] > hi) hi = heat[p];
        for (size_t q = np; q-- > 0;) {
            double t = heat[q] / hi;
            float *o = heat + 3 * q; /* in place from the end: 3 floats per pixel, fits the caller's 3·W·H */
            o[0] = (float)(t < 1.0 / 3 ? 3 * t : 1.0);
            o[1] = (float)(t < 1.0 / 3 ? 0.0 : t < 2.0 / 3 ? 3 * t - 1 : 1.0);
            o[2] = (float)(t < 2.0 / 3 ? 0.0 : 3 * t - 2);
        }
    }
    return SPR_OK;
}

spr_result spr_hash_file(const char *path, uint64_t *out, spr_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) return spr__fail(err, SPR_E_IO, "%s: cannot open: %s", path, strerror(errno));
    unsigned char buf[1 << 16];
    uint64_t h = SPR_HASH64_INIT;
    size_t got;
    while ((got = fread(buf, 1, sizeof buf, f)) > 0) h = spr_hash64_continue(h, buf, got);
    int bad = ferror(f);
    fclose(f);
    if (bad) return spr__fail(err, SPR_E_IO, "%s: read error", path);
    *out = h;
    return SPR_OK;
}
