/* spr_envmap.h — environment cube maps (SPEC §6.3): built in or read from
 * six faces.  The layout is spr_envmap's in spr_backend.h. */
#ifndef SPR_ENVMAP_H
#define SPR_ENVMAP_H

#include "spr_backend.h"

/* "sky" (gradient sky with a sun over a checkered ground) or "checker"
 * (an 8×8 checkerboard per face, one tint per face), size texels a side. */
spr_result spr_envmap_builtin(const char *name, int size, spr_envmap *out, spr_error *err);
/* DIR/px.png, nx.png, py.png, ny.png, pz.png, nz.png: square, one size,
 * each seen from the cube's centre as GL's cube map faces are. */
spr_result spr_envmap_load(const char *dir, spr_envmap *out, spr_error *err);
void spr_envmap_free(spr_envmap *e);

#endif
