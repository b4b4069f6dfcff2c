/* sw_fixed.h — the CPU backend's targets as the fixed-function stages of
 * core/render/spr_fixed.h address them. */
#ifndef SW_FIXED_H
#define SW_FIXED_H

#include "sw_internal.h"
#include "spr_fixed.h"

static inline spr_fixed_planes sw_fixed_planes(sw_target *tg)
{
    spr_fixed_planes p = {SW_F(tg, COLOR), SW_F(tg, DEPTH), SW_F(tg, TEST), SW_F(tg, OPACITY), SW_F(tg, NORMAL), SW_U(tg, ID), SW_U(tg, COUNT)};
    return p;
}

#endif
