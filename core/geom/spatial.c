/* spatial.c — Morton order and the spatially ordered working copy. */
#include "spr__spatial.h"
#include "spr_util.h"

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

spr_result spr__morton_order(const spr_cloud *c, const spr_bounds *b, uint32_t *order, spr_error *err)
{
    const size_t n = c->n;
    double ext = 0.0;
    for (int a = 0; a < 3; a++)
        if (b->hi[a] - b->lo[a] > ext) ext = b->hi[a] - b->lo[a];
    const double scale = ext > 0.0 ? 1024.0 / ext : 0.0;
    uint64_t *key = spr__big_alloc((n ? n : 1) * sizeof *key);
    if (!key) return spr__fail(err, SPR_E_NOMEM, "spatial order: out of memory for %zu splats", n);
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
    const int bad = spr__radix_sort_u64(key, order, n); /* stable: ties keep submission order */
    free(key);
    return bad ? spr__fail(err, SPR_E_NOMEM, "spatial order: out of memory sorting %zu splats", n) : SPR_OK;
}

spr_result spr__spatial_make(const spr_cloud *c, const spr_bounds *b, int threads, spr__spatial *s, spr_error *err)
{
    memset(s, 0, sizeof *s);
    const size_t n = c->n, m = n ? n : 1;
    s->c.n = n;
    s->c.pos = spr__big_alloc(3 * m * sizeof(float));
    s->c.nrm = spr__big_alloc(3 * m * sizeof(float));
    s->c.radius = spr__big_alloc(m * sizeof(float));
    s->order = spr__big_alloc(m * sizeof *s->order);
    s->rank = spr__big_alloc(m * sizeof *s->rank);
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
