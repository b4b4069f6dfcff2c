/* spr_util.h — small shared helpers: a monotonic clock and the binary heap
 * behind the priority queues of WGC and duplication. */
#ifndef SPR_UTIL_H
#define SPR_UTIL_H

#include <stddef.h>
#include <stdint.h>

/* Milliseconds on the monotonic clock. */
double spr_now_ms(void);

/* Binary heap of (key, id, ver).  max = 1: largest key first; max = 0:
 * smallest first; equal keys: smaller id first (a total order, so pops are
 * deterministic).  ver lets callers skip superseded entries (lazy updates). */
typedef struct spr__heap_item { double key; uint32_t id, ver; } spr__heap_item;
typedef struct spr__heap { spr__heap_item *a; size_t n, cap; int max; } spr__heap;
int spr__heap_push(spr__heap *h, spr__heap_item it); /* 0, or −1 out of memory */
spr__heap_item spr__heap_pop(spr__heap *h);          /* h->n > 0 */
void spr__heap_free(spr__heap *h);

#endif
