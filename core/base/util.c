/* util.c — monotonic clock, atomic file writes and the binary heap of spr_util.h. */
#include "spr_util.h"

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
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
