/* spr__inspect.h — what `check`, `explain` and `parity` compute, as library
 * functions (internal to splatref): the command line prints them, the
 * foreign-language interface (spr_ffi.h) hands the same JSON to Python, so
 * both report the same numbers from the same code.
 */
#ifndef SPR__INSPECT_H
#define SPR__INSPECT_H

#include <cjson/cJSON.h>
#include "spr__options.h"
#include "spr_check.h"
#include "spr_history.h"
#include "spr_parity.h"

/* The names the histories print (explain's text and JSON). */
extern const char *const spr__depth_names[SPR_DEPTH__COUNT];
extern const char *const spr__func_names[SPR_FUNC__COUNT];
extern const char *const spr__blend_names[SPR_BLEND__COUNT];

/* ---- check ---- */
/* The reference of `plane` ("color"/NULL: the final image; "weight"; a
 * plane's name) after pass `pass` (−1: the last pass that has it), rendered
 * on the CPU reference: *ref (caller frees) holds w·h·*ch floats, what
 * describes it ("final colour", "depth after pass 3 (visibility)").  0, or
 * −1 after one line (spr__error). */
int spr__check_reference(spr__args *a, spr_scene *s, const spr_render_desc *rd, const char *plane, int pass, float **ref, int *ch,
                         char *what, size_t what_cap);
/* The tier and its bounds as `check --tier/--ulp/--lsb/--position-tolerance`
 * read them (tier NULL: A, or B when a bound is given; ulp < 0, lsb < 0:
 * none; Tier B without bounds: lsb 1).  0, or −1 after one line. */
int spr__check_tier(spr__args *a, const char *tier, double ulp, int lsb, int position, int bits, spr_check_desc *d);
/* Give test the reference's channels (a grey PNG of three equal channels
 * for a one-channel plane).  0, or −1 after one line naming `name`. */
int spr__check_channels(spr__args *a, const char *name, float **test, int *tch, int rch, int w, int h);
/* report.json of check and compare, less the file names of its pictures. */
cJSON *spr__check_json(const char *ref_label, const char *image, const char *what, int w, int h, int ch, const spr_check_desc *d,
                       const spr_check_result *r, const char *explain);
/* "bit-exact", "ulp <= 2, lsb <= 1", "diagnostics only" … */
void spr__check_bounds_text(const spr_check_desc *d, char *s, size_t cap);

/* ---- explain ---- */
typedef struct spr__history_run {
    const char *name;      /* "cpu" or "gl" */
    char renderer[600];
    spr_history h;
    int ok;
} spr__history_run;
/* Render s on "cpu" or "gl" (the probe variant) recording pixel (x, y):
 * 0, 1 when GL has no device here (err says so), −1 with err set. */
int spr__history_run_one(spr_scene *s, const spr_render_desc *rd, const char *which, const struct spr_gl_desc *gl, int x, int y, spr__history_run *out,
                         spr_error *err);
/* The first difference between two histories: *ev the call, *frag the
 * fragment (−1: not a fragment), what a description; 0 when identical. */
int spr__history_difference(const spr_history *c, const spr_history *g, int *ev, int *frag, char *what, size_t cap);
/* `explain --json`: the pixel, the scene, each run's history, and with two
 * runs whether they are identical and where they first differ. */
cJSON *spr__explain_json(const spr_scene *s, const spr_render_desc *rd, int x, int y, const spr__history_run *runs, int nr);

/* ---- parity ---- */
typedef struct spr__parity_set {
    const char *dir;        /* the report's directory once complete (heat map paths), NULL: none */
    const spr_scene *s;
    const char *renderer;
    int n;
    const char *algo[SPR_ALGO__COUNT];
    const spr_parity_report *rep[SPR_ALGO__COUNT];
} spr__parity_set;
/* parity --report's report.json. */
cJSON *spr__parity_json(const spr__parity_set *r);
/* "fma=1 avx=1 avx2=1 avx512f=0": the CPU features of this machine. */
const char *spr__cpu_flags(void);

#endif
