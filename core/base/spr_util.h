/* spr_util.h — small shared helpers: a monotonic clock, progress reports of
 * long operations, writing a file through a temporary name, and the binary
 * heap behind the priority queues of WGC and duplication. */
#ifndef SPR_UTIL_H
#define SPR_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "spr_result.h"

/* Milliseconds on the monotonic clock. */
double spr_now_ms(void);

/* Progress callback used by long operations: done/total, a phase name. */
typedef void (*spr_progress_fn)(void *user, const char *phase, size_t done, size_t total);
typedef struct spr_progress { spr_progress_fn fn; void *user; } spr_progress;
static inline void spr_progress_report(const spr_progress *p, const char *phase, size_t done, size_t total)
{
    if (p && p->fn) p->fn(p->user, phase, done, total);
}

/* Write through a temporary name: open PATH.tmpPID, let `fn` write, rename
 * into place; on any failure nothing is left at either name. */
typedef int (*spr__writer_fn)(FILE *f, const void *user);
spr_result spr__write_atomic(const char *path, spr__writer_fn fn, const void *user, spr_error *err);

/* Binary heap of (key, id, ver).  max = 1: largest key first; max = 0:
 * smallest first; equal keys: smaller id first (a total order, so pops are
 * deterministic).  ver lets callers skip superseded entries (lazy updates). */
typedef struct spr__heap_item { double key; uint32_t id, ver; } spr__heap_item;
typedef struct spr__heap { spr__heap_item *a; size_t n, cap; int max; } spr__heap;
int spr__heap_push(spr__heap *h, spr__heap_item it); /* 0, or −1 out of memory */
spr__heap_item spr__heap_pop(spr__heap *h);          /* h->n > 0 */
void spr__heap_free(spr__heap *h);

#endif
