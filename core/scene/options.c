/* spr__args.c — option table parsing and typed getters for the CLI. */
#include "spr__options.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void spr__error(spr__args *a, const char *fmt, ...)
{
    char raw[2048], msg[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(raw, sizeof raw, fmt, ap);
    va_end(ap);
    spr__one_line(msg, sizeof msg, raw); /* one line whatever a value or a scene file's key holds */
    /* about an option read from --scene ("--NAME: …", "--A and --NAME go together"): say which file it came from */
    const char *where = "";
    for (const char *m = strstr(msg, "--"); m && !*where; m = strstr(m + 2, "--")) {
        size_t L = strspn(m + 2, "abcdefghijklmnopqrstuvwxyz0123456789-"); /* the option name m starts */
        for (int k = 0; a->opts && a->opts[k].name && !*where; k++)
            if (a->from_scene[k] && strlen(a->opts[k].name) == L && !strncmp(m + 2, a->opts[k].name, L)) where = a->scene_file;
    }
    if (a->sink) { /* a library call: the message is the error */
        a->sink->code = SPR_E_ARG;
        snprintf(a->sink->msg, sizeof a->sink->msg, "%.300s%s%.150s%s", msg, *where ? " (from " : "", where, *where ? ")" : "");
        return;
    }
    fprintf(stderr, "splatref %s: %s%s%s%s\n", a->cmd, msg, *where ? " (from " : "", where, *where ? ")" : "");
}

static void print_help(const char *cmd, const spr__opt *opts, const char *usage)
{
    printf("usage: splatref %s %s\n\n", cmd, usage);
    for (const spr__opt *o = opts; o->name; o++) {
        char left[64];
        snprintf(left, sizeof left, "--%s%s%s", o->name, o->arg ? " " : "", o->arg ? o->arg : "");
        printf("  %-24s %s\n", left, o->help);
    }
    printf("  %-24s %s\n", "--help", "show this text");
    for (const spr__opt *o = opts; o->name; o++)
        if (!strcmp(o->name, "algo")) { /* the registry, so help never lists a stale set */
            printf("\nalgorithms (--algo):\n");
            for (int al = 0; al < SPR_ALGO__COUNT; al++)
                printf("  %-24s %s (SPEC %s)\n", spr_algo_name((spr_algo)al), spr_algo_info_of((spr_algo)al)->summary,
                       spr_algo_info_of((spr_algo)al)->spec);
        }
}

/* A command's option values live as long as the process, argv's and a scene
 * file's alike: the scene's strings move from a (a command's local) to this
 * list, reachable to the end (the library's callers free theirs instead,
 * spr__scene_forget). */
static char **exit_kept;
static size_t exit_kept_n;
static void keep_to_exit(spr__args *a)
{
    for (int k = 0; k < SPR__MAX_OPTS; k++) {
        if (!a->scene_text[k]) continue;
        char **grown = realloc(exit_kept, (exit_kept_n + 1) * sizeof *grown);
        if (!grown) return; /* left in a: at worst a leak report, never a dangling value */
        exit_kept = grown;
        exit_kept[exit_kept_n++] = a->scene_text[k];
        a->scene_text[k] = NULL;
    }
}

int spr__parse(spr__args *a, const char *cmd, const spr__opt *opts, const char *usage, int max_positional, int argc, char **argv)
{
    memset(a, 0, sizeof *a);
    a->cmd = cmd;
    a->opts = opts;
    int n_opts = 0;
    while (opts[n_opts].name) n_opts++;
    if (n_opts > SPR__MAX_OPTS) { /* a programming error: the table outgrew the arrays */
        spr__error(a, "%d options, more than SPR__MAX_OPTS (%d)", n_opts, SPR__MAX_OPTS);
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
                spr__error(a, "unexpected argument '%s' (see splatref %s --help)", s, cmd);
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
            spr__error(a, "unknown option '--%.*s' (see splatref %s --help)", (int)nl, name, cmd);
            return 2;
        }
        if (!opts[k].arg) {
            if (eq) { spr__error(a, "--%s takes no value", opts[k].name); return 2; }
            a->value[k] = "1";
        } else if (eq) {
            a->value[k] = eq + 1;
        } else {
            if (i + 1 >= argc) { spr__error(a, "--%s needs a value (%s)", opts[k].name, opts[k].arg); return 2; }
            a->value[k] = argv[++i];
        }
    }
    /* a scene file fills what the command line left out (tables with the scene rows, SPR__SCENE_OPTS) */
    int has_scene_rows = 0;
    for (int k = 0; opts[k].name; k++) has_scene_rows |= !strcmp(opts[k].name, "save-scene");
    int bad = 0;
    for (int k = 0; has_scene_rows && opts[k].name; k++)
        if (!strcmp(opts[k].name, "scene") && a->value[k]) a->used[k] = 1, bad = spr__scene_read(a, a->value[k]) != 0;
    keep_to_exit(a);
    return bad ? 2 : 0;
}

const char *spr__get(spr__args *a, const char *name)
{
    for (int k = 0; a->opts[k].name; k++)
        if (!strcmp(a->opts[k].name, name)) {
            a->used[k] = 1;
            return a->value[k];
        }
    return NULL;
}

int spr__reject_unused(spr__args *a)
{
    for (int k = 0; a->opts[k].name; k++)
        if (a->value[k] && !a->used[k] && !a->from_scene[k]) {
            spr__error(a, "--%s is not used here: the command, algorithm or grouping chosen does not read it (see splatref %s --help)",
                      a->opts[k].name, a->cmd);
            return -1;
        }
    return 0;
}

int spr__flag(spr__args *a, const char *name) { return spr__get(a, name) != NULL; }

int spr__get_double(spr__args *a, const char *name, double *out, double lo, double hi)
{
    const char *v = spr__get(a, name);
    if (!v) return 0;
    char *e;
    double d = strtod(v, &e);
    if (e == v || *e || !isfinite(d) || d < lo || d > hi) {
        spr__error(a, "--%s: '%s' is not a number in [%g, %g]", name, v, lo, hi);
        return -1;
    }
    *out = d;
    return 1;
}

int spr__get_int(spr__args *a, const char *name, int *out, int lo, int hi)
{
    const char *v = spr__get(a, name);
    if (!v) return 0;
    char *e;
    errno = 0;
    long d = strtol(v, &e, 10);
    if (e == v || *e || errno || d < lo || d > hi) {
        spr__error(a, "--%s: '%s' is not an integer in [%d, %d]", name, v, lo, hi);
        return -1;
    }
    *out = (int)d;
    return 1;
}

int spr__get_size(spr__args *a, const char *name, size_t *out, size_t lo, size_t hi)
{
    const char *v = spr__get(a, name);
    if (!v) return 0;
    char *e;
    errno = 0;
    unsigned long long d = strtoull(v, &e, 10);
    if (e == v || *e || errno || v[0] == '-' || d < lo || d > hi) {
        spr__error(a, "--%s: '%s' is not a count in [%zu, %zu]", name, v, lo, hi);
        return -1;
    }
    *out = (size_t)d;
    return 1;
}

int spr__get_vec3(spr__args *a, const char *name, double out[3])
{
    const char *v = spr__get(a, name);
    if (!v) return 0;
    double t[3];
    char tail;
    if (sscanf(v, "%lf,%lf,%lf%c", &t[0], &t[1], &t[2], &tail) != 3 || !isfinite(t[0]) || !isfinite(t[1]) || !isfinite(t[2])) {
        spr__error(a, "--%s: '%s' is not three finite numbers x,y,z", name, v);
        return -1;
    }
    memcpy(out, t, sizeof t);
    return 1;
}

int spr__get_wh(spr__args *a, const char *name, int *w, int *h)
{
    const char *v = spr__get(a, name);
    if (!v) return 0;
    int x, y;
    char tail;
    if (sscanf(v, "%dx%d%c", &x, &y, &tail) != 2 || x < 1 || y < 1 || x > SPR_MAX_IMAGE_SIDE || y > SPR_MAX_IMAGE_SIDE) {
        spr__error(a, "--%s: '%s' is not WxH with sides in 1..%d", name, v, SPR_MAX_IMAGE_SIDE);
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

spr_progress spr__progress(int quiet)
{
    spr_progress p = {NULL, NULL};
    if (!quiet && isatty(2)) p.fn = progress_tty;
    return p;
}

static void warn_stderr(void *user, const char *msg)
{
    const spr__args *a = user;
    if (isatty(2)) fputs("\r\033[K", stderr); /* off a progress line */
    fprintf(stderr, "splatref %s: warning: %s\n", a->cmd, msg);
}

spr_warn spr__warn(spr__args *a)
{
    spr_warn w = {NULL, NULL};
    if (!a->sink) { /* the command line: on stderr, whatever --quiet says; a library call: dropped */
        w.fn = warn_stderr;
        w.user = a;
    }
    return w;
}

static int put_text(FILE *f, const void *user)
{
    const char *s = user;
    size_t n = strlen(s);
    return fwrite(s, 1, n, f) == n && fputc('\n', f) != EOF ? 0 : -1;
}

int spr__write_json(spr__args *a, const char *path, cJSON *root)
{
    char *text = root ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text) { spr__error(a, "%s: out of memory building JSON", path); return -1; }
    spr_error err = {0};
    int rc = spr__write_atomic(path, put_text, text, &err) ? -1 : 0;
    if (rc) spr__error(a, "%s", err.msg);
    free(text);
    return rc;
}

