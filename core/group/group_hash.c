/* group_hash.c — hash grouping ([ZP] §4.3, Eq. 9, Fig. 9; SPEC §5.3).
 *
 *   d   = largest |component| of the BSP leaf's average normal (or, with
 *         --hash-axis normal, of the splat's own normal)
 *   x_i = floor(p_i[(d+1)%3] / r_i),  y_i = floor(p_i[(d+2)%3] / r_i)
 *   g_i = (x_i + s·y_i) mod K          (non-negative; s = 3 for K = 8)
 *   mode 1: done.  mode 2: per cell (d, x, y) the first splat in submission
 *   order keeps g_i; the later ones are queued and, in submission order,
 *   take argmin_k Σ A_ij over neighbours j already placed in group k.
 *   mode 3: as mode 2 for splats nearer the eye than a threshold, as mode 1
 *   for the rest.
 */
#include "spr_util.h"
#include "spr_bsp.h"
#include "spr_group.h"
#include "spr_overlap.h"
#include "spr__group.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void spr_hash_defaults(spr_hash_desc *d)
{
    memset(d, 0, sizeof *d);
    d->K = 8;
    d->mode = 1;
    d->axis = SPR_HASH_AXIS_BSP;
}

/* Shortest non-zero vectors (x, y) with x + s·y ≡ 0 (mod K), |x|,|y| ≤ K. */
static long shortest2(int K, int s, int *bx, int *by, int not_parallel_to_x, int not_parallel_to_y)
{
    long best = -1;
    for (int y = -K; y <= K; y++)
        for (int x = -K; x <= K; x++) {
            if (!x && !y) continue;
            if (((long)x + (long)s * y) % K) continue;
            if ((not_parallel_to_x || not_parallel_to_y) && (long)x * not_parallel_to_y - (long)y * not_parallel_to_x == 0) continue;
            long l2 = (long)x * x + (long)y * y;
            if (best < 0 || l2 < best) { best = l2; *bx = x; *by = y; }
        }
    return best;
}

int spr_hash_step(int K)
{
    int best_s = 1, bx = 0, by = 0;
    long best = -1;
    for (int s = 1; s < K; s++) {
        long l2 = shortest2(K, s, &bx, &by, 0, 0);
        if (l2 > best) { best = l2; best_s = s; }
    }
    return best_s;
}

double spr_hash_enlarge_factor(int K)
{
    if (K <= 1) return 1.0;
    int s = spr_hash_step(K), ax = 1, ay = 0, bx = 0, by = 1;
    shortest2(K, s, &ax, &ay, 0, 0);
    shortest2(K, s, &bx, &by, ax, ay);
    /* of ±b, the one closer to a makes the acute triangle of the lattice */
    long dm = (long)(ax - bx) * (ax - bx) + (long)(ay - by) * (ay - by), dp = (long)(ax + bx) * (ax + bx) + (long)(ay + by) * (ay + by);
    if (dp < dm) { bx = -bx; by = -by; }
    double a = hypot(ax, ay), b = hypot(bx, by), c = hypot(ax - bx, ay - by);
    double area = fabs((double)ax * by - (double)ay * bx) / 2.0;
    return a * b * c / (4.0 * area);
}

int spr_hash_axis_of(const float n[3])
{
    int d = 0;
    if (fabsf(n[1]) > fabsf(n[d])) d = 1;
    if (fabsf(n[2]) > fabsf(n[d])) d = 2;
    return d;
}

/* In float [decision]: Eq. 9 fixes no precision; float is what a per-frame
 * (GPU-side) hash would compute. */
/* floor of a finite float as an integer, without a libm call */
static inline int64_t floor_i64(float q)
{
    int64_t t = (int64_t)q;
    return (float)t > q ? t - 1 : t;
}

inline void spr_hash_cell(const spr_cloud *c, size_t i, int d, int64_t *x, int64_t *y)
{
    static const int next[5] = {1, 2, 0, 1, 2};
    const float *p = c->pos + 3 * i;
    float r = c->radius[i];
    *x = floor_i64(p[next[d]] / r);
    *y = floor_i64(p[next[d + 1]] / r);
}

int spr_hash_table(int64_t x, int64_t y, int K, int s)
{
    int64_t m = (x + (int64_t)s * y) % K;
    return (int)(m < 0 ? m + K : m);
}

/* A collision is two splats in one (x, y) entry of the hash table (SPEC
 * §5.3: "the first splat of each (x,y) cell"), whatever their axes.  One
 * pass in submission order over a set of the cells seen so far finds every
 * later splat of a cell, without sorting the cells (a sort of 1.1M keys
 * cost as much as the rest of mode 1).  The set is a bitmap over the cells'
 * bounding rectangle when that is at most 64 bits a splat (a resampled
 * model: a few megabytes, in cache), else an open-addressing table (linear
 * probing, at most half full).  Written here: the set holds two integers a
 * key and needs no deletion, less than any library's interface asks. */
typedef struct cell_set {
    int64_t x0, y0;
    uint64_t w, *bits;      /* bitmap: bit (y − y0)·w + (x − x0) */
    int64_t (*key)[2];      /* else the table */
    unsigned char *used;
    size_t mask;
} cell_set;

/* A set sized for the cells cell[0 … n) (min/max: their rectangle). */
static int cell_set_init(cell_set *cs, const int64_t (*cell)[2], size_t n)
{
    memset(cs, 0, sizeof *cs);
    int64_t lo[2] = {INT64_MAX, INT64_MAX}, hi[2] = {INT64_MIN, INT64_MIN};
    for (size_t i = 0; i < n; i++)
        for (int a = 0; a < 2; a++) {
            lo[a] = cell[i][a] < lo[a] ? cell[i][a] : lo[a];
            hi[a] = cell[i][a] > hi[a] ? cell[i][a] : hi[a];
        }
    /* the spans as unsigned differences: no overflow for any int64 range */
    const uint64_t w = n ? (uint64_t)hi[0] - (uint64_t)lo[0] + 1 : 1, h = n ? (uint64_t)hi[1] - (uint64_t)lo[1] + 1 : 1;
    const uint64_t budget = 64 * (uint64_t)n + 65536;
    if (w && h && w <= budget && h <= budget / w) {
        cs->x0 = lo[0], cs->y0 = lo[1], cs->w = w;
        return (cs->bits = calloc((w * h + 63) / 64, sizeof *cs->bits)) != NULL;
    }
    size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    cs->mask = cap - 1;
    cs->key = malloc(cap * sizeof *cs->key);
    cs->used = calloc(cap, 1);
    return cs->key && cs->used;
}

static void cell_set_free(cell_set *cs)
{
    free(cs->bits);
    free(cs->key);
    free(cs->used);
}

/* The table slot of (x, y): where it is, else the empty slot it would take. */
static size_t cell_set_slot(const cell_set *cs, int64_t x, int64_t y)
{
    uint64_t h = ((uint64_t)x * 0x9E3779B97F4A7C15ull) ^ ((uint64_t)y * 0xC2B2AE3D27D4EB4Full);
    h ^= h >> 29;
    size_t s = (size_t)h & cs->mask;
    while (cs->used[s] && (cs->key[s][0] != x || cs->key[s][1] != y)) s = (s + 1) & cs->mask;
    return s;
}

/* Whether (x, y) is in the set; with add, put it there too. */
static int cell_set_test(cell_set *cs, const int64_t cell[2], int add)
{
    if (cs->bits) {
        const uint64_t b = ((uint64_t)cell[1] - (uint64_t)cs->y0) * cs->w + ((uint64_t)cell[0] - (uint64_t)cs->x0);
        const uint64_t m = 1ull << (b & 63);
        const int had = (cs->bits[b >> 6] & m) != 0;
        if (add) cs->bits[b >> 6] |= m;
        return had;
    }
    const size_t s = cell_set_slot(cs, cell[0], cell[1]);
    const int had = cs->used[s];
    if (add && !had) {
        cs->used[s] = 1;
        cs->key[s][0] = cell[0];
        cs->key[s][1] = cell[1];
    }
    return had;
}

/* Axes of all splats (BSP leaf normal or own normal). */
spr_result spr_hash_axes(const spr_cloud *c, spr_hash_axis how, int32_t *axis, spr_error *err)
{
    return spr__hash_axes_threads(c, how, 0, axis, err);
}

spr_result spr__hash_axes_threads(const spr_cloud *c, spr_hash_axis how, int threads, int32_t *axis, spr_error *err)
{
    if (how == SPR_HASH_AXIS_NORMAL) {
        for (size_t i = 0; i < c->n; i++) axis[i] = spr_hash_axis_of(c->nrm + 3 * i);
        return SPR_OK;
    }
    spr_bsp t;
    spr_result r = spr__bsp_build_threads(c, threads, &t, err);
    if (r) return r;
    spr_hash_axes_of_bsp(&t, axis);
    spr_bsp_free(&t);
    return SPR_OK;
}

void spr_hash_axes_of_bsp(const spr_bsp *t, int32_t *axis)
{
    for (size_t i = 0; i < t->n; i++) axis[i] = spr_hash_axis_of(t->nodes[t->leaf_of[i]].normal);
}

static int handles_collision(const spr_hash_desc *d, const spr_cloud *c, size_t i)
{
    if (d->mode == 2) return 1;
    if (d->mode != 3) return 0;
    double q = 0.0;
    for (int k = 0; k < 3; k++) q += ((double)c->pos[3 * i + k] - d->eye[k]) * ((double)c->pos[3 * i + k] - d->eye[k]);
    return sqrt(q) < d->near_dist;
}

enum { PLACED = 0, PENDING = 1, PENDING_COLLIDES = 2 };

/* Whether group k's placed neighbours adj[0 … m) of row's splat overlap it:
 * Σ A > 0. */
static int group_overlaps(const spr_overlap_row *row, const uint32_t *adj, size_t m, const int32_t *lab, int k)
{
    for (size_t e = 0; e < m; e++)
        if (lab[adj[e]] == k && spr_overlap_row_positive(row, adj[e])) return 1;
    return 0;
}

typedef struct area_edge { uint32_t j; int32_t g; float a; } area_edge;

/* The group of least total overlap Σ A_vj with v's placed neighbours adj[0
 * … m) (indices of the copy sp, labels lab in its order), ties: the table
 * group if minimal, else the smallest k.  Not every area is needed: a
 * group with no placed neighbour sums to exactly 0, the least possible, so
 * when there is one the answer is the table group if its sum is 0, else
 * the smallest group whose sum is 0; a sum is 0 when none of its areas is
 * positive, found without counting every sample.  Only a row whose every
 * group has a placed neighbour sums its areas, in the cloud's index order
 * (order: copy → cloud) as a full overlap graph's row would.  a, buf: room
 * for m areas and edges. */
static int least_overlap(const spr_cloud *sp, const uint32_t *order, const uint32_t *adj, size_t m, size_t v, const int32_t *lab, int K,
                         int table, double eps, float *a, area_edge *buf)
{
    size_t cnt[SPR_MAX_GROUPS] = {0};
    for (size_t e = 0; e < m; e++) cnt[lab[adj[e]]]++;
    if (!cnt[table]) return table;
    int empty = -1;
    for (int k = 0; k < K && empty < 0; k++)
        if (!cnt[k]) empty = k;
    if (empty >= 0) {
        spr_overlap_row row;
        spr_overlap_row_init(&row, sp, v, eps);
        if (!group_overlaps(&row, adj, m, lab, table)) return table;
        for (int k = 0; k < empty; k++)
            if (k != table && !group_overlaps(&row, adj, m, lab, k)) return k;
        return empty;
    }
    spr_overlap_areas(sp, v, adj, m, eps, a);
    for (size_t e = 0; e < m; e++) { /* insertion by cloud index: rows are short */
        const area_edge x = {order[adj[e]], lab[adj[e]], a[e]};
        size_t y = e;
        for (; y > 0 && buf[y - 1].j > x.j; y--) buf[y] = buf[y - 1];
        buf[y] = x;
    }
    double sum[SPR_MAX_GROUPS];
    for (int k = 0; k < K; k++) sum[k] = 0.0;
    for (size_t e = 0; e < m; e++) sum[buf[e].g] += buf[e].a;
    int best = table;
    for (int k = 0; k < K; k++)
        if (sum[k] < sum[best]) best = k;
    return best;
}

/* Mode 3: the splats that can take part in a collision nearer than its
 * threshold, as a row or a neighbour (NULL: all of them, or out of
 * memory): a neighbour j of a splat i within near_dist of the eye lies
 * within near_dist + r_i + r_j ≤ near_dist + 2·max r (widened by 1e-9
 * relative: more than any rounding of handles_collision's distance). */
static unsigned char *near_part(const spr_cloud *c, const spr_hash_desc *d)
{
    float rmax = 0.0f;
    for (size_t i = 0; i < c->n; i++) rmax = c->radius[i] > rmax ? c->radius[i] : rmax;
    const double reach = (d->near_dist + 2.0 * (double)rmax) * (1.0 + 1e-9);
    unsigned char *in = malloc(c->n ? c->n : 1);
    if (!in) return NULL;
    for (size_t i = 0; i < c->n; i++) {
        double q = 0.0;
        for (int k = 0; k < 3; k++) q += ((double)c->pos[3 * i + k] - d->eye[k]) * ((double)c->pos[3 * i + k] - d->eye[k]);
        in[i] = sqrt(q) < reach;
    }
    return in;
}

/* Place the pending splats in submission order, after every placed one: a
 * colliding splat takes the group of least total overlap A with the splats
 * placed before it (ties: its table group if minimal, else the smallest k);
 * the others keep their table group.  The rows and areas are those of the
 * Morton-ordered copy (a colliding splat's neighbours lie close there). */
static spr_result place_pending(const spr_cloud *c, spr_hash_desc *d, int32_t *label, const unsigned char *state,
                                spr_group_stats *st, spr_error *err)
{
    size_t colliding = 0;
    for (size_t i = 0; i < c->n; i++) colliding += state[i] == PENDING_COLLIDES;
    if (!colliding) return SPR_OK;
    if (!(d->eps > 0.0)) d->eps = spr_cloud_default_eps(c); /* a full pass: only when collisions need areas */
    /* the colliding rows only (mode 3: those nearer than its threshold),
     * each with its neighbours placed before it */
    spr__spatial sp;
    spr_graph g;
    double t1 = spr_now_ms();
    /* when pending splat i is placed, the placed splats are those placed
     * from the start and the pending ones before it: its only neighbours
     * that count, those j with before[j] < before[i] */
    uint32_t *before = spr__alloc((c->n ? c->n : 1) * sizeof *before);
    unsigned char *in = d->mode == 3 ? near_part(c, d) : NULL;
    if (!before || (d->mode == 3 && !in)) {
        free(before);
        return spr__fail(err, SPR_E_NOMEM, "hash: out of memory");
    }
    for (size_t i = 0; i < c->n; i++) before[i] = state[i] == PLACED ? 0 : (uint32_t)i + 1;
    spr_result r = spr__pair_graph_spatial(c, 1.0, in, state, PENDING_COLLIDES, before, d->threads, &d->progress, &sp, &g, err);
    free(before);
    free(in);
    st->ms_graph = spr_now_ms() - t1;
    if (r) return r;
    uint64_t max_deg = 1;
    for (size_t q = 0; q < g.n; q++)
        if (g.start[q + 1] - g.start[q] > max_deg) max_deg = g.start[q + 1] - g.start[q];
    area_edge *buf = malloc(max_deg * sizeof *buf);
    float *a = malloc(max_deg * sizeof *a);
    int32_t *lab = malloc((g.n ? g.n : 1) * sizeof *lab); /* the labels in the copy's order */
    if (!buf || !a || !lab) r = spr__fail(err, SPR_E_NOMEM, "hash: out of memory");
    for (size_t q = 0; !r && q < g.n; q++) lab[q] = label[sp.order[q]];
    /* the colliding splats in submission order, so the rows ahead can be
     * fetched: each is a random row of the copy, its neighbours' data and
     * labels close to it there */
    size_t nl = 0;
    uint32_t *todo = r ? NULL : malloc(colliding * sizeof *todo);
    if (!r && !todo) r = spr__fail(err, SPR_E_NOMEM, "hash: out of memory");
    for (size_t i = 0; !r && i < c->n; i++)
        if (state[i] == PENDING_COLLIDES) todo[nl++] = (uint32_t)i;
    for (size_t t = 0; !r && t < nl; t++) {
        if (t + 16 < nl) { /* hints, no arithmetic: the row's bounds, label and data first, its entries later */
            const uint32_t q2 = sp.rank[todo[t + 16]];
            __builtin_prefetch(g.start + q2);
            __builtin_prefetch(lab + q2);
            __builtin_prefetch(sp.c.pos + 3 * (size_t)q2);
            __builtin_prefetch(sp.c.nrm + 3 * (size_t)q2);
        }
        if (t + 8 < nl) __builtin_prefetch(g.adj + g.start[sp.rank[todo[t + 8]]]);
        const size_t i = todo[t];
        const uint32_t q = sp.rank[i];
        const int k = least_overlap(&sp.c, sp.order, g.adj + g.start[q], (size_t)(g.start[q + 1] - g.start[q]), q, lab, d->K, label[i],
                                    d->eps, a, buf);
        st->displaced += k != label[i];
        label[i] = lab[q] = k;
    }
    free(todo);
    free(lab);
    free(a);
    free(buf);
    spr_graph_free(&g);
    spr__spatial_free(&sp);
    return r;
}

spr_result spr_group_hash(const spr_cloud *c, const spr_hash_desc *din, int32_t *label, spr_group_stats *st, spr_error *err)
{
    spr_hash_desc d = *din;
    if (d.K < 1 || d.K > SPR_MAX_GROUPS) return spr__fail(err, SPR_E_ARG, "hash: --k %d outside 1..%d", d.K, SPR_MAX_GROUPS);
    if (d.mode < 1 || d.mode > 3) return spr__fail(err, SPR_E_ARG, "hash: --mode %d is not 1, 2 or 3", d.mode);
    memset(st, 0, sizeof *st);
    double t0 = spr_now_ms();
    const int s = d.K > 1 ? spr_hash_step(d.K) : 0;
    spr_result r = SPR_OK;
    int32_t *own = NULL; /* the axes computed here */
    const int32_t *axis = d.axes;
    cell_set cs = {0};
    unsigned char *state = NULL;
    int64_t (*cell)[2] = NULL; /* modes 2/3: every splat's cell, for the collisions */
    if (!axis && (d.axis == SPR_HASH_AXIS_BSP || d.mode != 1)) {
        if (!(own = spr__alloc(c->n * sizeof *own))) return spr__fail(err, SPR_E_NOMEM, "hash: out of memory");
        spr_progress_report(&d.progress, "BSP tree", 0, 1);
        r = spr__hash_axes_threads(c, d.axis, d.threads, own, err);
        spr_progress_report(&d.progress, "BSP tree", 1, 1);
        if (r) { free(own); return r; }
        axis = own;
    }
    if (d.mode != 1 && (!(cell = spr__alloc(c->n * sizeof *cell)) || !(state = calloc(c->n ? c->n : 1, 1)))) {
        r = spr__fail(err, SPR_E_NOMEM, "hash: out of memory");
        goto done;
    }
    const int pow2 = (d.K & (d.K - 1)) == 0;
    for (size_t i = 0; i < c->n; i++) { /* the per-frame work: one pass */
        int64_t x, y;
        spr_hash_cell(c, i, axis ? axis[i] : spr_hash_axis_of(c->nrm + 3 * i), &x, &y);
        /* two's complement masking is the non-negative remainder for K = 2^m */
        label[i] = pow2 ? (int32_t)((x + (int64_t)s * y) & (d.K - 1)) : spr_hash_table(x, y, d.K, s);
        if (cell) cell[i][0] = x, cell[i][1] = y;
    }
    st->K = d.K;
    st->ms_color = spr_now_ms() - t0;
    if (d.mode == 1) goto done;

    /* modes 2/3: the first splat of each cell keeps its group, the later
     * ones (where collisions are handled) are queued */
    if (!cell_set_init(&cs, (const int64_t (*)[2])cell, c->n)) { r = spr__fail(err, SPR_E_NOMEM, "hash: out of memory"); goto done; }
    for (size_t i = 0; i < c->n; i++)
        if (cell_set_test(&cs, cell[i], 1) && handles_collision(&d, c, i)) state[i] = PENDING_COLLIDES;
    r = place_pending(c, &d, label, state, st, err);
    st->ms_optimise = spr_now_ms() - t0 - st->ms_color;
done:
    cell_set_free(&cs);
    free(cell);
    free(state);
    free(own);
    return r;
}

spr_result spr_group_hash_update(const spr_cloud *c, const spr_hash_desc *din, int32_t *label, const uint32_t *changed,
                                 size_t m, spr_group_stats *st, spr_error *err)
{
    spr_hash_desc d = *din;
    if (d.K < 1 || d.K > SPR_MAX_GROUPS || d.mode < 1 || d.mode > 3)
        return spr__fail(err, SPR_E_ARG, "hash update: K %d or mode %d out of range", d.K, d.mode);
    memset(st, 0, sizeof *st);
    st->K = d.K;
    const int s = d.K > 1 ? spr_hash_step(d.K) : 0;
    int32_t *axis = malloc((c->n ? c->n : 1) * sizeof *axis);
    unsigned char *state = calloc(c->n ? c->n : 1, 1);
    cell_set cs = {0};
    int64_t (*cell)[2] = NULL;
    if (!axis || !state) { free(axis); free(state); return spr__fail(err, SPR_E_NOMEM, "hash update: out of memory"); }
    spr_result r = d.axes ? (memcpy(axis, d.axes, c->n * sizeof *axis), SPR_OK) : spr__hash_axes_threads(c, d.axis, d.threads, axis, err);
    for (size_t k = 0; k < m && !r; k++) {
        if (changed[k] >= c->n) r = spr__fail(err, SPR_E_ARG, "hash update: splat %u beyond the cloud", changed[k]);
        else state[changed[k]] = PENDING;
    }
    if (r) goto done;
    for (size_t k = 0; k < m; k++) {
        int64_t x, y;
        spr_hash_cell(c, changed[k], axis[changed[k]], &x, &y);
        label[changed[k]] = spr_hash_table(x, y, d.K, s);
    }
    if (d.mode != 1 && m) {
        /* a changed splat collides when an unchanged splat holds its cell */
        if (!(cell = malloc(c->n * sizeof *cell))) { r = spr__fail(err, SPR_E_NOMEM, "hash update: out of memory"); goto done; }
        for (size_t i = 0; i < c->n; i++) spr_hash_cell(c, i, axis[i], &cell[i][0], &cell[i][1]);
        if (!cell_set_init(&cs, (const int64_t (*)[2])cell, c->n)) { r = spr__fail(err, SPR_E_NOMEM, "hash update: out of memory"); goto done; }
        for (size_t i = 0; i < c->n; i++)
            if (!state[i]) cell_set_test(&cs, cell[i], 1);
        for (size_t i = 0; i < c->n; i++)
            if (state[i] && cell_set_test(&cs, cell[i], 0) && handles_collision(&d, c, i)) state[i] = PENDING_COLLIDES;
        r = place_pending(c, &d, label, state, st, err);
    }
done:
    cell_set_free(&cs);
    free(cell);
    free(axis);
    free(state);
    return r;
}
