/* merge.c — domain merging (SPEC §7.6, [R] §3.4): greedily merge the pair of
 * thresholded domains sharing the most points while both are flat (the
 * weighted λ0/(λ0+λ1+λ2) of their support polygons below `flat`) and face
 * the same way (normal dot above `dot`); the merged basis function is the
 * sum of the two, so the partition of unity is kept.  Each step recounts the
 * shared points over the current groups (O(points) per merge): plain, and
 * fast enough for the levels a renderer uses. */
#include "spr_domain.h"

#include <stdlib.h>
#include <string.h>

typedef struct pair_count { uint32_t a, b; uint32_t n; } pair_count;
static int by_pair(const void *x, const void *y)
{
    const pair_count *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    return (p->b > q->b) - (p->b < q->b);
}

/* The polygon of group g: the points with summed φ ≥ K over its regions. */
static spr_result group_polygon(const spr_cloud *c, const spr_csr *B, const uint32_t *group, uint32_t g, double K, uint32_t *idx,
                                double *phi, spr_polygon *pg, size_t *m, spr_error *err)
{
    *m = 0;
    for (size_t i = 0; i < B->rows; i++) {
        double s = 0.0;
        for (size_t q = B->ptr[i]; q < B->ptr[i + 1]; q++)
            if (group[B->col[q]] == g) s += B->val[q];
        if (s >= K) idx[*m] = (uint32_t)i, phi[(*m)++] = s;
    }
    if (*m < 3) { memset(pg, 0, sizeof *pg); pg->flatness = 1.0; return SPR_OK; } /* too small to judge: never merged */
    return spr_support_polygon(c, idx, phi, *m, 0.0, 0, pg, err);
}

spr_result spr_domain_merge(const spr_cloud *c, const spr_csr *B, double K, double flat, double dot, spr_csr *out, size_t *merges,
                            spr_error *err)
{
    memset(out, 0, sizeof *out);
    *merges = 0;
    const size_t R = B->cols, n = B->rows;
    uint32_t *group = malloc((R ? R : 1) * sizeof *group), *idx = malloc((n ? n : 1) * sizeof *idx), *in = malloc((R ? R : 1) * sizeof *in);
    double *phi = malloc((n ? n : 1) * sizeof *phi);
    spr_polygon *pg = malloc((R ? R : 1) * sizeof *pg);
    size_t cap = 1024, np = 0;
    pair_count *pc = malloc(cap * sizeof *pc);
    spr_result r = SPR_OK;
    if (!group || !idx || !in || !phi || !pg || !pc) { r = spr__fail(err, SPR_E_NOMEM, "merge: out of memory"); goto done; }
    for (size_t j = 0; j < R; j++) group[j] = (uint32_t)j;
    for (size_t j = 0; j < R && !r; j++) {
        size_t m;
        r = group_polygon(c, B, group, (uint32_t)j, K, idx, phi, &pg[j], &m, err);
    }
    while (!r) {
        /* shared points per pair of groups (each point's groups with summed φ ≥ K) */
        np = 0;
        for (size_t i = 0; i < n && !r; i++) {
            size_t ni = 0;
            for (size_t q = B->ptr[i]; q < B->ptr[i + 1]; q++) {
                const uint32_t g = group[B->col[q]];
                double s = 0.0;
                int seen = 0;
                for (size_t x = 0; x < ni; x++) seen |= in[x] == g;
                if (seen) continue;
                for (size_t q2 = B->ptr[i]; q2 < B->ptr[i + 1]; q2++)
                    if (group[B->col[q2]] == g) s += B->val[q2];
                if (s >= K) in[ni++] = g;
            }
            for (size_t x = 0; x < ni; x++)
                for (size_t y = x + 1; y < ni; y++) {
                    if (np == cap) {
                        pair_count *npc = realloc(pc, 2 * cap * sizeof *npc);
                        if (!npc) { r = spr__fail(err, SPR_E_NOMEM, "merge: out of memory"); break; }
                        pc = npc, cap *= 2;
                    }
                    pc[np++] = (pair_count){in[x] < in[y] ? in[x] : in[y], in[x] < in[y] ? in[y] : in[x], 1};
                }
        }
        if (r) break;
        qsort(pc, np, sizeof *pc, by_pair);
        uint32_t ba = 0, bb = 0, bn = 0;
        for (size_t x = 0; x < np;) {
            size_t y = x;
            while (y < np && pc[y].a == pc[x].a && pc[y].b == pc[x].b) y++;
            const uint32_t cnt = (uint32_t)(y - x), a = pc[x].a, b = pc[x].b;
            const double d = pg[a].normal[0] * pg[b].normal[0] + pg[a].normal[1] * pg[b].normal[1] + pg[a].normal[2] * pg[b].normal[2];
            if (cnt > bn && pg[a].flatness < flat && pg[b].flatness < flat && d > dot) bn = cnt, ba = a, bb = b; /* ties: the first pair */
            x = y;
        }
        if (!bn) break;
        for (size_t j = 0; j < R; j++)
            if (group[j] == bb) group[j] = ba;
        size_t m;
        r = group_polygon(c, B, group, ba, K, idx, phi, &pg[ba], &m, err);
        (*merges)++;
    }
    if (r) goto done;
    /* the merged basis: columns of a group summed, groups renumbered in order */
    uint32_t *num = malloc((R ? R : 1) * sizeof *num);
    if (!num) { r = spr__fail(err, SPR_E_NOMEM, "merge: out of memory"); goto done; }
    size_t R2 = 0;
    for (size_t j = 0; j < R; j++) num[j] = UINT32_MAX;
    for (size_t j = 0; j < R; j++)
        if (num[group[j]] == UINT32_MAX) num[group[j]] = (uint32_t)R2++;
    out->rows = n;
    out->cols = R2;
    out->ptr = malloc((n + 1) * sizeof *out->ptr);
    out->col = malloc((B->ptr[n] ? B->ptr[n] : 1) * sizeof *out->col);
    out->val = malloc((B->ptr[n] ? B->ptr[n] : 1) * sizeof *out->val);
    if (!out->ptr || !out->col || !out->val) { free(num); spr_csr_free(out); r = spr__fail(err, SPR_E_NOMEM, "merge: out of memory"); goto done; }
    size_t o = 0;
    out->ptr[0] = 0;
    for (size_t i = 0; i < n; i++) {
        const size_t row0 = o;
        for (size_t q = B->ptr[i]; q < B->ptr[i + 1]; q++) {
            const uint32_t col = num[group[B->col[q]]];
            size_t x = row0;
            while (x < o && out->col[x] != col) x++;
            if (x < o) out->val[x] += B->val[q];
            else out->col[o] = col, out->val[o++] = B->val[q];
        }
        for (size_t x = row0 + 1; x < o; x++) { /* ascending columns */
            uint32_t cc = out->col[x];
            double v = out->val[x];
            size_t y = x;
            while (y > row0 && out->col[y - 1] > cc) out->col[y] = out->col[y - 1], out->val[y] = out->val[y - 1], y--;
            out->col[y] = cc, out->val[y] = v;
        }
        out->ptr[i + 1] = o;
    }
    free(num);
done:
    free(group);
    free(idx);
    free(in);
    free(phi);
    free(pg);
    free(pc);
    return r;
}
