/* util.c — monotonic clock, atomic file writes and the binary heap of spr_util.h. */
#include "spr_util.h"

#include <math.h>

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <string.h>
#include <unistd.h>
#include <time.h>

double spr_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

spr_result spr__write_atomic(const char *path, spr__writer_fn fn, const void *user, spr_error *err)
{
    size_t l = strlen(path);
    char *tmp = malloc(l + 16);
    if (!tmp) return spr__fail(err, SPR_E_NOMEM, "%s: out of memory", path);
    snprintf(tmp, l + 16, "%s.tmp%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        spr_result r = spr__fail(err, SPR_E_IO, "%s: cannot create: %s", path, strerror(errno));
        free(tmp);
        return r;
    }
    int bad = fn(f, user) != 0;
    bad |= fflush(f) != 0;
    bad |= fclose(f) != 0;
    if (bad || rename(tmp, path) != 0) {
        int e = errno;
        remove(tmp);
        free(tmp);
        return spr__fail(err, SPR_E_IO, "%s: write failed: %s", path, strerror(e));
    }
    free(tmp);
    return SPR_OK;
}

static int first(const spr__heap *h, const spr__heap_item *x, const spr__heap_item *y)
{
    if (x->key != y->key) return h->max ? x->key > y->key : x->key < y->key;
    return x->id < y->id;
}

int spr__heap_push(spr__heap *h, spr__heap_item it)
{
    if (h->n == h->cap) {
        size_t cap = h->cap ? 2 * h->cap : 1024;
        spr__heap_item *na = realloc(h->a, cap * sizeof *na);
        if (!na) return -1;
        h->a = na;
        h->cap = cap;
    }
    size_t i = h->n++;
    h->a[i] = it;
    while (i && first(h, &h->a[i], &h->a[(i - 1) / 2])) {
        spr__heap_item t = h->a[i];
        h->a[i] = h->a[(i - 1) / 2];
        h->a[(i - 1) / 2] = t;
        i = (i - 1) / 2;
    }
    return 0;
}

spr__heap_item spr__heap_pop(spr__heap *h)
{
    spr__heap_item top = h->a[0];
    h->a[0] = h->a[--h->n];
    size_t i = 0;
    for (;;) {
        size_t l = 2 * i + 1, r = l + 1, m = i;
        if (l < h->n && first(h, &h->a[l], &h->a[m])) m = l;
        if (r < h->n && first(h, &h->a[r], &h->a[m])) m = r;
        if (m == i) break;
        spr__heap_item t = h->a[i];
        h->a[i] = h->a[m];
        h->a[m] = t;
        i = m;
    }
    return top;
}

void spr__heap_free(spr__heap *h)
{
    free(h->a);
    h->a = NULL;
    h->n = h->cap = 0;
}

void spr_warn_report(const spr_warn *w, const char *fmt, ...)
{
    if (!w || !w->fn) return;
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    w->fn(w->user, msg);
}

void spr__quat_of_columns(const double a[3], const double b[3], const double c[3], double q[4])
{
    const double m00 = a[0], m11 = b[1], m22 = c[2], tr = m00 + m11 + m22;
    if (tr > 0.0) { /* the largest of w, x, y, z first, for accuracy (Shepperd) */
        double s = 2.0 * sqrt(tr + 1.0);
        q[0] = 0.25 * s, q[1] = (b[2] - c[1]) / s, q[2] = (c[0] - a[2]) / s, q[3] = (a[1] - b[0]) / s;
    } else if (m00 > m11 && m00 > m22) {
        double s = 2.0 * sqrt(1.0 + m00 - m11 - m22);
        q[0] = (b[2] - c[1]) / s, q[1] = 0.25 * s, q[2] = (b[0] + a[1]) / s, q[3] = (c[0] + a[2]) / s;
    } else if (m11 > m22) {
        double s = 2.0 * sqrt(1.0 + m11 - m00 - m22);
        q[0] = (c[0] - a[2]) / s, q[1] = (b[0] + a[1]) / s, q[2] = 0.25 * s, q[3] = (c[1] + b[2]) / s;
    } else {
        double s = 2.0 * sqrt(1.0 + m22 - m00 - m11);
        q[0] = (a[1] - b[0]) / s, q[1] = (c[0] + a[2]) / s, q[2] = (c[1] + b[2]) / s, q[3] = 0.25 * s;
    }
    const double l = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; k++) q[k] /= l;
}

void *spr__big_alloc(size_t bytes)
{
    const size_t huge = (size_t)2 << 20;
    if (bytes < huge) return malloc(bytes ? bytes : 1);
    const size_t n = (bytes + huge - 1) / huge * huge;
    void *p = NULL;
    if (posix_memalign(&p, huge, n)) return NULL;
#ifdef MADV_HUGEPAGE
    madvise(p, n, MADV_HUGEPAGE); /* advice only: without THP the buffer is an ordinary one */
#endif
    return p;
}

void *spr__alloc(size_t bytes)
{
    return bytes >= ((size_t)32 << 20) ? spr__big_alloc(bytes) : malloc(bytes ? bytes : 1);
}

void *spr__big_calloc(size_t n, size_t size)
{
    if (size && n > SIZE_MAX / size) return NULL;
    void *p = spr__big_alloc(n * size);
    if (p) memset(p, 0, n * size); /* a reused block is not zero */
    return p;
}

/* Stable LSD radix sort of n (key, value) pairs by key, ascending, 11 bits a
 * pass; a pass whose digit is the same for every key is skipped (a frame's
 * distances share their sign and most of their exponent; 30-bit Morton codes
 * take three passes). */
int spr__radix_sort_u64(uint64_t *key, uint32_t *val, size_t n)
{
    uint64_t *k2 = spr__big_alloc(n * sizeof *k2);
    uint32_t *v2 = spr__big_alloc(n * sizeof *v2);
    if (!k2 || !v2) { free(k2), free(v2); return -1; }
    for (int shift = 0; shift < 64; shift += 11) {
        size_t cnt[2049] = {0};
        for (size_t i = 0; i < n; i++) cnt[(key[i] >> shift & 2047u) + 1]++;
        int single = 0;
        for (int b = 0; b < 2048; b++) single |= cnt[b + 1] == n;
        if (single) continue;
        for (int b = 0; b < 2048; b++) cnt[b + 1] += cnt[b];
        for (size_t i = 0; i < n; i++) {
            const size_t at = cnt[key[i] >> shift & 2047u]++;
            k2[at] = key[i], v2[at] = val[i];
        }
        memcpy(key, k2, n * sizeof *key);
        memcpy(val, v2, n * sizeof *val);
    }
    free(k2), free(v2);
    return 0;
}
