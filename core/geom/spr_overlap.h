/* spr_overlap.h — overlap areas between splats, by a fixed sample pattern.
 *
 * Every area here is integrated with the same 256 stratified samples on the
 * unit disk (16 equal-area rings × 16 sectors, ring k offset by half a
 * sector when k is odd), mapped onto a splat's plane with a tangent frame
 * derived from its normal alone, so results are reproducible to the bit
 * ([ZP] Eq. 8 leaves the integration open; SPEC §5.2 [decision]).
 */
#ifndef SPR_OVERLAP_H
#define SPR_OVERLAP_H

#include <stdint.h>
#include "spr_cloud.h"

#define SPR_DISK_SAMPLES 256
#define SPR_DISK_RINGS 16

/* A_ij of [ZP] Eq. 8: area of disk i within eps of plane j whose projection
 * lies in disk j (rounded to float, as stored in the overlap graph). */
double spr_overlap_area(const spr_cloud *c, size_t i, size_t j, double eps);
/* A_ij for the m splats js[] at once (the same arithmetic, one frame). */
void spr_overlap_areas(const spr_cloud *c, size_t i, const uint32_t *js, size_t m, double eps, float *out);
/* Whether A_ij > 0 (spr_overlap_areas' float), found without counting
 * every sample: it stops at the first ring with a sample that counts.  A
 * row holds disk i's frame for its tests against several j. */
typedef struct spr_overlap_row {
    const spr_cloud *c;
    size_t i;
    double eps, ri, e1[3], e2[3];
    int tiny; /* one sample's area rounds to 0 in float: the areas are counted */
} spr_overlap_row;
void spr_overlap_row_init(spr_overlap_row *row, const spr_cloud *c, size_t i, double eps);
int spr_overlap_row_positive(const spr_overlap_row *row, size_t j);

/* Clipped(p_i, r_i·own_scale, k) of [ZP] §4.4.2: the area of disk i (radius
 * r_i·own_scale) where some splat of cover[0..m) (radius r_j·cover_scale)
 * lies within eps of the sample and projects onto it (SPEC §5.2 [decision]). */
double spr_clipped_area(const spr_cloud *c, size_t i, double own_scale, const uint32_t *cover, size_t m, double cover_scale,
                        double eps);

/* The tangent frame (e1, e2) of a disk with unit normal n that the sample
 * pattern is laid on (internal; the tests' plain sample loop uses it). */
void spr__disk_frame(const float *n, double e1[3], double e2[3]);

#endif
