/* cli_outdir.c — output directories (render --dump, parity --report) that
 * appear whole or not at all: files are written into DIR.tmpPID, moved into
 * DIR when the command succeeds, and removed with the temporary directory
 * when it fails, so a failure leaves no partial output behind. */
#include "cli.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int cli_outdir_begin(spr__args *a, const char *opt, const char *dir, char *tmp, size_t cap)
{
    snprintf(tmp, cap, "%s.tmp%ld", dir, (long)getpid());
    if (mkdir(tmp, 0777) != 0) {
        spr__error(a, "--%s: cannot create %s: %s", opt, tmp, strerror(errno));
        return -1;
    }
    return 0;
}

/* Remove folder dir and the files in it (report folders hold files only). */
static void remove_files(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    char p[2048];
    while (d && (e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
            remove(p);
        }
    if (d) closedir(d);
    rmdir(dir);
}

/* Move every file (and report folder) of tmp into dir (created if missing), then remove tmp;
 * with commit = 0 delete them instead.  0, or −1 after one line. */
int cli_outdir_end(spr__args *a, const char *opt, const char *tmp, const char *dir, int commit)
{
    int rc = 0;
    if (commit && mkdir(dir, 0777) != 0 && errno != EEXIST) {
        spr__error(a, "--%s: cannot create %s: %s", opt, dir, strerror(errno));
        commit = 0;
        rc = -1;
    }
    DIR *d = opendir(tmp);
    struct dirent *e;
    char from[2048], to[2048];
    while (d && (e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        snprintf(from, sizeof from, "%s/%s", tmp, e->d_name);
        snprintf(to, sizeof to, "%s/%s", dir, e->d_name);
        struct stat st;
        const int is_dir = lstat(from, &st) == 0 && S_ISDIR(st.st_mode);
        if (commit && is_dir && lstat(to, &st) == 0 && S_ISDIR(st.st_mode)) remove_files(to); /* a report folder replaced whole */
        if (commit && rename(from, to) != 0) {
            spr__error(a, "--%s: cannot move %s into %s: %s", opt, e->d_name, dir, strerror(errno));
            commit = 0;
            rc = -1;
        }
        if (!commit) {
            if (is_dir) remove_files(from);
            else remove(from);
        }
    }
    if (d) closedir(d);
    rmdir(tmp);
    return rc;
}
