/* group_hash.c — hash grouping, mode 1 ([ZP] §4.3, Eq. 9, Fig. 9).
 *
 *   d   = index of the largest |component| of n_i  (SPEC §5.3 [decision])
 *   x_i = floor(p_i[(d+1)%3] / r_i),  y_i = floor(p_i[(d+2)%3] / r_i)
 *   g_i = (x_i + s·y_i) mod K          (non-negative remainder; s = 3 for K = 8)
 */
#include "spr_group.h"

#include <math.h>
#include <string.h>

int spr_hash_step(int K)
{
    int best_s = 1;
    long best = -1;
    for (int s = 1; s < K; s++) {
        /* shortest non-zero lattice vector (x, y) with x + s·y ≡ 0 (mod K) */
        long shortest = (long)K * K;
        for (int y = -K; y <= K; y++)
            for (int x = -K; x <= K; x++) {
                if (!x && !y) continue;
                long m = ((long)x + (long)s * y) % K;
                if (m) continue;
                long l2 = (long)x * x + (long)y * y;
                if (l2 < shortest) shortest = l2;
            }
        if (shortest > best) { best = shortest; best_s = s; }
    }
    return best_s;
}

void spr_hash_cell(const spr_cloud *c, size_t i, int64_t *x, int64_t *y)
{
    const float *n = c->nrm + 3 * i, *p = c->pos + 3 * i;
    int d = 0;
    if (fabsf(n[1]) > fabsf(n[d])) d = 1;
    if (fabsf(n[2]) > fabsf(n[d])) d = 2;
    double r = c->radius[i];
    *x = (int64_t)floor((double)p[(d + 1) % 3] / r);
    *y = (int64_t)floor((double)p[(d + 2) % 3] / r);
}

spr_result spr_group_hash(const spr_cloud *c, int K, int32_t *label, spr_group_stats *st, spr_error *err)
{
    if (K < 1 || K > SPR_MAX_GROUPS) return spr__fail(err, SPR_E_ARG, "hash: --k %d outside 1..%d", K, SPR_MAX_GROUPS);
    memset(st, 0, sizeof *st);
    int s = K > 1 ? spr_hash_step(K) : 0;
    for (size_t i = 0; i < c->n; i++) {
        int64_t x, y;
        spr_hash_cell(c, i, &x, &y);
        int64_t m = (x + (int64_t)s * y) % K;
        label[i] = (int32_t)(m < 0 ? m + K : m);
    }
    st->K = K;
    return SPR_OK;
}
