/* spr_profile_diff.h — why two renderer profiles (SPEC §10.9) differ at one
 * pixel, Gaussian by Gaussian (core/inspect/profile_diff.c; `explain
 * --gauss-profile A --vs B`). */
#ifndef SPR_PROFILE_DIFF_H
#define SPR_PROFILE_DIFF_H

#include "spr_algo.h"
#include "spr_scene.h"

#include <stdio.h>

/* "1 cull" … "9 colour": the rules of SPEC 10.9 by number (0: the skeleton). */
extern const char *const spr__gauss_rule_names[10];

typedef struct spr__pdiff_row {
    uint32_t id;        /* the Gaussian (file order) */
    char a[160], b[160]; /* its outcome at the pixel under each profile */
    char rule[160];     /* the rule(s) that make the difference */
} spr__pdiff_row;

typedef struct spr__pdiff {
    const spr_gauss_profile *a, *b;
    uint32_t color_a[4], color_b[4]; /* the pixel's final colour under each (float bits) */
    spr__pdiff_row *rows;
    int n, cap;
    int quiet; /* Gaussians neither profile blends here, dropped for different reasons (not listed) */
} spr__pdiff;

/* Profiles pa and pb (table rows) at pixel (x, y) (y from the bottom) of scene s with rd's other options: every
 * Gaussian treated differently, and why.  0, or −1 with err set. */
int spr__profile_diff(spr_scene *s, const spr_render_desc *rd, int pa, int pb, int x, int y, spr__pdiff *out, spr_error *err);
void spr__pdiff_free(spr__pdiff *d);

/* The table as text (core/inspect/profiles.c): rule r's value in words (0: the algorithm), the Markdown table of
 * docs/gaussians.md, and JSON (`profiles --json`, Python's splatref.profiles()). */
void spr__profile_rule_text(const spr_gauss_profile *p, int rule, char *out, size_t cap);
void spr__profiles_markdown(FILE *f);
struct cJSON *spr__profiles_json(void);

#endif
