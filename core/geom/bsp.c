/* bsp.c — kd tree over centres, leaf normals, back-to-front traversal. */
#include "spr_bsp.h"

#include <math.h>
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
typedef struct key_idx { float key; uint32_t idx; } key_idx;

static inline int ki_less(key_idx a, key_idx b) { return a.key < b.key || (a.key == b.key && a.idx < b.idx); }

static void ki_insertion(key_idx *v, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        key_idx x = v[i];
        size_t j = i;
        while (j > 0 && ki_less(x, v[j - 1])) v[j] = v[j - 1], j--;
        v[j] = x;
    }
}

static int ki_cmp(const void *a, const void *b)
{
    const key_idx *x = a, *y = b;
    return ki_less(*x, *y) ? -1 : ki_less(*y, *x) ? 1 : 0;
}

/* Put the k smallest of v[0 … n) first (any order on each side). */
static void ki_select(key_idx *v, size_t n, size_t k)
{
    size_t lo = 0, hi = n; /* the k-th lies in [lo, hi) */
    int budget = 64;
    while (hi - lo > 16) {
        if (budget-- == 0) { qsort(v + lo, hi - lo, sizeof *v, ki_cmp); return; } /* guards the worst case */
        /* median of three as the pivot */
        size_t mid = lo + (hi - lo) / 2;
        key_idx a = v[lo], b = v[mid], c = v[hi - 1], piv;
        if (ki_less(a, b)) piv = ki_less(b, c) ? b : ki_less(a, c) ? c : a;
        else piv = ki_less(a, c) ? a : ki_less(b, c) ? c : b;
        /* three-way partition: < piv | == piv | > piv (keys are distinct, so == is the pivot alone) */
        size_t i = lo, lt = lo, gt = hi;
        while (i < gt) {
            if (ki_less(v[i], piv)) { key_idx t = v[lt]; v[lt++] = v[i]; v[i++] = t; }
            else if (ki_less(piv, v[i])) { key_idx t = v[--gt]; v[gt] = v[i]; v[i] = t; }
            else i++;
        }
        if (k < lt) hi = lt;
        else if (k >= gt) lo = gt;
        else return;
    }
    ki_insertion(v + lo, hi - lo);
}

typedef struct sub_tree {
    spr_bsp_node *nodes;
    size_t n, cap;
} sub_tree;

typedef struct build_ctx {
    const spr_cloud *c;
    uint32_t *order, *leaf_of;
    key_idx *tmp;           /* n entries: selections work on [first, first + count) */
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
    const spr_cloud *c = bc->c;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t k = first; k < first + count; k++)
        for (int a = 0; a < 3; a++) {
            float v = c->pos[3 * (size_t)bc->order[k] + a];
            if (v < lo[a]) lo[a] = v;
            if (v > hi[a]) hi[a] = v;
        }
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    return count <= SPR_BSP_LEAF || !(hi[axis] > lo[axis]) ? -1 : axis;
}

/* Order [first, first+count) by `axis` completely (axis ≥ 0), or put the
 * `half` smallest first (half > 0). */
static void arrange(build_ctx *bc, uint32_t first, uint32_t count, int axis, uint32_t half)
{
    key_idx *v = bc->tmp + first;
    for (uint32_t k = 0; k < count; k++) {
        uint32_t i = bc->order[first + k];
        v[k] = (key_idx){bc->c->pos[3 * (size_t)i + axis], i};
    }
    if (half) ki_select(v, count, half);
    else qsort(v, count, sizeof *v, ki_cmp);
    for (uint32_t k = 0; k < count; k++) bc->order[first + k] = v[k].idx;
}

static void make_leaf(build_ctx *bc, spr_bsp_node *nd, int32_t id, uint32_t first, uint32_t count, int parent_axis)
{
    if (parent_axis >= 0) arrange(bc, first, count, parent_axis, 0); /* as the parent's full sort left it */
    nd->axis = -1;
    nd->first = first;
    nd->count = count;
    double s[3] = {0, 0, 0};
    for (uint32_t k = first; k < first + count; k++) {
        for (int a = 0; a < 3; a++) s[a] += bc->c->nrm[3 * (size_t)bc->order[k] + a];
        bc->leaf_of[bc->order[k]] = (uint32_t)id;
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
    uint32_t half = count / 2;
    arrange(bc, first, count, axis, half);
    /* the split: the smallest coordinate of the right half, the median the sort would give */
    float split = INFINITY;
    for (uint32_t k = first + half; k < first + count; k++) {
        float v = bc->c->pos[3 * (size_t)bc->order[k] + axis];
        if (v < split) split = v;
    }
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

/* The top of the tree: nodes split here, subtrees from depth `depth` on
 * listed as jobs (their ranges), in pre-order. */
typedef struct top_node {
    int job;                 /* ≥ 0: a subtree job; −1: an inner node split here */
    int axis;
    float split;
    int left, right;         /* top nodes */
    uint32_t first, count;
    int parent_axis;
} top_node;

static int build_top(build_ctx *bc, top_node *tn, int *n_tn, uint32_t first, uint32_t count, int parent_axis, int depth, int *n_jobs)
{
    int me = (*n_tn)++;
    tn[me] = (top_node){-1, -1, 0.0f, -1, -1, first, count, parent_axis};
    int axis = depth > 0 ? split_axis(bc, first, count) : -1;
    if (axis < 0) { /* a subtree job (a leaf, or the depth reached) */
        tn[me].job = (*n_jobs)++;
        return me;
    }
    uint32_t half = count / 2;
    arrange(bc, first, count, axis, half);
    float split = INFINITY;
    for (uint32_t k = first + half; k < first + count; k++) {
        float v = bc->c->pos[3 * (size_t)bc->order[k] + axis];
        if (v < split) split = v;
    }
    tn[me].axis = axis;
    tn[me].split = split;
    int l = build_top(bc, tn, n_tn, first, half, axis, depth - 1, n_jobs);
    int r = build_top(bc, tn, n_tn, first + half, count - half, axis, depth - 1, n_jobs);
    tn[me].left = l;
    tn[me].right = r;
    return me;
}

/* Splice in pre-order: returns the global id of top node `i`. */
static int32_t splice(spr_bsp *t, const top_node *tn, int i, sub_tree *jobs, const build_ctx *bc)
{
    const top_node *x = &tn[i];
    int32_t id = (int32_t)t->n_nodes;
    if (x->job >= 0) {
        sub_tree *st = &jobs[x->job];
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
    int32_t l = splice(t, tn, x->left, jobs, bc);
    int32_t r = splice(t, tn, x->right, jobs, bc);
    nd = &t->nodes[id];
    nd->left = l;
    nd->right = r;
    return id;
}

spr_result spr_bsp_build(const spr_cloud *c, spr_bsp *t, spr_error *err)
{
    memset(t, 0, sizeof *t);
    t->n = c->n;
    t->order = malloc((c->n ? c->n : 1) * sizeof(uint32_t));
    t->leaf_of = malloc((c->n ? c->n : 1) * sizeof(uint32_t));
    key_idx *tmp = malloc((c->n ? c->n : 1) * sizeof *tmp);
    if (!t->order || !t->leaf_of || !tmp) { free(tmp); spr_bsp_free(t); return spr__fail(err, SPR_E_NOMEM, "bsp: out of memory"); }
    for (size_t i = 0; i < c->n; i++) t->order[i] = (uint32_t)i;
    build_ctx bc = {c, t->order, t->leaf_of, tmp};
    enum { TOP_DEPTH = 5 };          /* up to 32 subtrees, built in parallel */
    top_node tn[2 << TOP_DEPTH];
    int n_tn = 0, n_jobs = 0;
    build_top(&bc, tn, &n_tn, 0, (uint32_t)c->n, -1, c->n > 4096 ? TOP_DEPTH : 0, &n_jobs);
    sub_tree jobs[1 << TOP_DEPTH];
    int job_node[1 << TOP_DEPTH];
    memset(jobs, 0, sizeof jobs);
    for (int i = 0; i < n_tn; i++)
        if (tn[i].job >= 0) job_node[tn[i].job] = i;
    int failed = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(| : failed)
    for (int j = 0; j < n_jobs; j++) {
        const top_node *x = &tn[job_node[j]];
        failed |= build(&bc, &jobs[j], x->first, x->count, x->parent_axis) < 0;
    }
    size_t total = (size_t)(n_tn - n_jobs);
    for (int j = 0; j < n_jobs; j++) total += jobs[j].n;
    if (!failed && (t->nodes = malloc((total ? total : 1) * sizeof *t->nodes))) splice(t, tn, 0, jobs, &bc);
    for (int j = 0; j < n_jobs; j++) free(jobs[j].nodes);
    free(tmp);
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

void spr_bsp_back_to_front(const spr_bsp *t, const spr_cloud *c, const spr_view *v, uint32_t *out)
{
    double eye[3], dir[3];
    eye_of(v, eye, dir);
    int32_t stack[128];
    int sp = 0;
    size_t o = 0;
    if (t->n_nodes) stack[sp++] = 0;
    depth_item *tmp = malloc(SPR_BSP_LEAF * 2 * sizeof *tmp + sizeof *tmp);
    while (sp) {
        const spr_bsp_node *nd = &t->nodes[stack[--sp]];
        if (nd->axis < 0) {
            depth_item *items = nd->count <= 2 * SPR_BSP_LEAF ? tmp : malloc(nd->count * sizeof *items);
            for (uint32_t k = 0; k < nd->count; k++) {
                uint32_t i = t->order[nd->first + k];
                double d = 0.0;
                for (int a = 0; a < 3; a++) d += ((double)c->pos[3 * (size_t)i + a] - eye[a]) * dir[a];
                items[k] = (depth_item){d, i};
            }
            qsort(items, nd->count, sizeof *items, far_first);
            for (uint32_t k = 0; k < nd->count; k++) out[o++] = items[k].i;
            if (items != tmp) free(items);
            continue;
        }
        /* the eye's side is near: push it first so the far side is visited first */
        double side = v->ortho ? -dir[nd->axis] : eye[nd->axis] - nd->split;
        int eye_right = side >= 0.0;
        stack[sp++] = eye_right ? nd->right : nd->left;
        stack[sp++] = eye_right ? nd->left : nd->right;
    }
    free(tmp);
}
