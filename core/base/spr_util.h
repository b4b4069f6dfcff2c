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

/* Warnings of readers that accept a file with a deviation (a header line
 * outside the grammar, normals that are all zero): one line each, naming
 * the file and the position; fn NULL: dropped. */
typedef void (*spr_warn_fn)(void *user, const char *msg);
typedef struct spr_warn { spr_warn_fn fn; void *user; } spr_warn;
void spr_warn_report(const spr_warn *w, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Write through a temporary name: open PATH.tmpPID, let `fn` write, rename
 * into place; on any failure nothing is left at either name. */
typedef int (*spr__writer_fn)(FILE *f, const void *user);
spr_result spr__write_atomic(const char *path, spr__writer_fn fn, const void *user, spr_error *err);

/* splitmix64: a small, well-known generator, the same bits everywhere
 * (mesh resampling, generated test scenes). */
/* The unit quaternion (w x y z) of the rotation whose columns are a, b, c (an orthonormal, right-handed frame), in double. */
void spr__quat_of_columns(const double a[3], const double b[3], const double c[3], double q[4]);
/* malloc for frame-sized buffers: from 2 MiB on, 2 MiB-aligned and marked
 * for transparent huge pages (madvise), so that first touching it takes one
 * page fault per 2 MiB instead of per 4 KiB (where the kernel's THP is
 * "madvise", Debian's default); freed with free(). */
void *spr__big_alloc(size_t bytes);
/* The same for n zeroed elements of size bytes (calloc's arguments). */
void *spr__big_calloc(size_t n, size_t size);
/* For per-call working arrays: spr__big_alloc from 32 MiB on (glibc's
 * largest mmap threshold, where it maps fresh pages anyway), else malloc,
 * whose reuse of a freed block a call repeated every frame gains more from. */
void *spr__alloc(size_t bytes);
/* Stable LSD radix sort of n (key, val) pairs by key, ascending (ties keep
 * their order); 0, or −1 when out of memory. */
int spr__radix_sort_u64(uint64_t *key, uint32_t *val, size_t n);

static inline uint64_t spr__splitmix64(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
/* Uniform in [0, 1) with 53 random bits. */
static inline double spr__uniform01(uint64_t *s) { return (double)(spr__splitmix64(s) >> 11) * 0x1.0p-53; }

/* Binary heap of (key, id, ver).  max = 1: largest key first; max = 0:
 * smallest first; equal keys: smaller id first (a total order, so pops are
 * deterministic).  ver lets callers skip superseded entries (lazy updates). */
typedef struct spr__heap_item { double key; uint32_t id, ver; } spr__heap_item;
typedef struct spr__heap { spr__heap_item *a; size_t n, cap; int max; } spr__heap;
int spr__heap_push(spr__heap *h, spr__heap_item it); /* 0, or −1 out of memory */
spr__heap_item spr__heap_pop(spr__heap *h);          /* h->n > 0 */
void spr__heap_free(spr__heap *h);

#endif
