/* check.c — an image against the reference under PARITY.md's tiers. */
#include "spr_check.h"
#include "spr_image.h"
#include "spr_parity.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *spr_tier_name(spr_tier t) { return t == SPR_TIER_A ? "A" : t == SPR_TIER_B ? "B" : "C"; }

/* The integer value a float has in an image of `bits` bits per value: 8
 * through spr_to_u8 (PARITY rule 8), 16 with the same rounding. */
static long quantised(float v, int bits)
{
    if (bits == 8) return spr_to_u8(v);
    float c = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
    if (c != c) c = 0.0f;
    return lrintf(c * 65535.0f);
}

/* Does channel value b (test) match a (reference) under d?  Tier A: same
 * bits (float) or same integer value; Tier B: within ulp and within lsb. */
static int matches(float a, float b, const spr_check_desc *d)
{
    if (d->bits == 32) {
        uint64_t u = spr_ulp_distance(a, b);
        if (u == 0) return 1;
        if (d->tier == SPR_TIER_A || (d->ulp < 0 && d->lsb < 0)) return 0;
        return (d->ulp < 0 || u <= (uint64_t)d->ulp) && (d->lsb < 0 || labs(quantised(a, 8) - quantised(b, 8)) <= d->lsb);
    }
    long la = quantised(a, d->bits), lb = quantised(b, d->bits);
    return la == lb || (d->tier != SPR_TIER_A && d->lsb >= 0 && labs(la - lb) <= d->lsb);
}

static int pixel_matches(const float *ref, const float *test, size_t pr, size_t pt, int ch, const spr_check_desc *d)
{
    for (int c = 0; c < ch; c++)
        if (!matches(ref[pr * ch + c], test[pt * ch + c], d)) return 0;
    return 1;
}

/* Some pixel of `in` within one pixel of (x, y) matches pixel p of `of`
 * (ref_first: `of` is the reference). */
static int near_match(const float *of, const float *in, int ref_first, int w, int h, int x, int y, int ch, const spr_check_desc *d)
{
    const size_t p = (size_t)y * w + x;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            int qx = x + dx, qy = y + dy;
            if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
            size_t q = (size_t)qy * w + qx;
            if (ref_first ? pixel_matches(of, in, p, q, ch, d) : pixel_matches(in, of, q, p, ch, d)) return 1;
        }
    return 0;
}

void spr_check_images(const float *ref, const float *test, int w, int h, int ch, const spr_check_desc *d, spr_check_result *r,
                      float *heat)
{
    spr_check_images_state(ref, test, w, h, ch, d, r, heat, NULL);
}

void spr_check_images_state(const float *ref, const float *test, int w, int h, int ch, const spr_check_desc *d, spr_check_result *r,
                            float *heat, unsigned char *state_out)
{
    memset(r, 0, sizeof *r);
    r->first_x = r->first_y = r->first_channel = -1;
    r->pixels = (size_t)w * h;
    const int lsb_bits = d->bits == 32 ? 8 : d->bits;
    double sum_abs = 0.0, max_sum = 0.0;
    int first_is_failing = 0;
    double *pix_sum = heat ? calloc(r->pixels, sizeof *pix_sum) : NULL;
    unsigned char *state = state_out ? state_out : heat ? calloc(r->pixels, 1) : NULL; /* 0 equal, 1 within, 2 rescued, 3 failing */
    if (state_out) memset(state_out, 0, r->pixels);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const size_t p = (size_t)y * w + x;
            int differs = 0, fails = 0, fc = -1;
            double s = 0.0;
            for (int c = 0; c < ch; c++) {
                const float a = ref[p * ch + c], b = test[p * ch + c];
                const long la = quantised(a, lsb_bits), lb = quantised(b, lsb_bits);
                const int lsb = (int)labs(la - lb);
                /* integer images: the difference of the stored values */
                const double ad = d->bits == 32 ? fabs((double)a - (double)b) : lsb / (d->bits == 8 ? 255.0 : 65535.0);
                sum_abs += isfinite(ad) ? ad : 0.0;
                s += isfinite(ad) ? ad : 1.0;
                if (d->bits == 32 ? spr_ulp_distance(a, b) != 0 : la != lb) {
                    differs = 1;
                    if (fc < 0) fc = c;
                }
                if (d->bits == 32) {
                    uint64_t u = spr_ulp_distance(a, b);
                    if (u > r->max_ulp) r->max_ulp = u;
                }
                if (lsb > r->max_lsb) r->max_lsb = lsb;
                if (ad > r->max_abs || !isfinite(ad)) r->max_abs = isfinite(ad) ? ad : INFINITY;
                if (d->tier != SPR_TIER_C && !matches(a, b, d) && !fails) fails = 1, fc = c; /* Tier C fails nothing */
            }
            if (pix_sum) pix_sum[p] = s, max_sum = s > max_sum ? s : max_sum;
            if (!differs) continue;
            r->differing++;
            int rescued = 0;
            if (fails && d->tier == SPR_TIER_B && d->position)
                rescued = near_match(ref, test, 1, w, h, x, y, ch, d) && near_match(test, ref, 0, w, h, x, y, ch, d);
            if (state) state[p] = !fails ? 1 : rescued ? 2 : 3;
            if (rescued) r->rescued++;
            else if (fails) r->failing++;
            const int failing_now = fails && !rescued;
            if (r->first_x < 0 || (failing_now && !first_is_failing)) {
                r->first_x = x, r->first_y = y, r->first_channel = fc;
                r->first_ref = ref[p * ch + fc], r->first_test = test[p * ch + fc];
                first_is_failing = failing_now;
            }
        }
    r->mean_abs = r->pixels ? sum_abs / ((double)r->pixels * ch) : 0.0;
    spr_image_diff_stats zs; /* [ZP] §6.3's ε, as `compare --metric zp-eps` computes it (a grey plane counts as three channels) */
    spr_image_diff(ref, ch, test, ch, w, h, NULL, &zs, NULL);
    r->zp_eps = zs.zp_eps;
    r->pass = d->tier == SPR_TIER_C ? 1 : r->failing == 0;
    if (heat) {
        static const float hue[4][3] = {{0, 0, 0}, {0.2f, 0.4f, 1.0f}, {1.0f, 0.85f, 0.1f}, {1.0f, 0.15f, 0.1f}};
        for (size_t p = 0; p < r->pixels; p++) {
            /* brightness: at least 0.35 so a 1-LSB difference is visible, then by size */
            const float k = state && state[p] ? (float)(0.35 + 0.65 * (max_sum > 0.0 ? pix_sum[p] / max_sum : 0.0)) : 0.0f;
            for (int c = 0; c < 3; c++) heat[3 * p + c] = state ? hue[state[p]][c] * k : 0.0f;
        }
    }
    free(pix_sum);
    if (state != state_out) free(state);
}
