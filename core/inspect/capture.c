/* capture.c — every plane of every pass of a frame kept in memory (the
 * pass hook of spr_capture_hook): what parity compares against and what
 * `splatref step` shows. */
#include "spr_algo.h"

#include <stdlib.h>
#include <string.h>

void spr_capture_hook(void *user, spr_backend *b, const spr_pass_info *info)
{
    spr_capture *cp = user;
    if (cp->failed) return;
    if (cp->n == cp->cap) {
        int cap = cp->cap ? 2 * cp->cap : 8;
        spr_captured_pass *np = realloc(cp->passes, (size_t)cap * sizeof *np);
        if (!np) { cp->failed = 1; snprintf(cp->err.msg, sizeof cp->err.msg, "capture: out of memory"); return; }
        cp->passes = np;
        cp->cap = cap;
    }
    spr_captured_pass *p = &cp->passes[cp->n++];
    memset(p, 0, sizeof *p);
    snprintf(p->name, sizeof p->name, "%s", info->name);
    p->index = info->index;
    p->group = info->group;
    p->target = info->target;
    p->composite = info->state == NULL;
    if (info->state) p->state = *info->state;
    p->stats = info->stats;
    p->ms = info->ms;
    const size_t np = (size_t)b->view.width * b->view.height;
    if (info->records) { /* a Gaussian preprocessing pass: its records */
        const size_t bytes = info->n_records * SPR_GREC_FLOATS * sizeof(float);
        if (!(p->records = malloc(bytes ? bytes : 1))) { cp->failed = 1; snprintf(cp->err.msg, sizeof cp->err.msg, "capture: out of memory"); return; }
        memcpy(p->records, info->records, bytes);
        p->n_records = info->n_records;
    }
    p->planes = spr_backend_target_planes(b, info->target);
    for (int k = 0; k < SPR_PLANE__COUNT && !cp->failed; k++) {
        if (!(p->planes & SPR_PLANE_BIT(k))) continue;
        p->plane[k] = malloc(np * (size_t)spr_plane_channels((spr_plane)k) * 4);
        spr_result r = !p->plane[k] ? SPR_E_NOMEM
                       : cp->as_float ? spr_backend_read_plane_f(b, info->target, (spr_plane)k, p->plane[k])
                                      : spr_backend_read_plane(b, info->target, (spr_plane)k, p->plane[k]);
        if (r) {
            cp->failed = 1;
            if (p->plane[k]) cp->err = b->err;
            else snprintf(cp->err.msg, sizeof cp->err.msg, "capture: out of memory");
        }
    }
}

void spr_capture_free(spr_capture *cp)
{
    for (int i = 0; i < cp->n; i++)
    {
        for (int k = 0; k < SPR_PLANE__COUNT; k++) free(cp->passes[i].plane[k]);
        free(cp->passes[i].records);
    }
    free(cp->passes);
    memset(cp, 0, sizeof *cp);
}
