/* cli.h — shared pieces of the `splatref` command line.
 *
 * Each subcommand declares its options in a table; spr__parse() rejects
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
#include "spr__options.h"
#include "spr_glbackend.h"
#include "spr_history.h"
#include "spr__inspect.h"

/* One backend's history of a frame at one pixel (core/inspect/explain.c). */
typedef spr__history_run cli_history_run;
/* Render s on "cpu" or "gl" (the probe variant) recording pixel (x, y):
 * 0, 1 when GL has no device here, −1 after one line. */
int cli_run_history(spr_scene *s, const spr_render_desc *rd, const char *which, const spr_gl_desc *gd, int x, int y, cli_history_run *out);
struct spr_hist_event;
/* One call of a pixel history as text (cli_explain.c); other: the same
 * call on a second backend (NULL: none), diff_ev/diff_frag: the first
 * difference to mark (−1: none). */
void cli_explain_event(FILE *f, const struct spr_hist_event *e, int idx, const struct spr_hist_event *other, int diff_ev, int diff_frag,
                       const char *other_name);

/* [size of S_0, …, size of S_{K−1}]. */
cJSON *cli_json_group_sizes(const spr_groups *g);

/* Output directories that appear whole or not at all (cli_outdir.c): write
 * into tmp (DIR.tmpPID, made by begin), then end moves the files into DIR
 * (commit) or deletes them.  0, or −1 after one line. */
int cli_outdir_begin(spr__args *a, const char *opt, const char *dir, char *tmp, size_t cap);
int cli_outdir_end(spr__args *a, const char *opt, const char *tmp, const char *dir, int commit);

/* parity --random: N generated scenes from seed on both backends (cli_random.c). */
int cli_parity_random(spr__args *a, int first, int count, uint64_t seed, const char *dir, const spr_gl_desc *gd, const char *junit);

struct spr_parity_report;
/* One summary line per algorithm, then its first differing planes. */
void cli_parity_summary(FILE *f, const char *algo, const struct spr_parity_report *p);
/* One differing plane as the summary prints it ("pass 3 geometry k2 plane depth: 5 pixels differ, …"). */
void cli_parity_plane_line(FILE *f, const struct spr_plane_diff *d);

/* JUnit XML reports (cli_junit.c): cases collected, then written through
 * a temporary file.  A NULL report (no --junit) takes every call as a no-op. */
typedef struct cli_junit cli_junit;
enum { CLI_JUNIT_PASS = 0, CLI_JUNIT_FAILURE, CLI_JUNIT_ERROR, CLI_JUNIT_SKIPPED };
cli_junit *cli_junit_new(const char *suite);
/* status CLI_JUNIT_*; message: the failure's first line; text: what the terminal showed. */
void cli_junit_add(cli_junit *j, const char *classname, const char *name, double seconds, int status, const char *message, const char *text);
int cli_junit_write(spr__args *a, cli_junit *j, const char *path);
void cli_junit_free(cli_junit *j);
/* Text printed to stdout and kept (a test case's failure text): print into
 * the FILE begin returns, end prints it and returns it, free releases it. */
typedef struct cli_text { FILE *f; char *buf; size_t len; } cli_text;
FILE *cli_text_begin(cli_text *t);
const char *cli_text_end(cli_text *t);   /* the text, also printed on stdout */
const char *cli_text_close(cli_text *t); /* the text, not printed */
void cli_text_free(cli_text *t);

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
int cmd_profiles(int argc, char **argv);

/* Where the CGAL demo data lives: $SPLATREF_DATA, else ./data/cgal/data. */
const char *cli_data_dir(void);

#endif
