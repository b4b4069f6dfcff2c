/* spr__options.h — the option tables behind the command line and scene
 * files (internal to splatref: the `splatref` tool and spr_scene_load()).
 *
 * Each command declares its options in a table; spr__parse() rejects
 * anything not in it with one line and exit status 2.  Values are read with
 * the spr__get_* helpers, which name the option in their error messages.
 * A scene is built from option values by spr__scene_setup(); a scene file
 * is those values in sections (spr__scene_read(), docs/scene-format.md).
 */
#ifndef SPR__OPTIONS_H
#define SPR__OPTIONS_H

#include <stddef.h>
#include <stdio.h>
#include <cjson/cJSON.h>
#include "spr_scene.h"

struct spr_gl_desc; /* spr_glbackend.h */

typedef struct spr__opt {
    const char *name;   /* without the leading "--" */
    const char *arg;    /* NULL for a flag, else the metavariable shown in --help */
    const char *help;
} spr__opt;

#define SPR__MAX_OPTS 128
typedef struct spr__args {
    const char *cmd;
    const spr__opt *opts;
    const char *value[SPR__MAX_OPTS]; /* NULL = not given; flags get "1" */
    unsigned char used[SPR__MAX_OPTS]; /* read by the command (spr__get) */
    unsigned char from_scene[SPR__MAX_OPTS]; /* value read from --scene (never refused as unused) */
    char *scene_text[SPR__MAX_OPTS]; /* the values --scene gave, owned (spr__scene_forget) */
    char scene_hash[32];  /* the scene's model.fnv1a64 while its model is used ("" otherwise) */
    char scene_file[1024];
    const char *positional[4];
    int n_positional;
    spr_error *sink;      /* set: messages go here instead of stderr (the library's callers) */
    spr_cloud *cloud_in;  /* set: the model is this cloud (spr_ffi.h's arrays), taken over by spr__load_model and zeroed */
    int camera_all;       /* set by check: --camera all is allowed (the scene is set up with the first entry's camera) */
} spr__args;

/* 0 on success, 1 when --help was printed, 2 after printing an error. */
int spr__parse(spr__args *a, const char *cmd, const spr__opt *opts, const char *usage, int max_positional, int argc, char **argv);
/* The value of --NAME (NULL when not given), marking the option as used. */
const char *spr__get(spr__args *a, const char *name);
/* −1 after one line naming the first option given but never read: an option
 * the command, algorithm or grouping chosen does not use. */
int spr__reject_unused(spr__args *a);
int spr__flag(spr__args *a, const char *name);
/* The helpers print "splatref CMD: --NAME: …" and return −1 on bad values. */
int spr__get_double(spr__args *a, const char *name, double *out, double lo, double hi);
int spr__get_int(spr__args *a, const char *name, int *out, int lo, int hi);
int spr__get_size(spr__args *a, const char *name, size_t *out, size_t lo, size_t hi);
int spr__get_vec3(spr__args *a, const char *name, double out[3]);
int spr__get_wh(spr__args *a, const char *name, int *w, int *h);
void spr__error(spr__args *a, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Progress on stderr, only when it is a terminal and --quiet is absent. */
spr_progress spr__progress(int quiet);
/* Readers' warnings: "splatref CMD: warning: …" on stderr (a library call: none). */
spr_warn spr__warn(spr__args *a);

int spr__domain_opts(spr__args *a, spr_scene_domain *o);
/* Replace level l's basis by its merged one when --merge was given. */
int spr__domain_merge(spr__args *a, const spr_cloud *c, const spr_scene_domain *o, spr_decomp *dc, int l, size_t *before);
/* Decompose c and build the primitives of o->level (default 2). 0 or −1 after one line. */
int spr__domain_prims(spr__args *a, const char *model, const spr_cloud *c, spr_scene_domain *o, int threads, const spr_progress *prog,
                     spr_rects *out, spr_prims_stats *st);

/* The model options of SPR__MODEL_OPTS (model, points for built-ins only,
 * radius rule, threads, quiet) into s->model, s->threads and ld. */
int spr__model_opts(spr__args *a, spr_scene *s, spr_load_desc *ld);
/* Load s->model, time it, and frame s->cam on it.  0 or −1 after one line. */
int spr__load_model(spr__args *a, spr_scene *s, const spr_load_desc *ld);
/* Read the grouping options (method from `method_opt`: "groups" or
 * "method"), only those the method uses.  0, or −1 after one line. */
int spr__parse_group_opts(spr__args *a, const char *method_opt, spr_grouping_desc *gd, const char **hash_near);
/* Group s->cloud as gd says (hash mode 3's eye from s->cam). */
int spr__make_groups(spr__args *a, spr_scene *s, spr_grouping_desc *gd, const char *hash_near);
/* What a scene's options ask to be done, once they are all read and checked. */
typedef struct spr__scene_plan {
    spr_load_desc ld;       /* how to load the model */
    spr_grouping_desc gd;   /* SPR_USES_GROUPS: how to group */
    const char *hash_near;  /* hash mode 3: --hash-near as given ("centre" or a distance) */
    unsigned uses;          /* SPR_USES_* of the algorithm(s) */
    int stream, quiet;
    const char *env;        /* SPR_USES_ENV: the cube map, sky | checker | a folder; NULL: none */
    int env_size;           /* texels a side of a built-in cube map */
    const char *save;       /* --save-scene F, or NULL */
    int save_matrices;      /* --scene-camera matrices */
} spr__scene_plan;
/* Read and check every scene option into s (camera, model name, domain
 * options), rd (no hook, no targets) and p, refusing options not used
 * (spr__reject_unused); nothing is loaded or built.  0 or −1 after one line. */
int spr__scene_opts(spr__args *a, spr_scene *s, spr_render_desc *rd, spr__scene_plan *p, int allow_all);
/* spr__scene_opts, then the work: the cube map, load and frame the model,
 * the BSP tree, the groups and the domain primitives when the algorithm uses
 * them, --save-scene.  allow_all: accept --algo all.  0 or −1 after one line. */
int spr__scene_setup(spr__args *a, spr_scene *s, spr_render_desc *rd, int allow_all);
/* A cameras.json entry's pinhole (its image w×h) into c; with size_given c's
 * width and height stay and the intrinsics scale to them. */
void spr__camera_pinhole_sized(spr_camera_desc *c, const spr_pinhole *p, int w, int h, int size_given);
/* Move a set-up scene to another pinhole view (check --camera all): the
 * camera as the options gave it, with this pinhole, framed on the model's
 * bounds again (near/far), and its view.  0, or −1 after one line. */
int spr__scene_move_camera(spr__args *a, spr_scene *s, const spr_pinhole *p, int w, int h);
/* The GL backend's options into d (from spr_gl_defaults): --gl-driver, and
 * --gl-device where the command has it.  0, or −1 after one line. */
int spr__gl_opts(spr__args *a, struct spr_gl_desc *d);
/* "cpu" or "gl" backend (gl: NULL for the defaults), or NULL after printing the reason. */
spr_backend *spr__backend(spr__args *a, const char *name, int threads, const struct spr_gl_desc *gl);

/* Scene files (cli_scenefile.c, docs/scene-format.md).  spr__parse reads
 * --scene F itself: its values fill the options the command line did not
 * give.  0, or −1 after one line naming the file and the key. */
int spr__scene_read(spr__args *a, const char *file);
/* Free the values spr__scene_read gave a (they are NULL again); once done
 * with a and with what spr__scene_setup made of it.  Commands need not. */
void spr__scene_forget(spr__args *a);
/* 1 for the options that determine an image (a scene file's keys) and --scene. */
int spr__is_scene_option(const char *name);
/* −1 after one line when the model file differs from the scene's hash. */
int spr__scene_check_model(spr__args *a, const char *model);
/* Write what determines s's image to path; matrices: the camera as raw
 * view and projection matrices instead of eye/target/up/fov. */
int spr__scene_save(spr__args *a, const spr_scene *s, const spr_render_desc *rd, const char *path, int matrices);

/* Print root (consumed) to path through a temporary file; 0 or −1 after a line. */
int spr__write_json(spr__args *a, const char *path, cJSON *root);

#endif
