/* cli.h — shared pieces of the `splatref` command line.
 *
 * Each subcommand declares its options in a table; cli_parse() rejects
 * anything not in it with one line and exit status 2.  Values are read with
 * the cli_get_* helpers, which name the option in their error messages.
 */
#ifndef CLI_H
#define CLI_H

#include <stddef.h>
#include <stdio.h>
#include "spr_algo.h"
#include "spr_io.h"
#include "spr_domain.h"
#include <cjson/cJSON.h>

typedef struct cli_opt {
    const char *name;   /* without the leading "--" */
    const char *arg;    /* NULL for a flag, else the metavariable shown in --help */
    const char *help;
} cli_opt;

#define CLI_MAX_OPTS 128
typedef struct cli_args {
    const char *cmd;
    const cli_opt *opts;
    const char *value[CLI_MAX_OPTS]; /* NULL = not given; flags get "1" */
    unsigned char used[CLI_MAX_OPTS]; /* read by the command (cli_get) */
    unsigned char from_scene[CLI_MAX_OPTS]; /* value read from --scene (never refused as unused) */
    char scene_hash[32];  /* the scene's model.fnv1a64 while its model is used ("" otherwise) */
    char scene_file[1024];
    const char *positional[4];
    int n_positional;
} cli_args;

/* 0 on success, 1 when --help was printed, 2 after printing an error. */
int cli_parse(cli_args *a, const char *cmd, const cli_opt *opts, const char *usage, int max_positional, int argc, char **argv);
/* The value of --NAME (NULL when not given), marking the option as used. */
const char *cli_get(cli_args *a, const char *name);
/* −1 after one line naming the first option given but never read: an option
 * the command, algorithm or grouping chosen does not use. */
int cli_reject_unused(cli_args *a);
int cli_flag(cli_args *a, const char *name);
/* The helpers print "splatref CMD: --NAME: …" and return −1 on bad values. */
int cli_get_double(cli_args *a, const char *name, double *out, double lo, double hi);
int cli_get_int(cli_args *a, const char *name, int *out, int lo, int hi);
int cli_get_size(cli_args *a, const char *name, size_t *out, size_t lo, size_t hi);
int cli_get_vec3(cli_args *a, const char *name, double out[3]);
int cli_get_wh(cli_args *a, const char *name, int *w, int *h);
void cli_error(cli_args *a, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Progress on stderr, only when it is a terminal and --quiet is absent. */
spr_progress cli_progress(int quiet);

/* A loaded scene: model, camera, view and grouping. */
/* The domain pipeline's options (cli_domopts.c). */
typedef struct cli_domain_opts_t {
    spr_decomp_desc dd;
    spr_prims_desc pd;
    int level;            /* −1: the default */
    int merge;
    double mflat, mdot;
    int level_used, levels;
    size_t regions;
    double ms_decomp;
} cli_domain_opts_t;
int cli_domain_opts(cli_args *a, cli_domain_opts_t *o);
/* Replace level l's basis by its merged one when --merge was given. */
int cli_domain_merge(cli_args *a, const spr_cloud *c, const cli_domain_opts_t *o, spr_decomp *dc, int l, size_t *before);
/* Decompose c and build the primitives of o->level (default 2). 0 or −1 after one line. */
int cli_domain_prims(cli_args *a, const char *model, const spr_cloud *c, cli_domain_opts_t *o, int threads, const spr_progress *prog,
                     spr_rects *out, spr_prims_stats *st);

typedef struct cli_scene {
    spr_cloud cloud;
    spr_camera_desc cam;
    spr_view view;
    spr_grouping g;
    const char *group_method;
    char model[1024];
    int threads;
    int all_algos;          /* parity/reference: --algo all (the default there) */
    spr_envmap env;         /* --env's cube map (texels NULL: none) */
    spr_rects rects;        /* the domain primitives of domain-* algorithms (n 0: none) */
    spr_prims_stats prims;
    cli_domain_opts_t dom;
    double load_ms;
} cli_scene;
/* The model options of CLI_MODEL_OPTS (model, points for built-ins only,
 * radius rule, threads, quiet) into s->model, s->threads and ld. */
int cli_model_opts(cli_args *a, cli_scene *s, spr_load_desc *ld);
/* Load s->model, time it, and frame s->cam on it.  0 or −1 after one line. */
int cli_load_model(cli_args *a, cli_scene *s, const spr_load_desc *ld);
/* Read the grouping options (method from `method_opt`: "groups" or
 * "method"), only those the method uses.  0, or −1 after one line. */
int cli_parse_group_opts(cli_args *a, const char *method_opt, spr_grouping_desc *gd, const char **hash_near);
/* Group s->cloud as gd says (hash mode 3's eye from s->cam). */
int cli_make_groups(cli_args *a, cli_scene *s, spr_grouping_desc *gd, const char *hash_near);
/* Read the scene options, load and frame the model, build the groups when
 * the algorithm uses them; fills rd (no hook).  allow_all: accept --algo all.
 * Options not used are refused (cli_reject_unused).  0 or −1 after one line. */
int cli_scene_setup(cli_args *a, cli_scene *s, spr_render_desc *rd, int allow_all);
/* "cpu" or "gl" backend, or NULL after printing the reason. */
spr_backend *cli_backend(cli_args *a, const char *name, int threads, int gl_device);
void cli_scene_free(cli_scene *s);

/* Scene files (cli_scenefile.c, docs/scene-format.md).  cli_parse reads
 * --scene F itself: its values fill the options the command line did not
 * give.  0, or −1 after one line naming the file and the key. */
int cli_scene_read(cli_args *a, const char *file);
/* −1 after one line when the model file differs from the scene's hash. */
int cli_scene_check_model(cli_args *a, const char *model);
/* Write what determines s's image to path; matrices: the camera as raw
 * view and projection matrices instead of eye/target/up/fov. */
int cli_scene_save(cli_args *a, const cli_scene *s, const spr_render_desc *rd, const char *path, int matrices);

#include "spr_history.h"
/* One backend's history of a frame at one pixel (cli_explain.c). */
typedef struct cli_history_run {
    const char *name;
    char renderer[600];
    spr_history h;
    int ok;
} cli_history_run;
/* Render s on "cpu" or "gl" (the probe variant) recording pixel (x, y):
 * 0, 1 when GL has no device here, −1 after one line. */
int cli_run_history(cli_scene *s, const spr_render_desc *rd, const char *which, int gl_device, int x, int y, cli_history_run *out);
struct spr_hist_event;
/* One call of a pixel history as text (cli_explain.c); other: the same
 * call on a second backend (NULL: none), diff_ev/diff_frag: the first
 * difference to mark (−1: none). */
void cli_explain_event(FILE *f, const struct spr_hist_event *e, int idx, const struct spr_hist_event *other, int diff_ev, int diff_frag,
                       const char *other_name);

/* Print root (consumed) to path through a temporary file; 0 or −1 after a line. */
int cli_write_json(cli_args *a, const char *path, cJSON *root);
/* [size of S_0, …, size of S_{K−1}]. */
cJSON *cli_json_group_sizes(const spr_groups *g);

/* Output directories that appear whole or not at all (cli_outdir.c): write
 * into tmp (DIR.tmpPID, made by begin), then end moves the files into DIR
 * (commit) or deletes them.  0, or −1 after one line. */
int cli_outdir_begin(cli_args *a, const char *opt, const char *dir, char *tmp, size_t cap);
int cli_outdir_end(cli_args *a, const char *opt, const char *tmp, const char *dir, int commit);

/* parity --random: N generated scenes from seed on both backends (cli_random.c). */
int cli_parity_random(cli_args *a, int count, uint64_t seed, const char *dir, int gl_device);

struct spr_parity_report;
/* One summary line per algorithm, then its first differing planes. */
void cli_parity_summary(const char *algo, const struct spr_parity_report *p);
const char *cli_cpu_flags(void);

int cmd_render(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_sample(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_check(int argc, char **argv);
int cmd_explain(int argc, char **argv);
int cmd_step(int argc, char **argv);
int cmd_show(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_parity(int argc, char **argv);
int cmd_group(int argc, char **argv);
int cmd_reference(int argc, char **argv);
int cmd_domains(int argc, char **argv);

/* Where the CGAL demo data lives: $SPLATREF_DATA, else ./data/cgal/data. */
const char *cli_data_dir(void);

#endif
