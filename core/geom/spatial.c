/* spatial.c — Morton order and the spatially ordered working copy. */
#include "spr__spatial.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* the 10 low bits of x spread to every third bit */
static uint32_t spread10(uint32_t x)
{
    x &= 0x3FFu;
    x = (x | x << 16) & 0x030000FFu;
    x = (x | x << 8) & 0x0300F00Fu;
    x = (x | x << 4) & 0x030C30C3u;
    x = (x | x << 2) & 0x09249249u;
    return x;
}

/* Written here rather than taken from a library: a stable two-pass radix
 * sort of 30-bit keys is twenty lines, and neither libc's qsort (not
 * stable, about ten times slower at 10M keys) nor our dependencies offer one. */
spr_result spr__morton_order(const spr_cloud *c, const spr_bounds *b, uint32_t *order, spr_error *err)
{
    const size_t n = c->n;
    double ext = 0.0;
    for (int a = 0; a < 3; a++)
        if (b->hi[a] - b->lo[a] > ext) ext = b->hi[a] - b->lo[a];
    const double scale = ext > 0.0 ? 1024.0 / ext : 0.0;
    uint32_t *key = malloc((n ? n : 1) * sizeof *key), *tk = malloc((n ? n : 1) * sizeof *tk), *ti = malloc((n ? n : 1) * sizeof *ti);
    size_t *cnt = calloc(1u << 15, sizeof *cnt);
    if (!key || !tk || !ti || !cnt) {
        free(key), free(tk), free(ti), free(cnt);
        return spr__fail(err, SPR_E_NOMEM, "spatial order: out of memory for %zu splats", n);
    }
    for (size_t i = 0; i < n; i++) {
        uint32_t code = 0;
        for (int a = 0; a < 3; a++) {
            double q = floor(((double)c->pos[3 * i + a] - b->lo[a]) * scale);
            uint32_t k = q < 0.0 ? 0u : q > 1023.0 ? 1023u : (uint32_t)q;
            code |= spread10(k) << a;
        }
        key[i] = code;
        order[i] = (uint32_t)i;
    }
    /* two stable passes of 15 bits, the low half first: ties keep submission order */
    uint32_t *src_k = key, *src_i = order, *dst_k = tk, *dst_i = ti;
    for (int pass = 0; pass < 2; pass++) {
        const int shift = 15 * pass;
        memset(cnt, 0, (1u << 15) * sizeof *cnt);
        for (size_t i = 0; i < n; i++) cnt[(src_k[i] >> shift) & 0x7FFFu]++;
        size_t sum = 0;
        for (size_t d = 0; d < (1u << 15); d++) {
            size_t t = cnt[d];
            cnt[d] = sum;
            sum += t;
        }
        for (size_t i = 0; i < n; i++) {
            size_t at = cnt[(src_k[i] >> shift) & 0x7FFFu]++;
            dst_k[at] = src_k[i];
            dst_i[at] = src_i[i];
        }
        uint32_t *t = src_k; src_k = dst_k; dst_k = t;
        t = src_i; src_i = dst_i; dst_i = t;
    }
    /* after two passes the result is back in key/order */
    free(key), free(tk), free(ti), free(cnt);
    return SPR_OK;
}

spr_result spr__spatial_make(const spr_cloud *c, const spr_bounds *b, int threads, spr__spatial *s, spr_error *err)
{
    memset(s, 0, sizeof *s);
    const size_t n = c->n, m = n ? n : 1;
    s->c.n = n;
    s->c.pos = malloc(3 * m * sizeof(float));
    s->c.nrm = malloc(3 * m * sizeof(float));
    s->c.radius = malloc(m * sizeof(float));
    s->order = malloc(m * sizeof *s->order);
    s->rank = malloc(m * sizeof *s->rank);
    if (!s->c.pos || !s->c.nrm || !s->c.radius || !s->order || !s->rank) {
        spr__spatial_free(s);
        return spr__fail(err, SPR_E_NOMEM, "spatial order: out of memory for a copy of %zu splats", n);
    }
    spr_result r = spr__morton_order(c, b, s->order, err);
    if (r) { spr__spatial_free(s); return r; }
#pragma omp parallel for num_threads(threads > 0 ? threads : omp_get_max_threads()) schedule(static)
    for (long q = 0; q < (long)n; q++) {
        const size_t i = s->order[q];
        memcpy(s->c.pos + 3 * (size_t)q, c->pos + 3 * i, 3 * sizeof(float));
        memcpy(s->c.nrm + 3 * (size_t)q, c->nrm + 3 * i, 3 * sizeof(float));
        s->c.radius[q] = c->radius[i];
        s->rank[i] = (uint32_t)q;
    }
    return SPR_OK;
}

void spr__spatial_free(spr__spatial *s)
{
    free(s->c.pos);
    free(s->c.nrm);
    free(s->c.radius);
    free(s->order);
    free(s->rank);
    memset(s, 0, sizeof *s);
}
