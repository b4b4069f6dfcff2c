/* bsp.c — kd tree over centres, leaf normals, back-to-front traversal. */
#include "spr_bsp.h"
#include "spr_util.h"

#include <math.h>
#include <omp.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <stdlib.h>
#include <string.h>

/* Building (SPEC §5.6).  Each node splits its range at the median of its
 * longest extent: the half of the splats with the smallest (coordinate,
 * index) keys goes left — a strict total order, so the halves are the same
 * sets whichever way they are found.  A selection (introselect on (key,
 * index) pairs, linear per level) finds them instead of a full sort; a leaf
 * is then sorted by its parent's axis, which is the order the full sort of
 * the parent left it in, so leaves, their summed normals and the node
 * numbering (depth-first, pre-order) are those of the sorting build.  The
 * top of the tree is split on the calling thread; the subtrees below it are
 * built in parallel into their own arrays and spliced in pre-order, so the
 * tree is the same for any thread count. */
/* A splat's centre and id, permuted along with the partitions so every
 * scan of a range reads memory in order (a gather through the order array
 * missed the cache once per splat per level). */
typedef struct pt4 { float v[3]; uint32_t idx; } pt4;

/* The order of a range along an axis, (coordinate, index), as one unsigned
 * integer: the float's bits made monotone (negative: all bits flipped;
 * otherwise the sign bit set; −0 first made +0, which the float comparison
 * calls equal), then the index.  Centres are finite (spr_cloud_validate). */
static inline uint64_t pt_key(const pt4 *a, int axis)
{
    const float f = a->v[axis] + 0.0f; /* −0 + 0 = +0 */
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    u = (u & 0x80000000u) ? ~u : (u | 0x80000000u);
    return (uint64_t)u << 32 | a->idx;
}

static inline int pt_less(const pt4 *a, const pt4 *b, int axis) { return pt_key(a, axis) < pt_key(b, axis); }

static _Thread_local int sort_axis;
static int pt_cmp(const void *a, const void *b)
{
    const pt4 *x = a, *y = b;
    return pt_less(x, y, sort_axis) ? -1 : pt_less(y, x, sort_axis) ? 1 : 0;
}

static void pt_sort(pt4 *v, size_t n, int axis)
{
    sort_axis = axis;
    qsort(v, n, sizeof *v, pt_cmp);
}

static void pt_insertion(pt4 *v, size_t n, int axis)
{
    for (size_t i = 1; i < n; i++) {
        pt4 x = v[i];
        const uint64_t kx = pt_key(&x, axis);
        size_t j = i;
        while (j > 0 && kx < pt_key(&v[j - 1], axis)) v[j] = v[j - 1], j--;
        v[j] = x;
    }
}

/* Put the k smallest of v[0 … n) by (v[axis], idx) first (any order on
 * each side): introselect, a full sort after 64 unlucky rounds. */
static void pt_select(pt4 *v, size_t n, size_t k, int axis)
{
    size_t lo = 0, hi = n; /* the k-th lies in [lo, hi) */
    int budget = 64;
    while (hi - lo > 16) {
        if (budget-- == 0) { pt_sort(v + lo, hi - lo, axis); return; }
        size_t mid = lo + (hi - lo) / 2;
        const pt4 *pp, *a = &v[lo], *b = &v[mid], *c = &v[hi - 1];
        if (pt_less(a, b, axis)) pp = pt_less(b, c, axis) ? b : pt_less(a, c, axis) ? c : a;
        else pp = pt_less(a, c, axis) ? a : pt_less(b, c, axis) ? c : b;

        /* the ids make every key distinct: two-way partition < piv | ≥ piv,
         * branch-free (every element swapped, the boundary moved by the
         * comparison; the branches of a data-dependent partition mispredict
         * half the time), then the pivot put at the boundary */
        const uint64_t kp = pt_key(pp, axis);
        { pt4 t = v[hi - 1]; v[hi - 1] = *pp; *(pt4 *)pp = t; }
        size_t lt = lo;
        for (size_t i = lo; i < hi - 1; i++) {
            const pt4 t = v[i];
            const size_t less = pt_key(&t, axis) < kp;
            v[i] = v[lt];
            v[lt] = t;
            lt += less;
        }
        { pt4 t = v[lt]; v[lt] = v[hi - 1]; v[hi - 1] = t; }
        if (k < lt) hi = lt;
        else if (k > lt) lo = lt + 1;
        else return;
    }
    pt_insertion(v + lo, hi - lo, axis);
}

typedef struct sub_tree {
    spr_bsp_node *nodes;
    size_t n, cap;
} sub_tree;

typedef struct build_ctx {
    const spr_cloud *c;
    uint32_t *order, *leaf_of;
    pt4 *pts;               /* n entries: centres in the current order */
} build_ctx;

static int32_t add_node(sub_tree *st)
{
    if (st->n == st->cap) {
        size_t cap = st->cap ? 2 * st->cap : 64;
        spr_bsp_node *nn = realloc(st->nodes, cap * sizeof *nn);
        if (!nn) return -1;
        st->nodes = nn;
        st->cap = cap;
    }
    memset(&st->nodes[st->n], 0, sizeof st->nodes[0]);
    return (int32_t)st->n++;
}

/* The extent's longest axis of a range; −1 (leaf) when it holds ≤ LEAF
 * splats or has no extent. */
static int split_axis(const build_ctx *bc, uint32_t first, uint32_t count)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
#if defined(__SSE2__)
    /* a pt4 is one 16-byte vector (x y z id): minps/maxps compute a < b ? a : b
     * per lane, the scalar loop's selection; the id lane is zeroed (its bits
     * would be denormal floats) and not read */
    const __m128 keep = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
    __m128 lo4 = _mm_set1_ps(INFINITY), hi4 = _mm_set1_ps(-INFINITY);
    for (const pt4 *q = bc->pts + first; q < bc->pts + first + count; q++) {
        const __m128 v = _mm_and_ps(_mm_loadu_ps(q->v), keep);
        lo4 = _mm_min_ps(v, lo4);
        hi4 = _mm_max_ps(v, hi4);
    }
    float l4[4], h4[4];
    _mm_storeu_ps(l4, lo4);
    _mm_storeu_ps(h4, hi4);
    for (int a = 0; a < 3; a++) lo[a] = l4[a], hi[a] = h4[a];
#else
    for (const pt4 *q = bc->pts + first; q < bc->pts + first + count; q++)
        for (int a = 0; a < 3; a++) {
            lo[a] = q->v[a] < lo[a] ? q->v[a] : lo[a];
            hi[a] = q->v[a] > hi[a] ? q->v[a] : hi[a];
        }
#endif
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    return count <= SPR_BSP_LEAF || !(hi[axis] > lo[axis]) ? -1 : axis;
}

/* Split [first, first+count) at its median along axis: the half smallest
 * first; returns the split coordinate (the smallest of the right half). */
static float split_at(build_ctx *bc, uint32_t first, uint32_t count, int axis)
{
    const uint32_t half = count / 2;
    pt_select(bc->pts + first, count, half, axis);
    /* the entry the sort would put at the median: the right half's least
     * key (its id decides between equal coordinates, −0 and +0 among them) */
    const pt4 *m = bc->pts + first + half;
    uint64_t km = pt_key(m, axis);
    for (const pt4 *q = m + 1; q < bc->pts + first + count; q++) {
        const uint64_t kq = pt_key(q, axis);
        if (kq < km) km = kq, m = q;
    }
    return m->v[axis];
}

static void make_leaf(build_ctx *bc, spr_bsp_node *nd, int32_t id, uint32_t first, uint32_t count, int parent_axis)
{
    if (parent_axis >= 0) { /* as the parent's full sort left it */
        if (count <= 4 * SPR_BSP_LEAF) pt_insertion(bc->pts + first, count, parent_axis);
        else pt_sort(bc->pts + first, count, parent_axis);
    }
    nd->axis = -1;
    nd->first = first;
    nd->count = count;
    double s[3] = {0, 0, 0};
    for (uint32_t k = first; k < first + count; k++) {
        if (k + 8 < first + count) __builtin_prefetch(bc->c->nrm + 3 * (size_t)bc->pts[k + 8].idx); /* scattered: a hint */
        const uint32_t i = bc->pts[k].idx;
        bc->order[k] = i;
        for (int a = 0; a < 3; a++) s[a] += bc->c->nrm[3 * (size_t)i + a];
        bc->leaf_of[i] = (uint32_t)id;
    }
    double l = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int a = 0; a < 3; a++) nd->normal[a] = l > 0.0 ? (float)(s[a] / l) : (a == 2 ? 1.0f : 0.0f);
}

/* A whole subtree into st, ids local to st (pre-order). */
static int32_t build(build_ctx *bc, sub_tree *st, uint32_t first, uint32_t count, int parent_axis)
{
    int32_t id = add_node(st);
    if (id < 0) return -1;
    int axis = split_axis(bc, first, count);
    if (axis < 0) {
        make_leaf(bc, &st->nodes[id], id, first, count, parent_axis);
        return id;
    }
    const uint32_t half = count / 2;
    const float split = split_at(bc, first, count, axis); /* the median the sort would give */
    int32_t l = build(bc, st, first, half, axis);
    int32_t r = l < 0 ? -1 : build(bc, st, first + half, count - half, axis);
    if (l < 0 || r < 0) return -1;
    spr_bsp_node *nd = &st->nodes[id];
    nd->axis = axis;
    nd->split = split;
    nd->left = l;
    nd->right = r;
    return id;
}

/* The top of the tree, split here: heap-numbered nodes (children of h are
 * 2h and 2h+1), so the numbering does not depend on which thread splits
 * which; the two halves of a node are split as parallel tasks. A node
 * at depth TOP_DEPTH, or a leaf, becomes a subtree job. */
enum { TOP_DEPTH = 5, TOP_NODES = 2 << TOP_DEPTH };
typedef struct top_node {
    int used, job;           /* job: 1 = a subtree built by build() */
    int axis;
    float split;
    uint32_t first, count;
    int parent_axis;
} top_node;

static void build_top(build_ctx *bc, top_node *tn, int h, uint32_t first, uint32_t count, int parent_axis, int depth)
{
    top_node *me = &tn[h];
    *me = (top_node){1, 0, -1, 0.0f, first, count, parent_axis};
    const int axis = depth > 0 ? split_axis(bc, first, count) : -1;
    if (axis < 0) {
        me->job = 1;
        return;
    }
    const uint32_t half = count / 2;
    me->axis = axis;
    me->split = split_at(bc, first, count, axis);
#pragma omp task if (count > 65536)
    build_top(bc, tn, 2 * h, first, half, axis, depth - 1);
#pragma omp task if (count > 65536)
    build_top(bc, tn, 2 * h + 1, first + half, count - half, axis, depth - 1);
#pragma omp taskwait
}

/* Splice in pre-order: returns the global id of top node h. */
static int32_t splice(spr_bsp *t, const top_node *tn, int h, sub_tree *jobs, const build_ctx *bc)
{
    const top_node *x = &tn[h];
    int32_t id = (int32_t)t->n_nodes;
    if (x->job) {
        sub_tree *st = &jobs[h];
        for (size_t k = 0; k < st->n; k++) {
            spr_bsp_node nd = st->nodes[k];
            if (nd.axis >= 0) nd.left += id, nd.right += id;
            t->nodes[t->n_nodes++] = nd;
        }
        for (uint32_t k = x->first; k < x->first + x->count; k++) bc->leaf_of[bc->order[k]] += (uint32_t)id;
        return id;
    }
    spr_bsp_node *nd = &t->nodes[t->n_nodes++];
    memset(nd, 0, sizeof *nd);
    nd->axis = x->axis;
    nd->split = x->split;
    int32_t l = splice(t, tn, 2 * h, jobs, bc);
    int32_t r = splice(t, tn, 2 * h + 1, jobs, bc);
    nd = &t->nodes[id];
    nd->left = l;
    nd->right = r;
    return id;
}

spr_result spr_bsp_build(const spr_cloud *c, spr_bsp *t, spr_error *err) { return spr__bsp_build_threads(c, 0, t, err); }

spr_result spr__bsp_build_threads(const spr_cloud *c, int threads, spr_bsp *t, spr_error *err)
{
    const int nt = threads > 0 ? threads : omp_get_max_threads();
    memset(t, 0, sizeof *t);
    t->n = c->n;
    t->order = spr__alloc(c->n * sizeof(uint32_t));
    t->leaf_of = spr__alloc(c->n * sizeof(uint32_t));
    pt4 *pts = spr__alloc(c->n * sizeof *pts);
    if (!t->order || !t->leaf_of || !pts) { free(pts); spr_bsp_free(t); return spr__fail(err, SPR_E_NOMEM, "bsp: out of memory"); }
    for (size_t i = 0; i < c->n; i++) {
        memcpy(pts[i].v, c->pos + 3 * i, sizeof pts[i].v);
        pts[i].idx = (uint32_t)i;
    }
    build_ctx bc = {c, t->order, t->leaf_of, pts};
    top_node tn[TOP_NODES];
    memset(tn, 0, sizeof tn);
#pragma omp parallel num_threads(nt)
#pragma omp single
    build_top(&bc, tn, 1, 0, (uint32_t)c->n, -1, c->n > 4096 ? TOP_DEPTH : 0);
    sub_tree jobs[TOP_NODES];
    memset(jobs, 0, sizeof jobs);
    int failed = 0;
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1) reduction(| : failed)
    for (int h = 1; h < TOP_NODES; h++)
        if (tn[h].used && tn[h].job) failed |= build(&bc, &jobs[h], tn[h].first, tn[h].count, tn[h].parent_axis) < 0;
    size_t total = 0;
    for (int h = 1; h < TOP_NODES; h++) total += tn[h].used ? (tn[h].job ? jobs[h].n : 1) : 0;
    if (!failed && (t->nodes = malloc((total ? total : 1) * sizeof *t->nodes))) splice(t, tn, 1, jobs, &bc);
    for (int h = 1; h < TOP_NODES; h++) free(jobs[h].nodes);
    free(pts);
    if (failed || !t->nodes) { spr_bsp_free(t); return spr__fail(err, SPR_E_NOMEM, "bsp: out of memory"); }
    return SPR_OK;
}

void spr_bsp_free(spr_bsp *t)
{
    free(t->nodes);
    free(t->order);
    free(t->leaf_of);
    memset(t, 0, sizeof *t);
}

typedef struct depth_item { double d; uint32_t i; } depth_item;
static int far_first(const void *a, const void *b)
{
    const depth_item *x = a, *y = b;
    if (x->d != y->d) return x->d > y->d ? -1 : 1;
    return (x->i > y->i) - (x->i < y->i);
}

/* Eye position (perspective) or a far point against the view direction (ortho). */
static void eye_of(const spr_view *v, double eye[3], double dir[3])
{
    double Vinv[16];
    spr__mat4_inverse(v->V, Vinv);
    for (int k = 0; k < 3; k++) {
        eye[k] = Vinv[4 * k + 3];
        dir[k] = -Vinv[4 * k + 2]; /* the camera looks down −z_eye */
    }
}

/* Items farthest first (far_first's order), by insertion: a leaf holds at
 * most 2·SPR_BSP_LEAF splats, where qsort's merge sort and callback cost
 * more than the comparisons. */
static void sort_far_first(depth_item *it, uint32_t n)
{
    for (uint32_t a = 1; a < n; a++) {
        depth_item v = it[a];
        uint32_t b = a;
        for (; b > 0 && far_first(&it[b - 1], &v) > 0; b--) it[b] = it[b - 1];
        it[b] = v;
    }
}

/* One leaf's splats farthest first into out (tmp: room for 2·SPR_BSP_LEAF
 * items or NULL; a larger leaf gets its own). */
static void leaf_far_first(const spr_bsp *t, const spr_cloud *c, const double eye[3], const double dir[3], const spr_bsp_node *nd,
                           depth_item *tmp, uint32_t *out)
{
    depth_item *it = nd->count <= 2 * SPR_BSP_LEAF && tmp ? tmp : malloc(nd->count * sizeof *it);
    if (!it) abort(); /* a leaf's few hundred bytes */
    for (uint32_t k = 0; k < nd->count; k++) {
        uint32_t i = t->order[nd->first + k];
        double d = 0.0;
        for (int a = 0; a < 3; a++) d += ((double)c->pos[3 * (size_t)i + a] - eye[a]) * dir[a];
        it[k] = (depth_item){d, i};
    }
    sort_far_first(it, nd->count);
    for (uint32_t k = 0; k < nd->count; k++) out[k] = it[k].i;
    if (it != tmp) free(it);
}

int spr_bsp_back_to_front(const spr_bsp *t, const spr_cloud *c, const spr_view *v, uint32_t *out)
{
    return spr__bsp_back_to_front_threads(t, c, v, 0, out);
}

int spr__bsp_back_to_front_threads(const spr_bsp *t, const spr_cloud *c, const spr_view *v, int threads, uint32_t *out)
{
    if (threads <= 0) threads = omp_get_max_threads();
    double eye[3], dir[3];
    eye_of(v, eye, dir);
    /* 1. the leaves in back-to-front order (a walk of the inner nodes), each
     *    with its place in out */
    int32_t *leaf = malloc((t->n_nodes ? t->n_nodes : 1) * sizeof *leaf);
    size_t *at = malloc((t->n_nodes ? t->n_nodes : 1) * sizeof *at);
    if (!leaf || !at) {
        free(leaf);
        free(at);
        return -1;
    }
    int32_t stack[128];
    int sp = 0;
    size_t nl = 0, o = 0;
    if (t->n_nodes) stack[sp++] = 0;
    while (sp) {
        const int32_t id = stack[--sp];
        const spr_bsp_node *nd = &t->nodes[id];
        if (nd->axis < 0) {
            leaf[nl] = id;
            at[nl++] = o;
            o += nd->count;
            continue;
        }
        /* the eye's side is near: push it first so the far side is visited first */
        double side = v->ortho ? -dir[nd->axis] : eye[nd->axis] - nd->split;
        int eye_right = side >= 0.0;
        stack[sp++] = eye_right ? nd->right : nd->left;
        stack[sp++] = eye_right ? nd->left : nd->right;
    }
    /* 2. each leaf sorted by depth into its place, leaves in parallel (each
     *    writes its own range: the same order on any number of threads) */
    const long nleaves = (long)nl;
#pragma omp parallel num_threads(threads)
    {
        depth_item *items = malloc(SPR_BSP_LEAF * 2 * sizeof *items + sizeof *items);
#pragma omp for schedule(dynamic, 64)
        for (long l = 0; l < nleaves; l++) leaf_far_first(t, c, eye, dir, &t->nodes[leaf[l]], items, out + at[l]);
        free(items);
    }
    free(leaf);
    free(at);
    return 0;
}
