/* spr_image.h — image files: 8-bit PNG and float PFM (written atomically).
 *
 * Images in memory are bottom row first (GL convention, SPEC §2); PNG is
 * written top row first and PFM bottom row first, as each format defines.
 */
#ifndef SPR_IMAGE_H
#define SPR_IMAGE_H

#include <stddef.h>
#include <stdint.h>
#include "spr_result.h"

/* The one conversion to 8 bits for every backend: lrintf(clamp(v,0,1)·255),
 * round half to even as GL's unorm conversion (PARITY.md rule 8). */
uint8_t spr_to_u8(float v);

/* RGB(A) float image with `channels` values per pixel (first 3 used) → PNG.  On failure (a full disk…) no file is
 * left and err is one line: the path, the system's reason and libpng's own error, which is never printed. */
spr_result spr_write_png(const char *path, const float *img, int w, int h, int channels, spr_error *err);
/* RGBA float image → PNG with its alpha channel (texture atlases). */
spr_result spr_write_png_rgba(const char *path, const float *img, int w, int h, spr_error *err);
/* channels = 1 → "Pf", 3 or 4 → "PF" (first 3); little-endian scale −1. */
spr_result spr_write_pfm(const char *path, const float *img, int w, int h, int channels, spr_error *err);
/* Read a PFM (either endianness) into RGB or grey floats (malloc'd). */
spr_result spr_read_pfm(const char *path, float **img, int *w, int *h, int *channels, spr_error *err);

/* 8- or 16-bit PNG (grey, RGB, with or without alpha, palette) as floats in
 * [0, 1], 3 or 4 channels, row 0 = the bottom row. */
spr_result spr_read_png(const char *path, float **img, int *w, int *h, int *channels, spr_error *err);
/* .png or .pfm by the name's ending. */
spr_result spr_read_image(const char *path, float **img, int *w, int *h, int *channels, spr_error *err);
/* The same, with the bits per value of the file: 8 or 16 (PNG), 32 (PFM). */
spr_result spr_read_image_bits(const char *path, float **img, int *w, int *h, int *channels, int *bits, spr_error *err);
/* The size (and the bits per channel a read gives: 8 or 16 for PNG, 32 for PFM) a PNG's IHDR or a PFM's header
 * states, without decoding anything (so a caller that knows the size it
 * wants can refuse another before the image is allocated): 0, or an error when the header cannot be read (the full
 * read then says what is wrong). */
spr_result spr_image_size(const char *path, int *w, int *h, int *bits, spr_error *err);

/* Differences of two images of one size on their 8-bit values (spr_to_u8),
 * RGB (a grey image repeats its channel): [ZP] §6.3's
 * ε = Σ_pixels (|ΔR| + |ΔG| + |ΔB|) / numPixel over every pixel. */
typedef struct spr_image_diff_stats {
    size_t pixels;      /* W·H */
    size_t differing;   /* pixels with any channel different */
    int max_abs;        /* largest |Δ| of one channel, 0 … 255 */
    double mean_abs;    /* mean |Δ| per channel */
    double zp_eps;      /* [ZP]'s ε */
    size_t bg_pixels;   /* pixels where b is the background colour (8-bit) */
    double zp_eps_bg;   /* the part of ε from those pixels: a drawn where b has nothing */
} spr_image_diff_stats;
/* bg: the background colour for bg_pixels and zp_eps_bg (NULL: black);
 * heat: NULL, or 3·W·H floats that receive an RGB heat map of the
 * per-pixel Σ|Δ| (black = equal, white = the largest). */
spr_result spr_image_diff(const float *a, int ch_a, const float *b, int ch_b, int w, int h, const float *bg,
                          spr_image_diff_stats *st, float *heat);

/* FNV-1a 64 of a byte buffer: the hash of a float image in the reference manifest. */
uint64_t spr_hash64(const void *data, size_t n);
/* The same hash over data given in pieces: h = SPR_HASH64_INIT, then each piece. */
#define SPR_HASH64_INIT 0xcbf29ce484222325ull
uint64_t spr_hash64_continue(uint64_t h, const void *data, size_t n);
/* FNV-1a 64 of a whole file, read in pieces (a model's identity in scene files). */
spr_result spr_hash_file(const char *path, uint64_t *out, spr_error *err);

#endif
