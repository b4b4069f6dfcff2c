/* groups.c — membership lists and the groups file format. */
#include "spr_group.h"
#include "spr_io.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

spr_result spr_groups_from_labels(const int32_t *label, size_t n, int K_hint, spr_groups *g, spr_error *err)
{
    memset(g, 0, sizeof *g);
    int K = K_hint;
    if (K <= 0)
        for (size_t i = 0; i < n; i++) K = label[i] + 1 > K ? label[i] + 1 : K;
    if (K < 1) K = 1;
    if (K > SPR_MAX_GROUPS) return spr__fail(err, SPR_E_TOO_LARGE, "groups: %d groups (limit %d)", K, SPR_MAX_GROUPS);
    for (size_t i = 0; i < n; i++)
        if (label[i] < 0 || label[i] >= K)
            return spr__fail(err, SPR_E_VALUE, "groups: splat %zu has group %d outside 0..%d", i, (int)label[i], K - 1);
    g->start = calloc((size_t)K + 1, sizeof(uint32_t));
    g->members = malloc((n ? n : 1) * sizeof(uint32_t));
    if (!g->start || !g->members) { spr_groups_free(g); return spr__fail(err, SPR_E_NOMEM, "groups: out of memory"); }
    for (size_t i = 0; i < n; i++) g->start[label[i] + 1]++;
    for (int k = 0; k < K; k++) g->start[k + 1] += g->start[k];
    uint32_t *fill = malloc((size_t)K * sizeof(uint32_t));
    if (!fill) { spr_groups_free(g); return spr__fail(err, SPR_E_NOMEM, "groups: out of memory"); }
    memcpy(fill, g->start, (size_t)K * sizeof(uint32_t));
    for (size_t i = 0; i < n; i++) g->members[fill[label[i]]++] = (uint32_t)i;
    free(fill);
    g->K = K;
    g->n_splats = n;
    return SPR_OK;
}

void spr_groups_free(spr_groups *g)
{
    free(g->start);
    free(g->members);
    free(g->radius_scale);
    memset(g, 0, sizeof *g);
}

spr_result spr_groups_read(const char *path, size_t n, int32_t *label, spr_error *err)
{
    char *buf;
    size_t len;
    spr_result r = spr__read_file(path, &buf, &len, err);
    if (r) return r;
    char *p = buf;
    size_t line = 1, i = 0;
    while (*p) {
        while (*p == ' ' || *p == '\t' || *p == '\r') p++;
        if (*p == '\n') { p++; line++; continue; }
        if (!*p) break;
        char *e;
        errno = 0;
        long v = strtol(p, &e, 10);
        if (e == p || errno || v < 0 || v >= SPR_MAX_GROUPS) {
            r = spr__fail(err, SPR_E_FORMAT, "%s:%zu: expected a group number in 0..%d", path, line, SPR_MAX_GROUPS - 1);
            goto done;
        }
        while (*e == ' ' || *e == '\t' || *e == '\r') e++;
        if (*e && *e != '\n') { r = spr__fail(err, SPR_E_FORMAT, "%s:%zu: one group number per line", path, line); goto done; }
        if (i >= n) { r = spr__fail(err, SPR_E_FORMAT, "%s:%zu: more groups than the %zu splats", path, line, n); goto done; }
        label[i++] = (int32_t)v;
        p = e;
    }
    if (i != n) r = spr__fail(err, SPR_E_TRUNCATED, "%s:%zu: %zu groups for %zu splats", path, line, i, n);
done:
    free(buf);
    return r;
}

typedef struct { const int32_t *label; size_t n; } labels_ref;

static int write_labels(FILE *f, const void *user)
{
    const labels_ref *l = user;
    for (size_t i = 0; i < l->n; i++)
        if (fprintf(f, "%d\n", (int)l->label[i]) < 0) return -1;
    return 0;
}

spr_result spr_groups_write(const char *path, const int32_t *label, size_t n, spr_error *err)
{
    labels_ref l = {label, n};
    return spr__write_atomic(path, write_labels, &l, err);
}
