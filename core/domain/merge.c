/* merge.c — domain merging (SPEC §7.6, [R] §3.4): greedily merge the pair of
 * thresholded domains sharing the most points while both are flat (the
 * weighted λ0/(λ0+λ1+λ2) of their support polygons below `flat`) and face
 * the same way (normal dot above `dot`); the merged basis function is the
 * sum of the two, so the partition of unity is kept.
 *
 * A merge changes only the merged group: its polygon and its shared-point
 * counts are recomputed from its own points (the basis transposed), pushed
 * on a max-heap, and entries of groups that changed since are skipped when
 * popped.  Ties go to the lower pair of group numbers. */
#include "spr_domain.h"

#include <stdlib.h>
#include <string.h>

typedef struct cand { uint32_t n, a, b, va, vb; } cand;

static int before(const cand *x, const cand *y) /* x pops first */
{
    if (x->n != y->n) return x->n > y->n;
    if (x->a != y->a) return x->a < y->a;
    return x->b < y->b;
}

typedef struct heap { cand *h; size_t n, cap; } heap;

static int heap_push(heap *q, cand c)
{
    if (q->n == q->cap) {
        size_t cap = q->cap ? 2 * q->cap : 1024;
        cand *nh = realloc(q->h, cap * sizeof *nh);
        if (!nh) return -1;
        q->h = nh, q->cap = cap;
    }
    size_t i = q->n++;
    while (i > 0 && before(&c, &q->h[(i - 1) / 2])) q->h[i] = q->h[(i - 1) / 2], i = (i - 1) / 2;
    q->h[i] = c;
    return 0;
}

static cand heap_pop(heap *q)
{
    cand top = q->h[0], last = q->h[--q->n];
    size_t i = 0;
    for (;;) {
        size_t l = 2 * i + 1, r = l + 1, m = i;
        const cand *cm = &last;
        if (l < q->n && before(&q->h[l], cm)) m = l, cm = &q->h[l];
        if (r < q->n && before(&q->h[r], cm)) m = r;
        if (m == i) break;
        q->h[i] = q->h[m];
        i = m;
    }
    if (q->n) q->h[i] = last;
    return top;
}

typedef struct merger {
    const spr_cloud *c;
    const spr_csr *B;     /* points × regions */
    spr_csr BT;           /* regions × points, every entry */
    double K;
    uint32_t *group;      /* region → group (its lowest region) */
    uint32_t *first, *next; /* the regions of each group, a list */
    uint32_t *ver;        /* group versions: bumped when a group changes */
    spr_polygon *pg;
    uint32_t *stamp, *stamp2, tick; /* point and group marks */
    uint32_t *pts, *cnt, *gl; /* scratch: the group's points, counts per group, groups touched */
    uint32_t *idx;
    double *phi;
    size_t m;             /* points of the group last gathered */
} merger;

/* Σ φ of group g at point i. */
static double sum_at(const merger *M, size_t i, uint32_t g)
{
    double s = 0.0;
    for (size_t q = M->B->ptr[i]; q < M->B->ptr[i + 1]; q++)
        if (M->group[M->B->col[q]] == g) s += M->B->val[q];
    return s;
}

/* The points of group g with Σ φ ≥ K into idx/phi (M->m of them). */
static void gather(merger *M, uint32_t g)
{
    M->tick++;
    M->m = 0;
    for (uint32_t j = M->first[g]; j != UINT32_MAX; j = M->next[j])
        for (size_t q = M->BT.ptr[j]; q < M->BT.ptr[j + 1]; q++) {
            const uint32_t i = M->BT.col[q];
            if (M->stamp[i] == M->tick) continue;
            M->stamp[i] = M->tick;
            const double s = sum_at(M, i, g);
            if (s >= M->K) M->idx[M->m] = i, M->phi[M->m++] = s;
        }
}

static spr_result polygon_of(merger *M, uint32_t g, spr_error *err)
{
    gather(M, g);
    if (M->m < 3) { /* too small to judge: never merged */
        memset(&M->pg[g], 0, sizeof M->pg[g]);
        M->pg[g].flatness = 1.0;
        return SPR_OK;
    }
    return spr_support_polygon(M->c, M->idx, M->phi, M->m, 0.0, 0, &M->pg[g], err);
}

/* Push (g, h, shared points) for every group h sharing points with g
 * (h > g only when `upper`: the first pass counts each pair once). */
static int push_pairs(merger *M, heap *q, uint32_t g, int upper)
{
    gather(M, g);
    size_t ng = 0;
    M->tick++;
    for (size_t x = 0; x < M->m; x++) {
        const size_t i = M->idx[x];
        for (size_t p = M->B->ptr[i]; p < M->B->ptr[i + 1]; p++) {
            const uint32_t h = M->group[M->B->col[p]];
            if (h == g || M->stamp2[h] == M->tick || sum_at(M, i, h) < M->K) continue;
            M->stamp2[h] = M->tick; /* once per point: later entries of h in the row are skipped */
            if (!M->cnt[h]) M->gl[ng++] = h;
            M->cnt[h]++;
        }
        M->tick++; /* a new point: groups may count again */
    }
    int bad = 0;
    for (size_t x = 0; x < ng; x++) {
        const uint32_t h = M->gl[x];
        if (!bad && (!upper || h > g)) {
            const uint32_t a = g < h ? g : h, b = g < h ? h : g;
            bad = heap_push(q, (cand){M->cnt[h], a, b, M->ver[a], M->ver[b]});
        }
        M->cnt[h] = 0;
    }
    return bad;
}

spr_result spr_domain_merge(const spr_cloud *c, const spr_csr *B, double K, double flat, double dot, spr_csr *out, size_t *merges,
                            spr_error *err)
{
    memset(out, 0, sizeof *out);
    *merges = 0;
    const size_t R = B->cols, n = B->rows;
    merger M = {.c = c, .B = B, .K = K};
    heap q = {0};
    spr_result r = spr_domain_members(B, 0, 0.0, &M.BT, err);
    if (r) return r;
    const size_t R1 = R ? R : 1, n1 = n ? n : 1;
    M.group = malloc(R1 * sizeof *M.group), M.first = malloc(R1 * sizeof *M.first), M.next = malloc(R1 * sizeof *M.next);
    M.ver = calloc(R1, sizeof *M.ver), M.pg = malloc(R1 * sizeof *M.pg), M.stamp = calloc(n1, sizeof *M.stamp);
    M.stamp2 = calloc(R1, sizeof *M.stamp2), M.cnt = calloc(R1, sizeof *M.cnt), M.gl = malloc(R1 * sizeof *M.gl);
    M.idx = malloc(n1 * sizeof *M.idx), M.phi = malloc(n1 * sizeof *M.phi);
    uint32_t *num = malloc(R1 * sizeof *num);
    if (!M.group || !M.first || !M.next || !M.ver || !M.pg || !M.stamp || !M.stamp2 || !M.cnt || !M.gl || !M.idx || !M.phi || !num) {
        r = spr__fail(err, SPR_E_NOMEM, "merge: out of memory");
        goto done;
    }
    for (size_t j = 0; j < R; j++) M.group[j] = M.first[j] = (uint32_t)j, M.next[j] = UINT32_MAX;
    for (size_t j = 0; j < R && !r; j++) r = polygon_of(&M, (uint32_t)j, err);
    for (size_t j = 0; j < R && !r; j++)
        if (push_pairs(&M, &q, (uint32_t)j, 1)) r = spr__fail(err, SPR_E_NOMEM, "merge: out of memory");
    while (!r && q.n) {
        const cand e = heap_pop(&q);
        if (M.ver[e.a] != e.va || M.ver[e.b] != e.vb || M.group[e.a] != e.a || M.group[e.b] != e.b) continue; /* changed since */
        const spr_polygon *pa = &M.pg[e.a], *pb = &M.pg[e.b];
        const double d = pa->normal[0] * pb->normal[0] + pa->normal[1] * pb->normal[1] + pa->normal[2] * pb->normal[2];
        if (!(pa->flatness < flat && pb->flatness < flat && d > dot)) continue; /* re-pushed if either changes */
        /* b joins a */
        uint32_t tail = e.a;
        while (M.next[tail] != UINT32_MAX) tail = M.next[tail];
        M.next[tail] = e.b;
        for (uint32_t j = e.b; j != UINT32_MAX; j = M.next[j]) M.group[j] = e.a;
        M.ver[e.a]++, M.ver[e.b]++;
        (*merges)++;
        if ((r = polygon_of(&M, e.a, err))) break;
        if (push_pairs(&M, &q, e.a, 0)) r = spr__fail(err, SPR_E_NOMEM, "merge: out of memory");
    }
    if (r) goto done;
    /* the merged basis: columns of a group summed, groups renumbered in order */
    size_t R2 = 0;
    for (size_t j = 0; j < R; j++) num[j] = UINT32_MAX;
    for (size_t j = 0; j < R; j++)
        if (num[M.group[j]] == UINT32_MAX) num[M.group[j]] = (uint32_t)R2++;
    out->rows = n;
    out->cols = R2;
    out->ptr = malloc((n + 1) * sizeof *out->ptr);
    out->col = malloc((B->ptr[n] ? B->ptr[n] : 1) * sizeof *out->col);
    out->val = malloc((B->ptr[n] ? B->ptr[n] : 1) * sizeof *out->val);
    if (!out->ptr || !out->col || !out->val) { spr_csr_free(out); r = spr__fail(err, SPR_E_NOMEM, "merge: out of memory"); goto done; }
    size_t o = 0;
    out->ptr[0] = 0;
    for (size_t i = 0; i < n; i++) {
        const size_t row0 = o;
        for (size_t p = B->ptr[i]; p < B->ptr[i + 1]; p++) {
            const uint32_t col = num[M.group[B->col[p]]];
            size_t x = row0;
            while (x < o && out->col[x] != col) x++;
            if (x < o) out->val[x] += B->val[p];
            else out->col[o] = col, out->val[o++] = B->val[p];
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
done:
    spr_csr_free(&M.BT);
    free(M.group), free(M.first), free(M.next), free(M.ver), free(M.pg), free(M.stamp), free(M.stamp2), free(M.cnt), free(M.gl);
    free(M.idx), free(M.phi), free(num), free(q.h);
    return r;
}
