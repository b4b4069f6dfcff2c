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

typedef struct { uint32_t splat, group; } membership;
static int by_membership(const void *a, const void *b)
{
    const membership *x = a, *y = b;
    if (x->group != y->group) return x->group < y->group ? -1 : 1;
    return (x->splat > y->splat) - (x->splat < y->splat);
}

spr_result spr_groups_read_any(const char *path, size_t n, spr_groups *g, int32_t *label, spr_error *err)
{
    memset(g, 0, sizeof *g);
    char *buf;
    size_t len;
    spr_result r = spr__read_file(path, &buf, &len, err);
    if (r) return r;
    /* the first data line tells the format: one number, or two */
    const char *p = buf;
    while (*p == '\n' || *p == '\r' || *p == ' ' || *p == '\t') p++;
    int tokens = 0;
    for (const char *t = p; *t && *t != '\n';) {
        while (*t == ' ' || *t == '\t' || *t == '\r') t++;
        if (!*t || *t == '\n') break;
        tokens++;
        while (*t && !strchr(" \t\r\n", *t)) t++;
    }
    if (tokens != 2) {
        free(buf);
        if ((r = spr_groups_read(path, n, label, err))) return r;
        return spr_groups_from_labels(label, n, 0, g, err);
    }
    size_t cap = n + n / 2 + 16, m = 0, line = 1;
    membership *ms = malloc(cap * sizeof *ms);
    if (!ms) { free(buf); return spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path); }
    for (size_t i = 0; i < n; i++) label[i] = -1;
    int K = 0;
    for (char *q = buf; *q;) {
        char *eol = strchr(q, '\n');
        if (eol) *eol = 0;
        char *t = q;
        while (*t == ' ' || *t == '\t' || *t == '\r') t++;
        if (*t) {
            char *e1, *e2;
            errno = 0;
            unsigned long sp = strtoul(t, &e1, 10), gr = e1 != t ? strtoul(e1, &e2, 10) : 0;
            while (e1 != t && (*e2 == ' ' || *e2 == '\t' || *e2 == '\r')) e2++;
            if (e1 == t || e2 == e1 || *e2 || errno || sp >= n || gr >= SPR_MAX_GROUPS) {
                r = spr__fail(err, SPR_E_FORMAT, "%s:%zu: expected `splat_index group` with splat < %zu and group < %d", path, line, n,
                              SPR_MAX_GROUPS);
                break;
            }
            if (m == cap) {
                membership *nm = realloc(ms, 2 * cap * sizeof *ms);
                if (!nm) { r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path); break; }
                ms = nm;
                cap *= 2;
            }
            ms[m++] = (membership){(uint32_t)sp, (uint32_t)gr};
            if (label[sp] < 0) label[sp] = (int32_t)gr;
            if ((int)gr + 1 > K) K = (int)gr + 1;
        }
        line++;
        if (!eol) break;
        q = eol + 1;
    }
    free(buf);
    for (size_t i = 0; !r && i < n; i++)
        if (label[i] < 0) r = spr__fail(err, SPR_E_VALUE, "%s: splat %zu is in no group", path, i);
    if (!r) {
        qsort(ms, m, sizeof *ms, by_membership);
        for (size_t i = 1; !r && i < m; i++)
            if (ms[i].group == ms[i - 1].group && ms[i].splat == ms[i - 1].splat)
                r = spr__fail(err, SPR_E_VALUE, "%s: splat %u listed twice in group %u", path, ms[i].splat, ms[i].group);
    }
    if (!r) {
        g->start = calloc((size_t)K + 1, sizeof(uint32_t));
        g->members = malloc((m ? m : 1) * sizeof(uint32_t));
        if (!g->start || !g->members) r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path);
        for (size_t i = 0; !r && i < m; i++) {
            g->members[i] = ms[i].splat;
            g->start[ms[i].group + 1]++;
        }
        for (int k = 0; !r && k < K; k++) g->start[k + 1] += g->start[k];
        g->K = K;
        g->n_splats = n;
    }
    free(ms);
    if (r) spr_groups_free(g);
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

static int write_memberships(FILE *f, const void *user)
{
    const spr_groups *g = user;
    for (int k = 0; k < g->K; k++)
        for (uint32_t m = g->start[k]; m < g->start[k + 1]; m++)
            if (fprintf(f, "%u %d\n", g->members[m], k) < 0) return -1;
    return 0;
}

spr_result spr_groups_write_memberships(const char *path, const spr_groups *g, spr_error *err)
{
    return spr__write_atomic(path, write_memberships, g, err);
}
