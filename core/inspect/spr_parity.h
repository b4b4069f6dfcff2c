/* spr_parity.h — compare two backends pass by pass, plane by plane (PARITY.md).
 *
 * spr_parity_run() renders the same scene on a reference backend and on a
 * backend under test, capturing every plane of every pass through the pass
 * hook, and reports for each plane: differing pixels, the largest
 * difference in ulps and in absolute value, and the first differing pixel
 * with both values.  Tier A (bit-exact) holds when every plane has 0
 * differing pixels and the fragment counts of every pass agree.
 */
#ifndef SPR_PARITY_H
#define SPR_PARITY_H

#include "spr_algo.h"

#define SPR_PLANE_FINAL SPR_PLANE__COUNT  /* the final image read back by spr_render */
#define SPR_PLANE_RECORDS (SPR_PLANE__COUNT + 1) /* a Gaussian preprocessing pass's records: rows of SPR_GREC_FLOATS values */
/* "final", "records" or the plane's name. */
const char *spr_parity_plane_name(int plane);

typedef struct spr_plane_diff {
    int pass;              /* index in execution order; −1 for the final image */
    char pass_name[32];
    int group;
    int plane;             /* spr_plane, SPR_PLANE_FINAL or SPR_PLANE_RECORDS */
    size_t values, differing_pixels;
    uint64_t max_ulp;      /* float planes: ulp distance; id/count planes: integer difference */
    double max_abs;
    int max_lsb;           /* float planes: largest difference of the 8-bit values (spr_to_u8) */
    int first_x, first_y, first_channel;  /* first differing pixel, row 0 = bottom; −1 if none (records: x the field, y the Gaussian) */
    double first_ref, first_test;
    char heatmap[256];     /* file name (in heatmap_dir) of the PNG written for a differing plane, "" otherwise */
} spr_plane_diff;

typedef struct spr_parity_report {
    int n_planes;
    spr_plane_diff *planes;
    int exact_planes;
    uint64_t max_ulp;
    int passes_ref, passes_test;
    int stats_mismatches;  /* passes whose generated/passed counts differ */
    char first_stats_mismatch[160];
} spr_parity_report;

/* Ordered ulp distance between two floats (0 for identical bits). */
uint64_t spr_ulp_distance(float a, float b);

/* Run desc_ref on `ref` and desc_test on `test` (normally the same desc;
 * different ones demonstrate a perturbation) and compare.  heatmap_dir:
 * where to write a diff heatmap PNG per differing plane (NULL: none);
 * label prefixes their names. */
spr_result spr_parity_run(spr_backend *ref, spr_backend *test, const spr_view *v, const spr_cloud *c,
                          const spr_render_desc *desc_ref, const spr_render_desc *desc_test, const char *heatmap_dir,
                          const char *label, spr_parity_report *rep, spr_error *err);
void spr_parity_report_free(spr_parity_report *rep);
/* 1 when every plane is bit-exact and every pass's counts agree. */
int spr_parity_exact(const spr_parity_report *rep);

#endif
