/* spr_swrast.h — the CPU reference backend.
 *
 * Tile-parallel (OpenMP) software rasterizer implementing spr_backend with
 * the float sequence of core/spr_fragment.h.  Splats are binned to 32×32
 * tiles in submission order and each tile runs its list in that order, so
 * every pixel sees its fragments in submission order and the output is
 * bit-identical for any thread count.  Threads run with FTZ/DAZ set, as
 * llvmpipe's rasterizer threads do (PARITY.md rule 6).
 */
#ifndef SPR_SWRAST_H
#define SPR_SWRAST_H

#include "spr_backend.h"

/* New CPU backend using `threads` OpenMP threads (0 = all cores); NULL and
 * err filled on failure.  Release with spr_backend_destroy(). */
spr_backend *spr_swrast_create(int threads, spr_error *err);

/* Draw disk splats pixel by pixel (on != 0) instead of eight pixels of a
 * row at once (the default): the same operations in the same order, so the
 * same bits; kept to check the vector path against (test raster). */
void spr_swrast_scalar(spr_backend *b, int on);

#endif
