/* spr__spatial.h — a spatially ordered working copy of a cloud (internal).
 *
 * Neighbour walks over a cloud in submission order touch scattered memory
 * (a resampled or captured cloud is in no spatial order at all): a copy of
 * the centres, normals and radii in Morton order keeps neighbours in nearby
 * cache lines.  The copy holds the same floats, so every per-pair result
 * computed on it has the same bits; callers map indices back through
 * order[] (copy → cloud) and rank[] (cloud → copy).
 */
#ifndef SPR__SPATIAL_H
#define SPR__SPATIAL_H

#include "spr_cloud.h"

typedef struct spr__spatial {
    spr_cloud c;      /* n, pos, nrm, radius only (the rest NULL) */
    uint32_t *order;  /* n: copy index → cloud index */
    uint32_t *rank;   /* n: cloud index → copy index */
} spr__spatial;

/* The permutation of c's splats by the Morton code of their centres (10
 * bits an axis over the bounds' cube), ties in submission order. */
spr_result spr__morton_order(const spr_cloud *c, const spr_bounds *b, uint32_t *order, spr_error *err);
/* The copy of c in Morton order; b: c's bounds. */
spr_result spr__spatial_make(const spr_cloud *c, const spr_bounds *b, int threads, spr__spatial *s, spr_error *err);
void spr__spatial_free(spr__spatial *s);

#endif
