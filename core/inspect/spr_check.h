/* spr_check.h — compare an image with the reference under PARITY.md's tiers.
 *
 * Tier A is bit-exact: float images compare bits; 8- and 16-bit images
 * compare integer values (the reference converted by spr_to_u8, or its
 * 16-bit analogue).  Tier B bounds the error: a channel passes when its ulp
 * distance is at most `ulp` (float images) and its difference in LSB at
 * most `lsb` (integer images; float images on their 8-bit values), each
 * bound that is given (≥ 0) holding; with
 * `position` = 1 a failing pixel passes when a matching pixel lies within
 * one pixel, searched both ways (dEQP's position-deviation compare), and
 * such pixels are counted apart.  Tier C never passes or fails: it reports
 * [ZP] §6.3's ε and the mean difference only.
 */
#ifndef SPR_CHECK_H
#define SPR_CHECK_H

#include <stddef.h>
#include <stdint.h>
#include "spr_result.h"

typedef enum spr_tier { SPR_TIER_A = 0, SPR_TIER_B, SPR_TIER_C } spr_tier;

typedef struct spr_check_desc {
    spr_tier tier;
    int bits;          /* of the image under test: 8, 16 (integer values) or 32 (float) */
    int64_t ulp;       /* Tier B, float images: largest ulp distance that passes; −1: no bound */
    int lsb;           /* Tier B: largest difference in LSB that passes (float images: of their 8-bit values); −1: no bound */
    int position;      /* Tier B: 1 = ±1-pixel position tolerance */
} spr_check_desc;

typedef struct spr_check_result {
    size_t pixels;
    size_t differing;          /* pixels with any channel not bit-identical (in the compared representation) */
    size_t failing;            /* pixels beyond the tier's bounds */
    size_t rescued;            /* of those, pixels passing only with the position tolerance */
    uint64_t max_ulp;          /* float images */
    int max_lsb;               /* on the compared integer values (float images: their 8-bit values) */
    double max_abs;
    double mean_abs;           /* per channel, in [0,1] units */
    double zp_eps;             /* [ZP] §6.3's ε (spr_image_diff): Σ (|ΔR|+|ΔG|+|ΔB|) in 8 bits / pixels */
    int first_x, first_y, first_channel; /* first failing pixel (row 0 = bottom), else first differing; −1: none */
    double first_ref, first_test;
    int pass;                  /* Tier A/B verdict; Tier C: 1 (never fails) */
} spr_check_result;

/* ref and test: w·h pixels of ch channels each (row 0 = bottom).  heat:
 * NULL or 3·w·h floats receiving a heat map (black equal, blue within
 * bounds, yellow rescued by position, red failing, brighter = larger). */
void spr_check_images(const float *ref, const float *test, int w, int h, int ch, const spr_check_desc *d, spr_check_result *r,
                      float *heat);
/* The same, and state (NULL or w·h bytes) receiving each pixel's verdict:
 * 0 equal, 1 within the bounds, 2 passing only within one pixel, 3 failing. */
void spr_check_images_state(const float *ref, const float *test, int w, int h, int ch, const spr_check_desc *d, spr_check_result *r,
                            float *heat, unsigned char *state);
/* "A", "B" or "C". */
const char *spr_tier_name(spr_tier t);

#endif
