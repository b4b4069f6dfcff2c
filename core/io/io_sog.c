/* io_sog.c — PlayCanvas SOG, version 2 (the default export of
 * splat-transform and SuperSplat): the quantised attributes of every
 * Gaussian as lossless WebP images, described by meta.json, either zipped
 * into one `.sog` file or side by side in a folder (`meta.json` given as the
 * model).  libzip reads the zip (stored or deflated entries, found through
 * its central directory), libwebp decodes the images and cJSON the JSON.
 *
 * The layout, as splat-transform's writer (src/lib/writers/write-sog.ts,
 * 2.7.1 and 3.7.0) writes it and PlayCanvas's engine reads it
 * (src/scene/gsplat/gsplat-sog-data.js and its shader chunks); the details
 * and their sources are in docs/formats.md:
 *   Gaussian i is texel i of every per-Gaussian image, row by row from the
 *   top-left (all those images share one size);
 *   means_l/means_u   16 bits a coordinate (low, high byte in R G B) over
 *                     [mins, maxs] of n = sign(v)·log(|v| + 1); v = sign(n)(e^|n| − 1);
 *   quats             the three smallest components of ±q·√2 as bytes
 *                     (c = (b/255 − 0.5)·√2), A = 252 + the index (w x y z)
 *                     of the largest, which is √(1 − a² − b² − c²);
 *   scales            indices into a 256-entry codebook of log σ;
 *   sh0               indices into a 256-entry codebook of f_dc, A the
 *                     opacity byte (after the sigmoid);
 *   shN               a palette of `count` SH vectors (labels: 16 bits in R G),
 *                     coefficient j of vector n at texel ((n mod 64)·K + j, n / 64)
 *                     of the centroids, R G B indices into a 256-entry codebook.
 * The frame is the training PLY's: nothing is turned.
 *
 * Hand-written rather than taken from a library: no SOG reader is packaged in
 * Debian (the engine's and splat-transform's are JavaScript). */
#include "spr_io.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <webp/decode.h>
#include <zip.h>
#include <zlib.h>

/* Pixels an image may have: 64 for every byte of the SOG (the zip, or the folder's files).  A real SOG spends
 * at least about a byte a Gaussian (means_l's low bytes do not compress), so this refuses no real file; it keeps a
 * small input from making the decoder allocate a large image (a lossless WebP of one colour is a few bytes at any
 * size). */
#define SOG_PIXELS_PER_BYTE 64u
#define SOG_PIXELS_FLOOR 65536u
/* Bytes a deflated zip entry may inflate to, per byte stored: deflate's own limit (1032:1). */
#define SOG_DEFLATE_RATIO 1032u

typedef struct sog_src {
    const char *path;         /* as the user named it: the .sog, or the folder's meta.json */
    zip_t *zip;               /* the .sog (NULL: a folder, or files in memory) */
    const spr__sog_file *mem; /* the files in memory (NULL: not) */
    size_t nmem;
    char dir[1024];           /* the folder (with a trailing '/') */
    size_t bytes;             /* the SOG's size: the zip's, the files' in memory, or the folder's files' so far */
} sog_src;

typedef struct sog_image {
    uint8_t *rgba;
    int w, h;
} sog_image;

/* The bytes of one of the SOG's files. */
static spr_result sog_read(sog_src *s, const char *name, unsigned char **out, size_t *len, spr_error *err)
{
    *out = NULL, *len = 0;
    if (!name[0] || strchr(name, '/') || strchr(name, '\\') || !strcmp(name, "..") || !strcmp(name, "."))
        return spr__fail(err, SPR_E_FORMAT, "%s: meta.json names the file \"%s\": a SOG's files are plain names beside meta.json", s->path, name);
    if (s->mem) {
        for (size_t k = 0; k < s->nmem; k++)
            if (!strcmp(s->mem[k].name, name)) {
                if (!(*out = malloc(s->mem[k].len ? s->mem[k].len : 1))) return spr__fail(err, SPR_E_NOMEM, "%s: %s: out of memory", s->path, name);
                memcpy(*out, s->mem[k].data, s->mem[k].len);
                *len = s->mem[k].len;
                return SPR_OK;
            }
        return spr__fail(err, SPR_E_FORMAT, "%s: no %s (meta.json names it)", s->path, name);
    }
    if (!s->zip) {
        char p[1400];
        snprintf(p, sizeof p, "%s%s", s->dir, name);
        char *b;
        spr_result r = spr__read_file(p, &b, len, err);
        if (r) return r;
        s->bytes += *len;
        *out = (unsigned char *)b;
        return SPR_OK;
    }
    const zip_int64_t k = zip_name_locate(s->zip, name, 0);
    if (k < 0)
        return spr__fail(err, SPR_E_FORMAT, "%s: the zip holds no %s (%s)", s->path, name, strcmp(name, "meta.json") ? "meta.json names it" : "a SOG's description");
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(s->zip, (zip_uint64_t)k, 0, &st) || !(st.valid & ZIP_STAT_SIZE) || !(st.valid & ZIP_STAT_COMP_SIZE))
        return spr__fail(err, SPR_E_FORMAT, "%s: %s: its size cannot be read from the zip's directory", s->path, name);
    const int stored = (st.valid & ZIP_STAT_COMP_METHOD) && st.comp_method == ZIP_CM_STORE;
    if (st.comp_size > s->bytes || st.size > (stored ? st.comp_size : st.comp_size * SOG_DEFLATE_RATIO + 64))
        return spr__fail(err, SPR_E_FORMAT, "%s: %s: the zip's directory says %llu bytes from %llu stored, which %s cannot hold", s->path, name,
                         (unsigned long long)st.size, (unsigned long long)st.comp_size, stored ? "an entry stored as is" : "deflate");
    unsigned char *b = malloc(st.size ? st.size : 1);
    if (!b) return spr__fail(err, SPR_E_NOMEM, "%s: %s: out of memory for %llu bytes", s->path, name, (unsigned long long)st.size);
    zip_file_t *f = zip_fopen_index(s->zip, (zip_uint64_t)k, 0);
    const zip_int64_t got = f ? zip_fread(f, b, st.size) : -1;
    char why[200] = "";
    if (f && got < 0) snprintf(why, sizeof why, " (%s)", zip_strerror(s->zip));
    if (!f) snprintf(why, sizeof why, " (%s)", zip_strerror(s->zip));
    if (f) zip_fclose(f);
    if (got < 0 || (zip_uint64_t)got != st.size) {
        free(b);
        return spr__fail(err, SPR_E_FORMAT, "%s: %s: %lld of its %llu bytes could be read from the zip%s", s->path, name, (long long)got,
                         (unsigned long long)st.size, why);
    }
    /* libzip checks an entry's CRC-32 only when it is read past its end: here it is compared whole (zlib) */
    const unsigned long crc = (st.valid & ZIP_STAT_CRC) ? crc32_z(0, b, (z_size_t)st.size) : 0;
    if ((st.valid & ZIP_STAT_CRC) && crc != st.crc) {
        free(b);
        return spr__fail(err, SPR_E_FORMAT, "%s: %s: its bytes have the CRC-32 %08lx, the zip's directory says %08lx (the zip is damaged)", s->path, name,
                         crc, (unsigned long)st.crc);
    }
    *out = b, *len = (size_t)st.size;
    return SPR_OK;
}

/* A WebP of the SOG, decoded to RGBA: lossless, at most the SOG's pixel budget. */
static spr_result sog_webp(sog_src *s, const char *name, sog_image *im, spr_error *err)
{
    unsigned char *b;
    size_t len;
    im->rgba = NULL;
    spr_result r = sog_read(s, name, &b, &len, err);
    if (r) return r;
    WebPBitstreamFeatures ft;
    if (WebPGetFeatures(b, len, &ft) != VP8_STATUS_OK) {
        free(b);
        return spr__fail(err, SPR_E_FORMAT, "%s: %s: not a WebP image", s->path, name);
    }
    const uint64_t px = (uint64_t)ft.width * (uint64_t)ft.height, budget = (uint64_t)s->bytes * SOG_PIXELS_PER_BYTE + SOG_PIXELS_FLOOR;
    if (ft.format != 2) r = spr__fail(err, SPR_E_FORMAT, "%s: %s: a lossy WebP (SOG's images are lossless: their bytes are indices)", s->path, name);
    else if (px > budget)
        r = spr__fail(err, SPR_E_TOO_LARGE, "%s: %s: %dx%d pixels, more than a SOG of %zu bytes can hold (%llu)", s->path, name, ft.width, ft.height,
                      s->bytes, (unsigned long long)budget);
    else if (!(im->rgba = WebPDecodeRGBA(b, len, &im->w, &im->h)))
        r = spr__fail(err, SPR_E_FORMAT, "%s: %s: the WebP data does not decode (truncated or corrupt)", s->path, name);
    free(b);
    return r;
}

/* Number `key` of object o, finite. */
static int num(const cJSON *o, const char *key, double *v)
{
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!cJSON_IsNumber(n) || !isfinite(n->valuedouble)) return 0;
    *v = n->valuedouble;
    return 1;
}

/* The attribute `key`: an object whose "files" holds nfiles names (into files), and, with cb, a "codebook" of 256
 * finite numbers (as float: the writer's float32 values), with mm, "mins" and "maxs" of 3. */
static spr_result attribute(const char *path, const cJSON *meta, const char *key, int nfiles, const char **files, float *cb, double *mins,
                            double *maxs, spr_error *err)
{
    const cJSON *o = cJSON_GetObjectItemCaseSensitive(meta, key), *f = cJSON_GetObjectItemCaseSensitive(o, "files");
    if (!cJSON_IsObject(o)) return spr__fail(err, SPR_E_FORMAT, "%s: meta.json has no \"%s\" object", path, key);
    if (cJSON_GetArraySize(f) != nfiles) return spr__fail(err, SPR_E_FORMAT, "%s: meta.json: %s.files is not %d file name%s", path, key, nfiles, nfiles > 1 ? "s" : "");
    for (int k = 0; k < nfiles; k++) {
        const cJSON *e = cJSON_GetArrayItem(f, k);
        if (!cJSON_IsString(e)) return spr__fail(err, SPR_E_FORMAT, "%s: meta.json: %s.files[%d] is not a string", path, key, k);
        files[k] = e->valuestring;
    }
    if (cb) {
        const cJSON *c = cJSON_GetObjectItemCaseSensitive(o, "codebook");
        if (cJSON_GetArraySize(c) != 256) return spr__fail(err, SPR_E_FORMAT, "%s: meta.json: %s.codebook is not 256 numbers", path, key);
        int k = 0;
        const cJSON *e;
        cJSON_ArrayForEach(e, c)
        {
            if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble) || !isfinite((float)e->valuedouble))
                return spr__fail(err, SPR_E_FORMAT, "%s: meta.json: %s.codebook[%d] is not a finite number", path, key, k);
            cb[k++] = (float)e->valuedouble;
        }
    }
    if (mins) {
        const cJSON *lo = cJSON_GetObjectItemCaseSensitive(o, "mins"), *hi = cJSON_GetObjectItemCaseSensitive(o, "maxs");
        if (cJSON_GetArraySize(lo) != 3 || cJSON_GetArraySize(hi) != 3)
            return spr__fail(err, SPR_E_FORMAT, "%s: meta.json: %s.mins and %s.maxs are not 3 numbers each", path, key, key);
        for (int k = 0; k < 3; k++) {
            const cJSON *a = cJSON_GetArrayItem(lo, k), *b = cJSON_GetArrayItem(hi, k);
            if (!cJSON_IsNumber(a) || !cJSON_IsNumber(b) || !isfinite(a->valuedouble) || !isfinite(b->valuedouble) ||
                !(a->valuedouble <= b->valuedouble) || fabs(a->valuedouble) > 88.0 || fabs(b->valuedouble) > 88.0)
                return spr__fail(err, SPR_E_FORMAT, "%s: meta.json: %s axis %d: mins and maxs are not finite log-coordinates with min <= max (|n| <= 88)",
                                 path, key, k);
            mins[k] = a->valuedouble, maxs[k] = b->valuedouble;
        }
    }
    return SPR_OK;
}

typedef struct sog_layout {
    size_t n;
    const uint8_t *L, *U, *Q, *S, *C;   /* means_l, means_u, quats, scales, sh0: RGBA, texel i of Gaussian i */
    const uint8_t *lab, *cen;           /* shN: labels (RGBA like the others), centroids (cen_w wide) */
    int cen_w, K, sh_k;                 /* K: coefficients a channel beyond DC */
    double mins[3], maxs[3];
    float scb[256], ccb[256], hcb[256]; /* codebooks: log σ, f_dc, SH */
} sog_layout;

static void sog_splat(const void *user, size_t i, spr__gauss *g, float *sh)
{
    const sog_layout *L = user;
    const size_t p = 4 * i;
    for (int k = 0; k < 3; k++) {
        const double t = (double)(L->L[p + (size_t)k] | L->U[p + (size_t)k] << 8) / 65535.0;
        const double n = L->mins[k] + (L->maxs[k] - L->mins[k]) * t;
        g->pos[k] = n < 0.0 ? -(exp(-n) - 1.0) : exp(n) - 1.0;
        g->sigma[k] = exp((double)L->scb[L->S[p + (size_t)k]]);
        g->rgb[k] = 0.5 + SPR__SH_C0 * (double)L->ccb[L->C[p + (size_t)k]];
    }
    g->alpha = L->C[p + 3] / 255.0;
    /* smallest three: the stored ones in w x y z order around the largest (validated: A in 252..255) */
    const int m = L->Q[p + 3] - 252;
    double c[3], s2 = 0.0;
    for (int k = 0; k < 3; k++) {
        c[k] = (L->Q[p + (size_t)k] / 255.0 - 0.5) * 1.4142135623730951;
        s2 += c[k] * c[k];
    }
    for (int k = 0, j = 0; k < 4; k++) g->q[k] = k == m ? sqrt(s2 < 1.0 ? 1.0 - s2 : 0.0) : c[j++];
    if (sh) {
        for (int ch = 0; ch < 3; ch++) sh[ch] = L->ccb[L->C[p + (size_t)ch]];
        if (L->sh_k > 1) {
            const size_t lab = (size_t)(L->lab[p] | L->lab[p + 1] << 8);
            const uint8_t *t = L->cen + 4 * ((lab / 64) * (size_t)L->cen_w + (lab % 64) * (size_t)L->K);
            for (int k = 1; k < L->sh_k; k++)
                for (int ch = 0; ch < 3; ch++) sh[3 * k + ch] = L->hcb[t[4 * (size_t)(k - 1) + (size_t)ch]];
        }
    }
}

/* The per-Gaussian images: all of means_l's size, enough texels for count. */
static spr_result same_size(const char *path, const char *name, const sog_image *im, const sog_image *ref, size_t n, spr_error *err)
{
    if (im->w != ref->w || im->h != ref->h)
        return spr__fail(err, SPR_E_FORMAT, "%s: %s is %dx%d, means_l %dx%d (every per-Gaussian image has one size)", path, name, im->w, im->h, ref->w,
                         ref->h);
    if ((uint64_t)im->w * (uint64_t)im->h < n)
        return spr__fail(err, SPR_E_FORMAT, "%s: %s: %dx%d texels hold fewer than the %zu Gaussians of meta.json's count", path, name, im->w, im->h, n);
    return SPR_OK;
}

static spr_result sog_parse(sog_src *s, const char *json, size_t jlen, const spr__gauss_opts *o, spr_cloud *c, spr_error *err)
{
    const char *path = s->path;
    cJSON *meta = cJSON_ParseWithLength(json, jlen);
    if (!meta || !cJSON_IsObject(meta)) {
        cJSON_Delete(meta);
        return spr__fail(err, SPR_E_FORMAT, "%s: meta.json is not a JSON object", path);
    }
    spr_result r = SPR_OK;
    enum { ML, MU, QU, SC, S0, HC, HL, NIMG };
    sog_image im[NIMG];
    memset(im, 0, sizeof im);
    sog_layout *L = calloc(1, sizeof *L);
    const char *files[NIMG] = {0};
    double v, cnt = 0.0, bands = 0.0, palette = 0.0;
    const cJSON *shn = cJSON_GetObjectItemCaseSensitive(meta, "shN");
    if (!L) { r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path); goto done; }
    if (!num(meta, "version", &v)) {
        r = spr__fail(err, SPR_E_FORMAT, "%s: meta.json has no \"version\": a version 1 SOG, which is not read (splat-transform writes version 2: "
                                         "convert it again)", path);
        goto done;
    }
    if (v != 2.0) { r = spr__fail(err, SPR_E_FORMAT, "%s: meta.json: SOG version %g is not read (version 2 is)", path, v); goto done; }
    if (!num(meta, "count", &cnt) || cnt != floor(cnt) || cnt < 1.0 || cnt > SPR_MAX_SPLATS) {
        r = spr__fail(err, SPR_E_FORMAT, "%s: meta.json: \"count\" is not a whole number of Gaussians in 1..%u", path, SPR_MAX_SPLATS);
        goto done;
    }
    L->n = (size_t)cnt; /* nothing is allocated for it before the images, whose size bounds it, are read */
    const cJSON *model = cJSON_GetObjectItemCaseSensitive(meta, "model");
    if (model && (!cJSON_IsString(model) || (strcmp(model->valuestring, "default") && strcmp(model->valuestring, "antialiased")))) {
        r = spr__fail(err, SPR_E_FORMAT, "%s: meta.json: \"model\" %s%s%s is not read (default and antialiased are)", path,
                      cJSON_IsString(model) ? "\"" : "", cJSON_IsString(model) ? model->valuestring : "(not a string)", cJSON_IsString(model) ? "\"" : "");
        goto done;
    }
    if ((r = attribute(path, meta, "means", 2, files + ML, NULL, L->mins, L->maxs, err)) ||
        (r = attribute(path, meta, "quats", 1, files + QU, NULL, NULL, NULL, err)) ||
        (r = attribute(path, meta, "scales", 1, files + SC, L->scb, NULL, NULL, err)) ||
        (r = attribute(path, meta, "sh0", 1, files + S0, L->ccb, NULL, NULL, err)))
        goto done;
    if (shn) {
        if ((r = attribute(path, meta, "shN", 2, files + HC, L->hcb, NULL, NULL, err))) goto done;
        if (!num(shn, "bands", &bands) || (bands != 1.0 && bands != 2.0 && bands != 3.0) || !num(shn, "count", &palette) ||
            palette != floor(palette) || palette < 1.0 || palette > 65536.0) {
            r = spr__fail(err, SPR_E_FORMAT, "%s: meta.json: shN.bands is not 1, 2 or 3, or shN.count is not a palette size in 1..65536", path);
            goto done;
        }
        L->K = bands == 1.0 ? 3 : bands == 2.0 ? 8 : 15;
    }
    for (int k = 0; k < NIMG; k++) {
        if (!files[k]) continue;
        if ((r = sog_webp(s, files[k], &im[k], err)) || (k != HC && (r = same_size(path, files[k], &im[k], &im[ML], L->n, err)))) goto done;
    }
    if (shn && (im[HC].w != 64 * L->K || (uint64_t)im[HC].h * 64 < (uint64_t)palette)) {
        r = spr__fail(err, SPR_E_FORMAT, "%s: %s is %dx%d: %d bands need 64·%d texels a row and %.0f palette entries need %.0f rows", path, files[HC],
                      im[HC].w, im[HC].h, (int)bands, L->K, palette, ceil(palette / 64.0));
        goto done;
    }
    /* what the decoder cannot report itself: a quaternion's index byte, an SH label beyond the palette */
    for (size_t i = 0; i < L->n; i++) {
        const uint8_t a = im[QU].rgba[4 * i + 3];
        if (a < 252) {
            r = spr__fail(err, SPR_E_FORMAT, "%s: %s texel (%zu, %zu) (Gaussian %zu): alpha %d is not 252..255 (252 + the index of the largest component)",
                          path, files[QU], i % (size_t)im[QU].w, i / (size_t)im[QU].w, i, a);
            goto done;
        }
        if (shn) {
            const size_t lab = (size_t)(im[HL].rgba[4 * i] | im[HL].rgba[4 * i + 1] << 8);
            if (lab >= (size_t)palette) {
                r = spr__fail(err, SPR_E_FORMAT, "%s: %s texel (%zu, %zu) (Gaussian %zu): label %zu, beyond the palette's %.0f entries", path, files[HL],
                              i % (size_t)im[HL].w, i / (size_t)im[HL].w, i, lab, palette);
                goto done;
            }
        }
    }
    L->L = im[ML].rgba, L->U = im[MU].rgba, L->Q = im[QU].rgba, L->S = im[SC].rgba, L->C = im[S0].rgba;
    L->lab = im[HL].rgba, L->cen = im[HC].rgba, L->cen_w = im[HC].w;
    if ((r = spr__gauss_alloc(c, L->n, 1 + L->K, o, path, err))) goto done;
    L->sh_k = c->sh_k;
    c->gauss_aa = cJSON_IsString(model) && !strcmp(model->valuestring, "antialiased"); /* splat-transform 3.x: trained with Mip-Splatting's filter */
    r = spr__gauss_fill(c, o, sog_splat, L, path, err);
done:
    for (int k = 0; k < NIMG; k++) WebPFree(im[k].rgba);
    free(L);
    cJSON_Delete(meta);
    return r;
}

spr_result spr__parse_sog(const char *path, const char *buf, size_t len, const spr__gauss_opts *o, spr_cloud *c, spr_error *err)
{
    memset(c, 0, sizeof *c);
    sog_src s = {path, NULL, NULL, 0, "", len};
    zip_error_t ze;
    zip_error_init(&ze);
    zip_source_t *src = zip_source_buffer_create(buf, len, 0, &ze);
    if (src) s.zip = zip_open_from_source(src, ZIP_RDONLY | ZIP_CHECKCONS, &ze);
    if (!s.zip) {
        spr_result r = spr__fail(err, SPR_E_FORMAT, "%s: not a zip archive (a .sog zips meta.json and its WebP images): %s", path, zip_error_strerror(&ze));
        if (src) zip_source_free(src);
        zip_error_fini(&ze);
        return r;
    }
    zip_error_fini(&ze);
    unsigned char *json;
    size_t jlen;
    spr_result r = sog_read(&s, "meta.json", &json, &jlen, err);
    if (!r) {
        r = sog_parse(&s, (const char *)json, jlen, o, c, err);
        free(json);
    }
    zip_discard(s.zip); /* frees the source too */
    return r;
}

spr_result spr__parse_sog_folder(const char *path, const char *buf, size_t len, const spr__gauss_opts *o, spr_cloud *c, spr_error *err)
{
    memset(c, 0, sizeof *c);
    sog_src s = {path, NULL, NULL, 0, "", len};
    const char *slash = strrchr(path, '/');
    const size_t dl = slash ? (size_t)(slash - path) + 1 : 0;
    if (dl >= sizeof s.dir) return spr__fail(err, SPR_E_ARG, "%s: the path is too long", path);
    memcpy(s.dir, path, dl);
    s.dir[dl] = '\0';
    return sog_parse(&s, buf, len, o, c, err);
}

spr_result spr__parse_sog_files(const char *path, const spr__sog_file *files, size_t n, const spr__gauss_opts *o, spr_cloud *c, spr_error *err)
{
    memset(c, 0, sizeof *c);
    sog_src s = {path, NULL, files, n, "", 0};
    const spr__sog_file *meta = NULL;
    for (size_t k = 0; k < n; k++) {
        s.bytes += files[k].len;
        if (!strcmp(files[k].name, "meta.json")) meta = &files[k];
    }
    if (!meta) return spr__fail(err, SPR_E_FORMAT, "%s: no meta.json", path);
    return sog_parse(&s, (const char *)meta->data, meta->len, o, c, err);
}
