/* spr_algo.h — the rendering algorithms, written once over spr_backend.
 *
 * spr_render() runs one algorithm as a sequence of named passes, calls the
 * pass hook after each (dumps, traces: SPEC §8) and returns the final image.
 * Algorithms: pbr2p1 (SPEC §4.1, algo_pbr2p1.c) and deferred (SPEC §4.2,
 * algo_deferred.c).
 */
#ifndef SPR_ALGO_H
#define SPR_ALGO_H

#include "spr_backend.h"
#include "spr_group.h"

typedef enum spr_algo {
    SPR_ALGO_DEFERRED = 0,
    SPR_ALGO_PBR2P1,
    SPR_ALGO__COUNT
} spr_algo;
int spr_algo_from_name(const char *name);  /* −1 if unknown */
const char *spr_algo_name(spr_algo a);

/* What the hook sees after a pass. */
typedef struct spr_pass_info {
    int index;                    /* 0-based, in execution order */
    const char *name;             /* "visibility", "blend", "normalize", "geometry", "composite" */
    int group;                    /* k of a geometry pass, −1 otherwise */
    const spr_pass_state *state;  /* NULL for compositing passes */
    int target;                   /* the target the pass wrote */
    spr_draw_stats stats;
    double ms;
} spr_pass_info;
typedef void (*spr_pass_hook)(void *user, spr_backend *b, const spr_pass_info *info);

typedef struct spr_render_desc {
    spr_algo algo;
    spr_kernel kernel;
    int voronoi;                 /* deferred: Voronoi test value (§3.3) */
    double eps;                  /* world units; 0 = 2 × mean splat radius */
    double lowres_n;             /* 0 = derived from ε (§3.3) */
    float background[3];
    const spr_groups *groups;    /* deferred; NULL = one group */
    spr_pass_hook hook;
    void *hook_user;
} spr_render_desc;

typedef struct spr_pass_record {
    char name[32];
    int group;
    spr_draw_stats stats;
    double ms;
} spr_pass_record;

typedef struct spr_render_result {
    float *rgba;         /* W·H·4: final colour, alpha 1 where covered; row 0 = bottom */
    int width, height;
    float eps_t;
    spr_lowres lowres;
    int K;
    int n_passes;
    spr_pass_record *passes;
} spr_render_result;

/* Run desc->algo for `cloud` seen through `view` on backend b. */
spr_result spr_render(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc,
                      spr_render_result *out, spr_error *err);
void spr_render_result_free(spr_render_result *r);

/* ---- internal: shared by the algorithm files ---- */
typedef struct spr__run {
    spr_backend *b;
    const spr_cloud *cloud;
    const spr_render_desc *desc;
    spr_render_result *out;
    spr_error *err;
    float eps_t;
    spr_lowres lowres;
    int pass_cap;
} spr__run;
spr_result spr__run_draw(spr__run *run, const char *name, int group, int target, const spr_draw_desc *d);
spr_result spr__run_composite(spr__run *run, const char *name, const spr_composite_desc *c);
spr_result spr__algo_pbr2p1(spr__run *run, int *final_target);
spr_result spr__algo_deferred(spr__run *run, int *final_target);

#endif
