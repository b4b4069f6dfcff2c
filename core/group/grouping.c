/* grouping.c — grouping as one library call (SPEC §5): a method (none, MGC,
 * WGC, hash, a groups file), then an optional extension for coverage.
 * Every caller (render, group, bench, parity, reference, the tests) goes
 * through spr_group_run, so the defaults and ε are decided once. */
#include "spr_util.h"
#include "spr_group.h"

#include <stdlib.h>
#include <string.h>

static const char *const method_names[SPR_GROUP__COUNT] = {"none", "mgc", "wgc", "hash", "file"};
static const char *const extend_names[SPR_EXTEND__COUNT] = {"none", "dup", "radius", "hash-radius"};

int spr_group_method_from_name(const char *name)
{
    for (int m = 0; m < SPR_GROUP__COUNT; m++)
        if (!strcmp(name, method_names[m])) return m;
    return -1;
}
const char *spr_group_method_name(spr_group_method m) { return (unsigned)m < SPR_GROUP__COUNT ? method_names[m] : "?"; }
int spr_group_extend_from_name(const char *name)
{
    for (int e = 0; e < SPR_EXTEND__COUNT; e++)
        if (!strcmp(name, extend_names[e])) return e;
    return -1;
}

void spr_grouping_defaults(spr_grouping_desc *d)
{
    memset(d, 0, sizeof *d);
    d->method = SPR_GROUP_MGC;
    spr_mgc_defaults(&d->mgc);
    spr_wgc_defaults(&d->wgc);
    spr_hash_defaults(&d->hash);
    spr_extend_defaults(&d->ext);
}

void spr_grouping_free(spr_grouping *g)
{
    spr_groups_free(&g->groups);
    spr_overlap_graph_free(&g->graph);
    free(g->labels);
    memset(g, 0, sizeof *g);
}

spr_result spr_group_run(const spr_cloud *c, const spr_grouping_desc *d, spr_grouping *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    size_t n = c->n;
    if ((unsigned)d->method >= SPR_GROUP__COUNT || (unsigned)d->extend >= SPR_EXTEND__COUNT)
        return spr__fail(err, SPR_E_ARG, "groups: unknown method %d or extension %d", (int)d->method, (int)d->extend);
    if (!(out->labels = malloc((n ? n : 1) * sizeof(int32_t)))) return spr__fail(err, SPR_E_NOMEM, "groups: out of memory");
    spr_result r = SPR_OK;
    double t0 = spr_now_ms();
    switch (d->method) {
    case SPR_GROUP_NONE:
        memset(out->labels, 0, n * sizeof(int32_t));
        out->stats.K = 1;
        break;
    case SPR_GROUP_MGC: {
        spr_mgc_desc m = d->mgc;
        m.threads = d->threads;
        m.progress = d->progress;
        r = spr_group_mgc(c, &m, out->labels, &out->stats, err);
        break;
    }
    case SPR_GROUP_WGC: {
        spr_wgc_desc w = d->wgc;
        w.threads = d->threads;
        w.progress = d->progress;
        w.graph_out = d->keep_graph ? &out->graph : NULL;
        r = spr_group_wgc(c, &w, out->labels, &out->stats, err);
        break;
    }
    case SPR_GROUP_HASH: {
        spr_hash_desc h = d->hash;
        h.threads = d->threads;
        h.progress = d->progress;
        r = spr_group_hash(c, &h, out->labels, &out->stats, err);
        break;
    }
    case SPR_GROUP_FILE:
        if (!d->file) r = spr__fail(err, SPR_E_ARG, "groups: no groups file named");
        else r = spr_groups_read_any(d->file, n, &out->groups, out->labels, err);
        if (!r) out->stats.K = out->groups.K;
        break;
    default: break;
    }
    out->ms_grouping = spr_now_ms() - t0;
    if (r) { spr_grouping_free(out); return r; }
    t0 = spr_now_ms();
    spr_extend_desc ed = d->ext;
    ed.threads = d->threads;
    ed.progress = d->progress;
    if (d->method == SPR_GROUP_FILE) {
        if (d->extend != SPR_EXTEND_NONE) r = spr__fail(err, SPR_E_ARG, "groups: a groups file cannot be extended");
    } else if (d->extend == SPR_EXTEND_DUP) {
        r = spr_group_duplicate(c, out->labels, out->stats.K, &ed, &out->groups, &out->dup_ratio, err);
    } else {
        r = spr_groups_from_labels(out->labels, n, out->stats.K, &out->groups, err);
        if (!r && d->extend == SPR_EXTEND_RADIUS) r = spr_group_enlarge(c, &out->groups, &ed, &out->capped_groups, err);
        if (!r && d->extend == SPR_EXTEND_HASH_RADIUS) {
            /* [ZP] §4.4.2's fast approximation: the lattice circumradius, √50/4 for K = 8 */
            out->groups.radius_scale = malloc((size_t)out->groups.K * sizeof(float));
            if (!out->groups.radius_scale) r = spr__fail(err, SPR_E_NOMEM, "groups: out of memory");
            for (int k = 0; !r && k < out->groups.K; k++) out->groups.radius_scale[k] = (float)spr_hash_enlarge_factor(out->groups.K);
        }
    }
    out->ms_extend = d->extend != SPR_EXTEND_NONE ? spr_now_ms() - t0 : 0.0;
    if (r) spr_grouping_free(out);
    return r;
}
