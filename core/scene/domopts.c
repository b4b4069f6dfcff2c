/* cli_domopts.c — the options of the domain pipeline (SPEC §7.1–7.6),
 * shared by `domains` and by the domain-* algorithms of render, parity,
 * reference and bench: read them once, decompose, merge, build the
 * primitives of one level. */
#include "spr_util.h"
#include "spr__options.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int spr__domain_opts(spr__args *a, spr_scene_domain *o)
{
    memset(o, 0, sizeof *o);
    spr_decomp_defaults(&o->dd);
    spr_prims_defaults(&o->pd);
    o->level = -1;
    const char *how = spr__get(a, "domain"), *rbf = spr__get(a, "rbf"), *norm = spr__get(a, "normalize"), *merge = spr__get(a, "merge");
    const char *texture = spr__get(a, "texture");
    if (texture && strcmp(texture, "radial") && strcmp(texture, "affine")) { spr__error(a, "--texture: '%s' is not radial or affine", texture); return -1; }
    o->pd.affine = texture && !strcmp(texture, "affine");
    char mtail;
    if (merge && (sscanf(merge, "%lf,%lf%c", &o->mflat, &o->mdot, &mtail) != 2 || !(o->mflat >= 0.0 && o->mflat <= 1.0) ||
                  !(o->mdot >= -1.0 && o->mdot <= 1.0))) {
        spr__error(a, "--merge: '%s' is not FLAT,DOT with FLAT in [0,1] and DOT in [-1,1]", merge);
        return -1;
    }
    o->merge = merge != NULL;
    o->pd.tex.extend_color = spr__flag(a, "extend-color");
    if (spr__get_int(a, "level", &o->level, 0, 1000) < 0 || spr__get_double(a, "threshold", &o->pd.K, 1e-12, 1.0) < 0 ||
        spr__get_int(a, "knn", &o->dd.k, 3, 256) < 0 || spr__get_double(a, "delta", &o->dd.delta, 1e-12, 1e12) < 0 ||
        spr__get_double(a, "normal-power", &o->dd.normal_power, 0.0, 64.0) < 0 || spr__get_double(a, "omega", &o->dd.omega, 0.0, 0.999) < 0 ||
        spr__get_double(a, "enlarge", &o->pd.enlarge, 0.0, 10.0) < 0 || spr__get_double(a, "width", &o->pd.tex.width, 1e-3, 100.0) < 0 ||
        spr__get_double(a, "texel", &o->pd.tex.texel_factor, 1e-3, 100.0) < 0 ||
        spr__get_double(a, "nbr-ratio", &o->pd.nbr_ratio, 0.0, 1.0) < 0)
        return -1;
    if (rbf && strcmp(rbf, "constant") && strcmp(rbf, "linear") && strcmp(rbf, "gauss")) { spr__error(a, "--rbf: '%s' is not constant, linear or gauss", rbf); return -1; }
    if (rbf) o->pd.tex.shape = !strcmp(rbf, "constant") ? SPR_RBF_CONSTANT : !strcmp(rbf, "linear") ? SPR_RBF_LINEAR : SPR_RBF_GAUSS;
    if (norm && strcmp(norm, "gt0") && strcmp(norm, "ge1")) { spr__error(a, "--normalize: '%s' is not gt0 or ge1", norm); return -1; }
    if (norm) o->pd.tex.normalize = !strcmp(norm, "ge1") ? SPR_NORM_GE1 : SPR_NORM_GT0;
    if (how && strcmp(how, "thresholded") && strcmp(how, "strict")) { spr__error(a, "--domain: '%s' is not thresholded or strict", how); return -1; }
    o->pd.strict = how && !strcmp(how, "strict");
    return 0;
}

int spr__domain_merge(spr__args *a, const spr_cloud *c, const spr_scene_domain *o, spr_decomp *dc, int l, size_t *before)
{
    *before = dc->regions[l];
    if (!o->merge) return 0;
    spr_error err = {0};
    spr_csr M;
    size_t merges;
    if (spr_domain_merge(c, &dc->basis[l], o->pd.K, o->mflat, o->mdot, &M, &merges, &err)) {
        spr__error(a, "%s", err.msg);
        return -1;
    }
    spr_csr_free(&dc->basis[l]);
    dc->basis[l] = M;
    dc->regions[l] = M.cols;
    return 0;
}

int spr__domain_prims(spr__args *a, const char *model, const spr_cloud *c, spr_scene_domain *o, int threads, const spr_progress *prog,
                     spr_rects *out, spr_prims_stats *st)
{
    spr_error err = {0};
    spr_decomp dc = {0};
    o->dd.threads = threads;
    if (prog) o->dd.progress = *prog;
    o->pd.threads = threads;
    double t0 = spr_now_ms();
    if (spr_decompose(c, &o->dd, &dc, &err)) { spr__error(a, "%s: %s", model, err.msg); return -1; }
    o->ms_decomp = spr_now_ms() - t0;
    int l = o->level >= 0 ? o->level : (dc.levels > 2 ? 2 : dc.levels - 1); /* default: level 2, as the figures of [R] 4 */
    if (l >= dc.levels) {
        spr__error(a, "--level %d: the decomposition of %s has levels 0..%d", l, model, dc.levels - 1);
        spr_decomp_free(&dc);
        return -1;
    }
    o->level_used = l;
    o->levels = dc.levels;
    size_t before;
    int rc = spr__domain_merge(a, c, o, &dc, l, &before);
    o->regions = dc.regions[l];
    if (!rc && spr_domain_prims(c, &dc.basis[l], &o->pd, out, st, &err)) {
        spr__error(a, "%s level %d: %s", model, l, err.msg);
        rc = -1;
    }
    spr_decomp_free(&dc);
    return rc;
}
