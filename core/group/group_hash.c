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
 * §5.3: "the first splat of each (x,y) cell"), whatever their axes. */
typedef struct cell_key { int64_t x, y; uint32_t i; } cell_key;
static int by_cell(const void *a, const void *b)
{
    const cell_key *p = a, *q = b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    if (p->y != q->y) return p->y < q->y ? -1 : 1;
    return (p->i > q->i) - (p->i < q->i);
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

/* Group of minimal total overlap with placed neighbours (A over og's edges from v). */
static int least_overlap(const spr_overlap_graph *og, size_t v, const int32_t *label, const unsigned char *placed, int K,
                         int table)
{
    double sum[SPR_MAX_GROUPS];
    for (int k = 0; k < K; k++) sum[k] = 0.0;
    for (uint64_t e = og->g.start[v]; e < og->g.start[v + 1]; e++) {
        uint32_t j = og->g.adj[e];
        if (placed[j]) sum[label[j]] += og->A[e];
    }
    int best = table;
    for (int k = 0; k < K; k++)
        if (sum[k] < sum[best]) best = k;
    return best;
}

static int same_cell(const cell_key *a, const cell_key *b) { return a->x == b->x && a->y == b->y; }

enum { PLACED = 0, PENDING = 1, PENDING_COLLIDES = 2 };

/* When pending splat i is placed, the placed splats are those placed from
 * the start and the pending ones before it: the only areas it reads. */
static int placed_before(const void *user, size_t i, uint32_t j)
{
    const unsigned char *state = user;
    return state[j] == PLACED || j < i;
}

/* Place the pending splats in submission order, after every placed one: a
 * colliding splat takes the group of least total overlap A with the splats
 * placed before it (ties: its table group if minimal, else the smallest k);
 * the others keep their table group. */
static spr_result place_pending(const spr_cloud *c, spr_hash_desc *d, int32_t *label, const unsigned char *state,
                                spr_group_stats *st, spr_error *err)
{
    size_t colliding = 0;
    for (size_t i = 0; i < c->n; i++) colliding += state[i] == PENDING_COLLIDES;
    if (!colliding) return SPR_OK;
    unsigned char *placed = malloc(c->n);
    if (!placed) return spr__fail(err, SPR_E_NOMEM, "hash: out of memory");
    for (size_t i = 0; i < c->n; i++) placed[i] = state[i] == PLACED;
    spr_overlap_graph og;
    double t1 = spr_now_ms();
    if (!(d->eps > 0.0)) d->eps = spr_cloud_default_eps(c); /* a full pass: only when collisions need areas */
    /* neighbours and areas only for the colliding splats: mode 3 does
     * collision work only for the splats nearer than its threshold */
    spr_result r = spr_overlap_graph_build_rows_need(c, d->eps, state, PENDING_COLLIDES, d->threads, &d->progress, placed_before, state, &og, err);
    st->ms_graph = spr_now_ms() - t1;
    for (size_t i = 0; !r && i < c->n; i++) {
        if (state[i] == PLACED) continue;
        if (state[i] == PENDING_COLLIDES) {
            int g = least_overlap(&og, i, label, placed, d->K, label[i]);
            st->displaced += g != label[i];
            label[i] = g;
        }
        placed[i] = 1;
    }
    if (!r) spr_overlap_graph_free(&og);
    free(placed);
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
    int32_t *axis = NULL;
    if (d.axes) {
        axis = (int32_t *)d.axes; /* not freed below */
    } else if (d.axis == SPR_HASH_AXIS_BSP || d.mode != 1) {
        if (!(axis = malloc((c->n ? c->n : 1) * sizeof *axis))) return spr__fail(err, SPR_E_NOMEM, "hash: out of memory");
        spr_progress_report(&d.progress, "BSP tree", 0, 1);
        r = spr__hash_axes_threads(c, d.axis, d.threads, axis, err);
        spr_progress_report(&d.progress, "BSP tree", 1, 1);
        if (r) { free(axis); return r; }
    }
    const int pow2 = (d.K & (d.K - 1)) == 0;
    for (size_t i = 0; i < c->n; i++) { /* the per-frame work: one pass */
        int64_t x, y;
        spr_hash_cell(c, i, axis ? axis[i] : spr_hash_axis_of(c->nrm + 3 * i), &x, &y);
        /* two's complement masking is the non-negative remainder for K = 2^m */
        label[i] = pow2 ? (int32_t)((x + (int64_t)s * y) & (d.K - 1)) : spr_hash_table(x, y, d.K, s);
    }
    st->K = d.K;
    st->ms_color = spr_now_ms() - t0;
    if (axis == d.axes) axis = NULL;
    if (d.mode == 1) { free(axis); return SPR_OK; }
    if (!axis) {
        if (!(axis = malloc((c->n ? c->n : 1) * sizeof *axis))) return spr__fail(err, SPR_E_NOMEM, "hash: out of memory");
        if (d.axes) memcpy(axis, d.axes, c->n * sizeof *axis);
        else if ((r = spr__hash_axes_threads(c, d.axis, d.threads, axis, err))) { free(axis); return r; }
    }

    /* modes 2/3: the first splat of each cell keeps its group, the later
     * ones (where collisions are handled) are queued */
    cell_key *keys = malloc(c->n * sizeof *keys);
    unsigned char *state = calloc(c->n ? c->n : 1, 1);
    if (!keys || !state) { r = spr__fail(err, SPR_E_NOMEM, "hash: out of memory"); goto done; }
    for (size_t i = 0; i < c->n; i++) {
        spr_hash_cell(c, i, axis[i], &keys[i].x, &keys[i].y);
        keys[i].i = (uint32_t)i;
    }
    qsort(keys, c->n, sizeof *keys, by_cell);
    for (size_t k = 1; k < c->n; k++)
        if (same_cell(&keys[k], &keys[k - 1]) && handles_collision(&d, c, keys[k].i)) state[keys[k].i] = PENDING_COLLIDES;
    r = place_pending(c, &d, label, state, st, err);
    st->ms_optimise = spr_now_ms() - t0 - st->ms_color;
done:
    free(keys);
    free(state);
    free(axis);
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
    cell_key *keys = NULL;
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
        if (!(keys = malloc(c->n * sizeof *keys))) { r = spr__fail(err, SPR_E_NOMEM, "hash update: out of memory"); goto done; }
        size_t nk = 0;
        for (size_t i = 0; i < c->n; i++)
            if (!state[i]) {
                keys[nk] = (cell_key){0, 0, (uint32_t)i};
                spr_hash_cell(c, i, axis[i], &keys[nk].x, &keys[nk].y);
                nk++;
            }
        qsort(keys, nk, sizeof *keys, by_cell);
        for (size_t i = 0; i < c->n; i++) {
            if (!state[i]) continue;
            cell_key probe = {0, 0, 0};
            spr_hash_cell(c, i, axis[i], &probe.x, &probe.y);
            size_t lo = 0, hi = nk;
            while (lo < hi) {
                size_t mid = (lo + hi) / 2;
                if (by_cell(&keys[mid], &probe) < 0) lo = mid + 1; else hi = mid;
            }
            if (lo < nk && same_cell(&keys[lo], &probe) && handles_collision(&d, c, i)) state[i] = PENDING_COLLIDES;
        }
        r = place_pending(c, &d, label, state, st, err);
    }
done:
    free(keys);
    free(axis);
    free(state);
    return r;
}
