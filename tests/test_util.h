/* test_util.h — tiny scenes with values that can be worked out by hand.
 *
 * The hand camera: orthographic, eye (0,0,2) looking at the origin, view
 * height 2, near 1, far 3.  For a W×H image the pixel centre (x, y) is at
 * world (−1 + (x+0.5)·2/W, −1 + (y+0.5)·2/H); its ray starts at z = 1
 * (o0, t = 0) and ends at z = −1 (t = 1): d = (0, 0, −2), so a splat at
 * world z has t = (1 − z)/2.
 */
#ifndef TEST_UTIL_H
#define TEST_UTIL_H

#include <check.h>
#include "spr_algo.h"
#include "spr_io.h"
#include "spr_swrast.h"
#include "spr_glbackend.h"

void tu_hand_view(int W, int H, spr_view *v);
/* A view from (0, 0, eye_z) at the origin: perspective with fov_deg > 0, else orthographic ortho_height high. */
void tu_view(double eye_z, double fov_deg, double ortho_height, double near_plane, double far_plane, int W, int H, spr_view *v);
/* Cloud of n splats with the given positions; normals +z, radius r, colour white. */
void tu_cloud(spr_cloud *c, size_t n, const double *xyz, float r);
/* Uniform in [0, 1) from the LCG state *s (a fixed seed: the same values on every machine). */
double tu_uniform(uint64_t *s);
void tu_set_color(spr_cloud *c, size_t i, float r, float g, float b);
/* Render on a fresh CPU backend with `threads`; ck_assert on failure. */
void tu_render(const spr_view *v, const spr_cloud *c, const spr_render_desc *d, int threads, spr_render_result *out);
/* The GL suites' backend description: spr_gl_defaults with the driver that
 * SPLATREF_TEST_GL_DRIVER names (llvmpipe | zink | default; unset: EGL's
 * choice), so CTest gl_zink runs the gl suite on zink.  An unknown name ends
 * the run (exit 2) with one line. */
void tu_gl_desc(spr_gl_desc *d);
/* A built-in model of about n points ("builtin:NAME"), or fail the test. */
spr_cloud tu_builtin(const char *name, size_t n);
/* SPLATREF_TEST_SIZE=small (the sanitizer build of .ci/run): the scenes of
 * tu_model shrink — built-ins to a quarter of n, data files to every 8th
 * splat — so instrumented runs stay fast; assertions are unchanged. */
int tu_small(void);
/* A built-in model ("builtin:…", n points) or a CGAL data file (n ignored). */
spr_cloud tu_model(const char *name, size_t n);
/* Load a CGAL data file (SPR_DATA_DIR/rel) or fail the test. */
void tu_load(const char *rel, spr_cloud *c);
const char *tu_data(const char *rel);

/* The real bunny framed by the default camera at W×H, with MGC groups
 * (c, both relaxations); K in g->K.  Free with tu_bunny_free(). */
typedef struct tu_bunny {
    spr_cloud cloud;
    spr_view view;
    spr_groups groups;
} tu_bunny;
void tu_bunny_scene(tu_bunny *s, int W, int H, double c);
void tu_bunny_free(tu_bunny *s);

/* Run `prog` (the splatref CLI when NULL) with NAME=VALUE added to its
 * environment when env is not NULL; the exit status, stderr (and stdout
 * when out_too) in err. */
/* A fresh folder /tmp/spr_TAG_XXXXXX written into dir. */
void tu_tmpdir(char dir[64], const char *tag);
/* dir/name, in one of 16 rotating buffers. */
const char *tu_in(const char *dir, const char *name);
/* The JSON file at path, parsed (the test fails when it cannot be read or parsed); cJSON_Delete it. */
struct cJSON *tu_read_json(const char *path);
int tu_run(const char *prog, const char *env, int out_too, char *const argv[], char *err, size_t cap);
/* 1 when files a and b hold the same bytes (both must open). */
int tu_same_file(const char *a, const char *b);

#endif
