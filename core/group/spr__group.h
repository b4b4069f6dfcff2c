/* spr__group.h — grouping's internal interfaces (not installed). */
#ifndef SPR__GROUP_H
#define SPR__GROUP_H

#include "spr_group.h"
#include "spr__spatial.h"

/* The pair graph of a cloud left on its Morton-ordered copy: *s gets the
 * copy (free with spr__spatial_free) and *gs the rows i of the copy with
 * row[s->order[i]] == want, each with the neighbours j (copy indices, in
 * the order found) that come before it: before[s->order[j]] <
 * before[s->order[i]] (in, before, row: in the cloud's indices).  With
 * `in`, only the splats i with in[i] take part, as rows and as neighbours:
 * the copy holds those alone (s->c.n of them; s->order gives their cloud
 * indices, s->rank is UINT32_MAX for the others).  For a caller that walks
 * the rows itself: no conversion to the cloud's indices. */
spr_result spr__pair_graph_spatial(const spr_cloud *c, double f, const unsigned char *in, const unsigned char *row, unsigned char want,
                                   const uint32_t *before, int threads, const spr_progress *prog, spr__spatial *s, spr_graph *gs,
                                   spr_error *err);

/* spr_overlap_graph_build and, into *w (malloc'd), spr_wgc_weights of it:
 * the same bits, the weights computed on the copy before its conversion. */
spr_result spr__overlap_graph_weights(const spr_cloud *c, double eps, int threads, const spr_progress *prog, spr_overlap_graph *og, float **w,
                                      spr_error *err);

#endif
