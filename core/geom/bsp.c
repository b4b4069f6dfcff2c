/* bsp.c — kd tree over centres, leaf normals, back-to-front traversal. */
#include "spr_bsp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct build_ctx {
    const spr_cloud *c;
    spr_bsp *t;
    size_t cap;
    int axis; /* for the comparator */
} build_ctx;

static _Thread_local build_ctx *sort_ctx;
static int by_axis(const void *a, const void *b)
{
    uint32_t i = *(const uint32_t *)a, j = *(const uint32_t *)b;
    float x = sort_ctx->c->pos[3 * (size_t)i + sort_ctx->axis], y = sort_ctx->c->pos[3 * (size_t)j + sort_ctx->axis];
    if (x != y) return x < y ? -1 : 1;
    return (i > j) - (i < j);
}

static int32_t build(build_ctx *bc, uint32_t first, uint32_t count)
{
    spr_bsp *t = bc->t;
    if (t->n_nodes == bc->cap) {
        size_t cap = bc->cap ? 2 * bc->cap : 64;
        spr_bsp_node *nn = realloc(t->nodes, cap * sizeof *nn);
        if (!nn) return -1;
        t->nodes = nn;
        bc->cap = cap;
    }
    int32_t id = (int32_t)t->n_nodes++;
    spr_bsp_node *nd = &t->nodes[id];
    memset(nd, 0, sizeof *nd);
    const spr_cloud *c = bc->c;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t k = first; k < first + count; k++)
        for (int a = 0; a < 3; a++) {
            float v = c->pos[3 * (size_t)t->order[k] + a];
            if (v < lo[a]) lo[a] = v;
            if (v > hi[a]) hi[a] = v;
        }
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    if (count <= SPR_BSP_LEAF || !(hi[axis] > lo[axis])) {
        nd->axis = -1;
        nd->first = first;
        nd->count = count;
        double s[3] = {0, 0, 0};
        for (uint32_t k = first; k < first + count; k++) {
            for (int a = 0; a < 3; a++) s[a] += c->nrm[3 * (size_t)t->order[k] + a];
            t->leaf_of[t->order[k]] = (uint32_t)id;
        }
        double l = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
        for (int a = 0; a < 3; a++) nd->normal[a] = l > 0.0 ? (float)(s[a] / l) : (a == 2 ? 1.0f : 0.0f);
        return id;
    }
    bc->axis = axis;
    sort_ctx = bc;
    qsort(t->order + first, count, sizeof(uint32_t), by_axis);
    uint32_t half = count / 2;
    float split = c->pos[3 * (size_t)t->order[first + half] + axis];
    /* children: [first, first+half) and [first+half, first+count) */
    int32_t l = build(bc, first, half);
    int32_t r = l < 0 ? -1 : build(bc, first + half, count - half);
    if (l < 0 || r < 0) return -1;
    nd = &bc->t->nodes[id]; /* nodes may have moved */
    nd->axis = axis;
    nd->split = split;
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
    if (!t->order || !t->leaf_of) { spr_bsp_free(t); return spr__fail(err, SPR_E_NOMEM, "bsp: out of memory"); }
    for (size_t i = 0; i < c->n; i++) t->order[i] = (uint32_t)i;
    build_ctx bc = {c, t, 0, 0};
    if (build(&bc, 0, (uint32_t)c->n) < 0) { spr_bsp_free(t); return spr__fail(err, SPR_E_NOMEM, "bsp: out of memory"); }
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
