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

/* RGB(A) float image with `channels` values per pixel (first 3 used) → PNG. */
spr_result spr_write_png(const char *path, const float *img, int w, int h, int channels, spr_error *err);
/* channels = 1 → "Pf", 3 or 4 → "PF" (first 3); little-endian scale −1. */
spr_result spr_write_pfm(const char *path, const float *img, int w, int h, int channels, spr_error *err);
/* Read a PFM (either endianness) into RGB or grey floats (malloc'd). */
spr_result spr_read_pfm(const char *path, float **img, int *w, int *h, int *channels, spr_error *err);

/* FNV-1a 64 of a byte buffer: the hash of a float image in the reference manifest. */
uint64_t spr_hash64(const void *data, size_t n);

#endif
