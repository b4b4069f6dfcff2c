/* spr_trace.h — the trace backend: any backend, with every call written down.
 *
 * spr_trace_create() wraps a backend and forwards every call to it,
 * writing one line per call to `out`: views, targets and their planes,
 * clears, each draw's full pass state and fragment counts, each composite
 * op with its inputs, each read — the step-by-step record of SPEC §8 as a
 * sequence of backend calls (in the manner of apitrace).  Output planes
 * are the inner backend's, bit for bit.
 */
#ifndef SPR_TRACE_H
#define SPR_TRACE_H

#include <stdio.h>
#include "spr_backend.h"

/* A backend forwarding to `inner` (owned: destroyed with the trace backend)
 * and writing its calls to `out` (not owned); NULL on out of memory. */
spr_backend *spr_trace_create(spr_backend *inner, FILE *out, spr_error *err);

#endif
