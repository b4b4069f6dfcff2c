/* spr_history.h — pixel history (SPEC §8), in the manner of RenderDoc's.
 *
 * spr_history_create() wraps a backend (as the trace backend does) and
 * records, for one pixel, every draw and composite of a frame: the pixel's
 * planes before and after each call as the backend holds them, every
 * fragment that reached the pixel (the backend's own values: the CPU
 * rasterizer's, or the GL programs' probe variant — spr_probe in
 * spr_backend.h) in submission order, and the notes of the composite
 * functions (each step of the §4.2 loop with its ε decision, …).  The
 * fixed-function stages are replayed on the recorded fragments with the
 * reference's depth test and blending (spr_fixed.h): each fragment gets the
 * test value it met, its outcome and the planes after it, and the replay is
 * checked against the planes the backend holds after the call.
 */
#ifndef SPR_HISTORY_H
#define SPR_HISTORY_H

#include "spr_algo.h"

typedef struct spr_hist_frag {
    spr_probe_frag f;
    float z_before;      /* the test plane when the fragment arrived */
    int passed;          /* the depth test: 1 pass, 0 fail, −1 none (list draws) */
    uint32_t after[SPR_PLANE__COUNT][4]; /* the pixel's planes after it (replayed; value bits) */
} spr_hist_frag;

typedef enum spr_hist_kind {
    SPR_HIST_SPLATS = 0,
    SPR_HIST_RECTS,
    SPR_HIST_COMPOSITE,
    SPR_HIST_GAUSS_RASTER, /* SPEC 10.4, 10.5: the pixel's loop over its tile's list, as notes (SPR_NOTE_GAUSS_*) */
    SPR_HIST_GAUSS_DRAW    /* SPEC 10.7: the ellipses' fragments (t = power, ρ = α), replayed under premultiplied over */
} spr_hist_kind;

typedef struct spr_hist_event {
    spr_hist_kind kind;
    int pass;                 /* spr_pass_info.index of the pass it belongs to (−1: none) */
    char pass_name[32];
    int group;
    int target;
    unsigned planes;          /* the target's planes */
    /* draws */
    spr_pass_state state;
    size_t submitted;         /* splats or rectangles submitted */
    int list, depth_mask, mask_target;
    int rect_output;          /* spr_rect_output of a rectangle draw */
    /* composites */
    spr_composite_op op;
    int n_inputs;
    int inputs[SPR_MAX_COMPOSITE_INPUTS];
    unsigned in_planes[SPR_MAX_COMPOSITE_INPUTS];
    uint32_t in_vals[SPR_MAX_COMPOSITE_INPUTS][SPR_PLANE__COUNT][4];
    float eps_t;
    /* the Gaussian rasterizers */
    float gprm[SPR_GPRM_COUNT];
    /* both */
    uint32_t before[SPR_PLANE__COUNT][4], after[SPR_PLANE__COUNT][4]; /* as the backend holds them */
    spr_hist_frag *frags;
    int n_frags;
    spr_probe_note *notes;
    int n_notes;
    int replay_matches;       /* draws: the replayed planes equal `after` (1), or not (0) */
    char replay_note[160];    /* the first plane where they do not */
} spr_hist_event;

typedef struct spr_history {
    int x, y;
    spr_hist_event *ev;
    int n, cap;
    int overflow;             /* more than SPR_PROBE_MAX records in one call */
    int labelled;             /* events already given a pass */
} spr_history;

/* A backend forwarding to `inner` (owned) and recording pixel (x, y) of
 * every draw and composite into h (not owned; zero it first).  NULL on
 * error (inner is destroyed then). */
spr_backend *spr_history_create(spr_backend *inner, int x, int y, spr_history *h, spr_error *err);
/* Give the events recorded since the last call the pass `info` (call it
 * from the render's pass hook). */
void spr_history_pass(spr_history *h, const spr_pass_info *info);
void spr_history_free(spr_history *h);

/* A plane value of the history as a double (id/count planes: the integer,
 * "none" ids −1). */
double spr_history_value(spr_plane p, uint32_t bits);

#endif
