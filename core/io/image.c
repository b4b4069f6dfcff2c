/* image.c — PNG through libpng, PFM by hand (a two-line header and raw floats). */
#include "spr_image.h"
#include "spr_io.h"

#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

uint8_t spr_to_u8(float v)
{
    float c = v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
    if (c != c) c = 0.0f;
    return (uint8_t)lrintf(c * 255.0f);
}

typedef struct { const float *img; int w, h, ch; } img_ref;

static int png_body(FILE *f, const void *user)
{
    const img_ref *im = user;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    uint8_t *row = malloc((size_t)im->w * 3);
    if (!png || !info || !row) { png_destroy_write_struct(&png, &info); free(row); return -1; }
    if (setjmp(png_jmpbuf(png))) { png_destroy_write_struct(&png, &info); free(row); return -1; }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)im->w, (png_uint_32)im->h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = im->h - 1; y >= 0; y--) {
        const float *src = im->img + (size_t)y * im->w * im->ch;
        for (int x = 0; x < im->w; x++)
            for (int c = 0; c < 3; c++) row[3 * x + c] = spr_to_u8(src[(size_t)x * im->ch + (im->ch == 1 ? 0 : c)]);
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(row);
    return 0;
}

spr_result spr_write_png(const char *path, const float *img, int w, int h, int channels, spr_error *err)
{
    img_ref r = {img, w, h, channels};
    return spr__write_atomic(path, png_body, &r, err);
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
    img_ref r = {img, w, h, channels};
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

uint64_t spr_hash64(const void *data, size_t n)
{
    const unsigned char *p = data;
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}
