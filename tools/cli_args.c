/* cli_args.c — option table parsing and typed getters for the CLI. */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void cli_error(cli_args *a, const char *fmt, ...)
{
    char msg[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    /* a bad value read from --scene: say which file it came from */
    const char *where = "";
    for (int k = 0; a->opts && a->opts[k].name; k++) {
        size_t L = strlen(a->opts[k].name);
        if (a->from_scene[k] && !strncmp(msg, "--", 2) && !strncmp(msg + 2, a->opts[k].name, L) && msg[2 + L] == ':') where = a->scene_file;
    }
    fprintf(stderr, "splatref %s: %s%s%s%s\n", a->cmd, msg, *where ? " (from " : "", where, *where ? ")" : "");
}

static void print_help(const char *cmd, const cli_opt *opts, const char *usage)
{
    printf("usage: splatref %s %s\n\n", cmd, usage);
    for (const cli_opt *o = opts; o->name; o++) {
        char left[64];
        snprintf(left, sizeof left, "--%s%s%s", o->name, o->arg ? " " : "", o->arg ? o->arg : "");
        printf("  %-24s %s\n", left, o->help);
    }
    printf("  %-24s %s\n", "--help", "show this text");
    for (const cli_opt *o = opts; o->name; o++)
        if (!strcmp(o->name, "algo")) { /* the registry, so help never lists a stale set */
            printf("\nalgorithms (--algo):\n");
            for (int al = 0; al < SPR_ALGO__COUNT; al++)
                printf("  %-24s %s (SPEC %s)\n", spr_algo_name((spr_algo)al), spr_algo_info_of((spr_algo)al)->summary,
                       spr_algo_info_of((spr_algo)al)->spec);
        }
}

int cli_parse(cli_args *a, const char *cmd, const cli_opt *opts, const char *usage, int max_positional, int argc, char **argv)
{
    memset(a, 0, sizeof *a);
    a->cmd = cmd;
    a->opts = opts;
    int n_opts = 0;
    while (opts[n_opts].name) n_opts++;
    if (n_opts > CLI_MAX_OPTS) { /* a programming error: the table outgrew the arrays */
        cli_error(a, "%d options, more than CLI_MAX_OPTS (%d)", n_opts, CLI_MAX_OPTS);
        return 2;
    }
    for (int i = 0; i < argc; i++) {
        const char *s = argv[i];
        if (!strcmp(s, "--help") || !strcmp(s, "-h")) {
            print_help(cmd, opts, usage);
            return 1;
        }
        if (strncmp(s, "--", 2) != 0) {
            if (a->n_positional >= max_positional) {
                cli_error(a, "unexpected argument '%s' (see splatref %s --help)", s, cmd);
                return 2;
            }
            a->positional[a->n_positional++] = s;
            continue;
        }
        const char *name = s + 2, *eq = strchr(name, '=');
        size_t nl = eq ? (size_t)(eq - name) : strlen(name);
        int k = 0;
        for (; opts[k].name; k++)
            if (strlen(opts[k].name) == nl && !strncmp(opts[k].name, name, nl)) break;
        if (!opts[k].name) {
            cli_error(a, "unknown option '--%.*s' (see splatref %s --help)", (int)nl, name, cmd);
            return 2;
        }
        if (!opts[k].arg) {
            if (eq) { cli_error(a, "--%s takes no value", opts[k].name); return 2; }
            a->value[k] = "1";
        } else if (eq) {
            a->value[k] = eq + 1;
        } else {
            if (i + 1 >= argc) { cli_error(a, "--%s needs a value (%s)", opts[k].name, opts[k].arg); return 2; }
            a->value[k] = argv[++i];
        }
    }
    for (int k = 0; opts[k].name; k++) /* a scene file fills what the command line left out */
        if (!strcmp(opts[k].name, "scene") && a->value[k] && (a->used[k] = 1, cli_scene_read(a, a->value[k]))) return 2;
    return 0;
}

const char *cli_get(cli_args *a, const char *name)
{
    for (int k = 0; a->opts[k].name; k++)
        if (!strcmp(a->opts[k].name, name)) {
            a->used[k] = 1;
            return a->value[k];
        }
    return NULL;
}

int cli_reject_unused(cli_args *a)
{
    for (int k = 0; a->opts[k].name; k++)
        if (a->value[k] && !a->used[k] && !a->from_scene[k]) {
            cli_error(a, "--%s is not used here: the command, algorithm or grouping chosen does not read it (see splatref %s --help)",
                      a->opts[k].name, a->cmd);
            return -1;
        }
    return 0;
}

int cli_flag(cli_args *a, const char *name) { return cli_get(a, name) != NULL; }

int cli_get_double(cli_args *a, const char *name, double *out, double lo, double hi)
{
    const char *v = cli_get(a, name);
    if (!v) return 0;
    char *e;
    double d = strtod(v, &e);
    if (e == v || *e || !isfinite(d) || d < lo || d > hi) {
        cli_error(a, "--%s: '%s' is not a number in [%g, %g]", name, v, lo, hi);
        return -1;
    }
    *out = d;
    return 1;
}

int cli_get_int(cli_args *a, const char *name, int *out, int lo, int hi)
{
    const char *v = cli_get(a, name);
    if (!v) return 0;
    char *e;
    errno = 0;
    long d = strtol(v, &e, 10);
    if (e == v || *e || errno || d < lo || d > hi) {
        cli_error(a, "--%s: '%s' is not an integer in [%d, %d]", name, v, lo, hi);
        return -1;
    }
    *out = (int)d;
    return 1;
}

int cli_get_size(cli_args *a, const char *name, size_t *out, size_t lo, size_t hi)
{
    const char *v = cli_get(a, name);
    if (!v) return 0;
    char *e;
    errno = 0;
    unsigned long long d = strtoull(v, &e, 10);
    if (e == v || *e || errno || v[0] == '-' || d < lo || d > hi) {
        cli_error(a, "--%s: '%s' is not a count in [%zu, %zu]", name, v, lo, hi);
        return -1;
    }
    *out = (size_t)d;
    return 1;
}

int cli_get_vec3(cli_args *a, const char *name, double out[3])
{
    const char *v = cli_get(a, name);
    if (!v) return 0;
    double t[3];
    char tail;
    if (sscanf(v, "%lf,%lf,%lf%c", &t[0], &t[1], &t[2], &tail) != 3 || !isfinite(t[0]) || !isfinite(t[1]) || !isfinite(t[2])) {
        cli_error(a, "--%s: '%s' is not three finite numbers x,y,z", name, v);
        return -1;
    }
    memcpy(out, t, sizeof t);
    return 1;
}

int cli_get_wh(cli_args *a, const char *name, int *w, int *h)
{
    const char *v = cli_get(a, name);
    if (!v) return 0;
    int x, y;
    char tail;
    if (sscanf(v, "%dx%d%c", &x, &y, &tail) != 2 || x < 1 || y < 1 || x > SPR_MAX_IMAGE_SIDE || y > SPR_MAX_IMAGE_SIDE) {
        cli_error(a, "--%s: '%s' is not WxH with sides in 1..%d", name, v, SPR_MAX_IMAGE_SIDE);
        return -1;
    }
    *w = x;
    *h = y;
    return 1;
}

/* One status line, rewritten in place ("\r", erase to end of line) and
 * erased when a phase completes, so results print on a clean line. */
static void progress_tty(void *user, const char *phase, size_t done, size_t total)
{
    (void)user;
    if (total == 1 && done == 0)
        fprintf(stderr, "\r\033[K%s ...", phase);
    else if (done < total)
        fprintf(stderr, "\r\033[K%s %5.1f%% (%zu of %zu)", phase, 100.0 * (double)done / (double)total, done, total);
    else
        fprintf(stderr, "\r\033[K");
    fflush(stderr);
}

spr_progress cli_progress(int quiet)
{
    spr_progress p = {NULL, NULL};
    if (!quiet && isatty(2)) p.fn = progress_tty;
    return p;
}

const char *cli_data_dir(void)
{
    const char *d = getenv("SPLATREF_DATA");
    if (d && *d) return d;
    if (access("data/cgal/data/meshes", F_OK) == 0) return "data/cgal/data";
    return SPR_DEFAULT_DATA; /* the source tree this binary was built from */
}
