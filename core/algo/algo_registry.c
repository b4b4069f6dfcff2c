/* algo_registry.c — the table of algorithms (SPR_ALGO_LIST in spr_algo.h). */
#include "spr_algo.h"

#include <stdio.h>
#include <string.h>

static const spr_algo_info algos[SPR_ALGO__COUNT] = {
#define SPR__ALGO_ROW(e, fn, name, uses, spec, summary) {name, uses, spec, summary, spr__algo_##fn},
    SPR_ALGO_LIST(SPR__ALGO_ROW)
#undef SPR__ALGO_ROW
};

const spr_algo_info *spr_algo_info_of(spr_algo a) { return (unsigned)a < SPR_ALGO__COUNT ? &algos[a] : NULL; }
const char *spr_algo_name(spr_algo a) { return (unsigned)a < SPR_ALGO__COUNT ? algos[a].name : "?"; }

int spr_algo_from_name(const char *name)
{
    for (int a = 0; a < SPR_ALGO__COUNT; a++)
        if (!strcmp(name, algos[a].name)) return a;
    return -1;
}

const char *spr_algo_names(const char *sep)
{
    static char buf[256];
    size_t o = 0;
    buf[0] = 0;
    for (int a = 0; a < SPR_ALGO__COUNT && o < sizeof buf; a++)
        o += (size_t)snprintf(buf + o, sizeof buf - o, "%s%s", a ? sep : "", algos[a].name);
    return buf;
}
