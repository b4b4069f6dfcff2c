/* cli_domains.c — `splatref domains`: the multi-scale soft decomposition of
 * a model (SPEC §7.1–7.4), its levels with their domains and support
 * rectangles, and files that let a reader or another tool check them. */
#include "spr_util.h"
#include "cli.h"
#include "cli_scene_opts.h"
#include "spr_domain.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const cli_opt domains_opts[] = {
    CLI_MODEL_OPTS,
    {"level", "L", "the level (0 = coarsest) for --basis-out and --dump; --stats prints every level"},
    {"domain", "HOW", "thresholded (phi >= --threshold, default) | strict (largest phi)"},
    {"threshold", "K", "thresholded domains: phi >= K (default 0.01)"},
    {"k", "K", "neighbours of the local analysis and of the coupling graph (default 10)"},
    {"delta", "D", "coupling 1/(D + max sigma) (default 0.01)"},
    {"normal-power", "P", "coupling times |n_j.n_k|^P: weak across creases (default 4; 0: sigma alone)"},
    {"omega", "W", "prolongation smoothing in [0,1): how much the basis functions overlap (default 0.5)"},
    {"enlarge", "E", "support rectangles grown by E about their centre (default 0.05)"},
    {"texture", "HOW", "radial (default) | affine: qhull Delaunay, barycentric inside, radial elsewhere ([R] 3.3.3)"},
    {"rbf", "SHAPE", "radial texture basis: constant | linear (default) | gauss ([R] 3.3.2)"},
    {"width", "W", "radial support W x the point radius (default 1)"},
    {"texel", "T", "texel side T x the domain's mean radius (default 1)"},
    {"normalize", "WHEN", "gt0: where f > 0 (Eq. 3.4, default) | ge1: where f >= 1 (Eq. 3.3)"},
    {"extend-color", NULL, "texels no point reaches take the nearest point's colour ([R] 3.3.4)"},
    {"merge", "FLAT,DOT", "merge overlapping domains flatter than FLAT whose normals' dot exceeds DOT ([R] 3.4), e.g. 0.05,0.9"},
    {"stats", NULL, "print [R] Table 5.2's columns built so far, one row per level"},
    {"basis-out", "F", "one line per point of --level, in input order: x y z strict_domain j:phi ... (phi > 0)"},
    {"dump", "F.ply", "the strict domains of --level as a colour-coded point cloud"},
    {NULL, NULL, NULL}};

typedef struct basis_file { const spr_cloud *c; const spr_csr *B; const int32_t *strict; } basis_file;

static int write_basis(FILE *f, const void *user)
{
    const basis_file *bf = user;
    for (size_t i = 0; i < bf->B->rows; i++) {
        const float *p = bf->c->pos + 3 * i;
        fprintf(f, "%.9g %.9g %.9g %d", p[0], p[1], p[2], bf->strict[i]);
        for (size_t q = bf->B->ptr[i]; q < bf->B->ptr[i + 1]; q++)
            if (bf->B->val[q] > 0.0) fprintf(f, " %u:%.9g", bf->B->col[q], bf->B->val[q]);
        if (fputc('\n', f) == EOF) return -1;
    }
    return 0;
}

/* A colour per region: well spread hues from a hash of its number. */
static void region_color(int32_t j, float rgb[3])
{
    uint64_t s = (uint64_t)(uint32_t)j * 0x9E3779B97F4A7C15ull + 1;
    for (int k = 0; k < 3; k++) rgb[k] = 0.15f + 0.8f * (float)((spr__splitmix64(&s) >> 40) & 0xffff) / 65535.0f;
}

/* Polygons of one level: one per domain with at least 3 points. */
static int level_polygons(const spr_cloud *c, const spr_csr *B, int strict, double K, double enlarge, const spr_texture_desc *td, int affine,
                          size_t *npoly, double *err_mean, double *errn_mean, double *pts_mean, size_t *texels, spr_error *err)
{
    spr_csr T;
    if (spr_domain_members(B, strict, K, &T, err)) return -1;
    *npoly = 0;
    *texels = 0;
    double e = 0.0, en = 0.0, pts = 0.0;
    for (size_t j = 0; j < T.rows; j++) {
        const size_t m = T.ptr[j + 1] - T.ptr[j];
        if (m < 3) continue;
        spr_polygon pg;
        if (spr_support_polygon(c, T.col + T.ptr[j], T.val + T.ptr[j], m, enlarge, 1, &pg, err)) continue;
        (*npoly)++;
        e += pg.error, en += pg.error_norm, pts += (double)m;
        spr_texture tex;
        size_t ntri;
        if (affine ? spr_texture_affine(c, T.col + T.ptr[j], T.val + T.ptr[j], m, &pg, td, &tex, &ntri, err)
                   : spr_texture_radial(c, T.col + T.ptr[j], T.val + T.ptr[j], m, &pg, td, &tex, err)) {
            spr_csr_free(&T);
            return -1;
        }
        *texels += (size_t)tex.w * (size_t)tex.h;
        spr_texture_free(&tex);
    }
    *err_mean = *npoly ? e / (double)*npoly : 0.0;
    *errn_mean = *npoly ? en / (double)*npoly : 0.0;
    *pts_mean = *npoly ? pts / (double)*npoly : 0.0;
    spr_csr_free(&T);
    return 0;
}

int cmd_domains(int argc, char **argv)
{
    cli_args a;
    int pr = cli_parse(&a, "domains", domains_opts, "--model M [--stats] [--level L --basis-out F --dump F.ply] [options]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    cli_scene s;
    memset(&s, 0, sizeof s);
    spr_load_desc ld;
    spr_decomp_desc dd;
    spr_decomp_defaults(&dd);
    int level = -1, rc = 2;
    double K = 0.01, enlarge = 0.05;
    spr_texture_desc td = {1.0, 1.0, SPR_RBF_LINEAR, SPR_NORM_GT0, cli_flag(&a, "extend-color")};
    const char *how = cli_get(&a, "domain"), *basis_out = cli_get(&a, "basis-out"), *dump = cli_get(&a, "dump");
    const char *rbf = cli_get(&a, "rbf"), *norm = cli_get(&a, "normalize"), *merge = cli_get(&a, "merge"), *texture = cli_get(&a, "texture");
    if (texture && strcmp(texture, "radial") && strcmp(texture, "affine")) { cli_error(&a, "--texture: '%s' is not radial or affine", texture); return 2; }
    const int affine = texture && !strcmp(texture, "affine");
    double mflat = 0.0, mdot = 0.0;
    char mtail;
    if (merge && (sscanf(merge, "%lf,%lf%c", &mflat, &mdot, &mtail) != 2 || !(mflat >= 0.0 && mflat <= 1.0) || !(mdot >= -1.0 && mdot <= 1.0))) {
        cli_error(&a, "--merge: '%s' is not FLAT,DOT with FLAT in [0,1] and DOT in [-1,1]", merge);
        return 2;
    }
    const int stats = cli_flag(&a, "stats");
    if (cli_model_opts(&a, &s, &ld) || cli_get_int(&a, "level", &level, 0, 1000) < 0 || cli_get_double(&a, "threshold", &K, 1e-12, 1.0) < 0 ||
        cli_get_int(&a, "k", &dd.k, 3, 256) < 0 || cli_get_double(&a, "delta", &dd.delta, 1e-12, 1e12) < 0 ||
        cli_get_double(&a, "normal-power", &dd.normal_power, 0.0, 64.0) < 0 || cli_get_double(&a, "omega", &dd.omega, 0.0, 0.999) < 0 ||
        cli_get_double(&a, "enlarge", &enlarge, 0.0, 10.0) < 0 || cli_get_double(&a, "width", &td.width, 1e-3, 100.0) < 0 ||
        cli_get_double(&a, "texel", &td.texel_factor, 1e-3, 100.0) < 0 || (cli_flag(&a, "quiet"), cli_reject_unused(&a)))
        return 2;
    if (rbf && strcmp(rbf, "constant") && strcmp(rbf, "linear") && strcmp(rbf, "gauss")) { cli_error(&a, "--rbf: '%s' is not constant, linear or gauss", rbf); return 2; }
    if (rbf) td.shape = !strcmp(rbf, "constant") ? SPR_RBF_CONSTANT : !strcmp(rbf, "linear") ? SPR_RBF_LINEAR : SPR_RBF_GAUSS;
    if (norm && strcmp(norm, "gt0") && strcmp(norm, "ge1")) { cli_error(&a, "--normalize: '%s' is not gt0 or ge1", norm); return 2; }
    if (norm) td.normalize = !strcmp(norm, "ge1") ? SPR_NORM_GE1 : SPR_NORM_GT0;
    if (how && strcmp(how, "thresholded") && strcmp(how, "strict")) { cli_error(&a, "--domain: '%s' is not thresholded or strict", how); return 2; }
    if ((basis_out || dump) && level < 0) { cli_error(&a, "--basis-out and --dump need --level"); return 2; }
    if (!stats && !basis_out && !dump) { cli_error(&a, "nothing to do: give --stats, --basis-out or --dump"); return 2; }
    const int strict = how && !strcmp(how, "strict");
    dd.threads = s.threads;
    dd.progress = ld.progress;
    spr_error err = {0};
    spr_decomp dc = {0};
    int32_t *dom = NULL;
    size_t *merged_from = NULL;
    if (cli_load_model(&a, &s, &ld)) goto done;
    double t0 = spr_now_ms();
    if (spr_decompose(&s.cloud, &dd, &dc, &err)) { fprintf(stderr, "splatref domains: %s: %s\n", s.model, err.msg); goto done; }
    const double ms_decomp = spr_now_ms() - t0;
    if (level >= dc.levels) { cli_error(&a, "--level %d: the decomposition has levels 0..%d", level, dc.levels - 1); goto done; }
    merged_from = calloc((size_t)dc.levels, sizeof *merged_from);
    if (!merged_from) { cli_error(&a, "out of memory"); goto done; }
    for (int l = 0; merge && l < dc.levels; l++) { /* every level's basis replaced by its merged one */
        spr_csr M;
        size_t merges;
        if (spr_domain_merge(&s.cloud, &dc.basis[l], K, mflat, mdot, &M, &merges, &err)) {
            fprintf(stderr, "splatref domains: %s\n", err.msg);
            goto done;
        }
        merged_from[l] = dc.regions[l];
        spr_csr_free(&dc.basis[l]);
        dc.basis[l] = M;
        dc.regions[l] = M.cols;
    }
    printf("domains: %s, %zu points, %d levels (local analysis %.0f ms, coarsening and basis %.0f ms, all %.0f ms)\n", s.model, s.cloud.n,
           dc.levels, dc.ms_analysis, dc.ms_coarsen, ms_decomp);
    if (stats) {
        if (merge) printf("  (merged at flatness < %g and normal dot > %g: regions before merging in brackets)\n", mflat, mdot);
        printf("  %5s %8s %9s %12s %12s %12s %10s %12s %9s\n", "level", "regions", "polygons", "points/poly", "error", "norm. error", "texels",
               "tex. bytes", "ms");
        for (int l = 0; l < dc.levels; l++) {
            size_t np, texels;
            double e, en, pts;
            double t1 = spr_now_ms();
            if (level_polygons(&s.cloud, &dc.basis[l], strict, K, enlarge, &td, affine, &np, &e, &en, &pts, &texels, &err)) {
                fprintf(stderr, "splatref domains: level %d: %s\n", l, err.msg[0] ? err.msg : "out of memory");
                goto done;
            }
            char reg[48];
            if (merge) snprintf(reg, sizeof reg, "%zu(%zu)", dc.regions[l], merged_from[l]);
            else snprintf(reg, sizeof reg, "%zu", dc.regions[l]);
            printf("  %5d %8s %9zu %12.1f %12.4g %12.4g %10zu %12zu %9.1f\n", l, reg, np, pts, e, en, texels, 4 * texels,
                   spr_now_ms() - t1);
        }
        printf("  (%s domains%s; error: mean distance point-projection per polygon, normalised by the mean radius;\n"
               "   %s%s textures, width %g, texel %g x mean radius, normalised where %s, RGBA 8-bit bytes;\n"
               "   primitives per pixel and render times come with the rendering stage; ms: polygons and textures)\n",
               strict ? "strict" : "thresholded", strict ? "" : " at phi >= K", affine ? "affine (radial where no triangle) + radial " : "radial ",
               td.shape == SPR_RBF_CONSTANT ? "constant" : td.shape == SPR_RBF_LINEAR ? "linear" : "gauss", td.width, td.texel_factor,
               td.normalize == SPR_NORM_GE1 ? "f >= 1" : "f > 0");
    }
    if (basis_out || dump) {
        const spr_csr *B = &dc.basis[level];
        dom = malloc(s.cloud.n * sizeof *dom);
        if (!dom) { cli_error(&a, "out of memory"); goto done; }
        spr_domain_strict(B, dom);
        if (basis_out) {
            basis_file bf = {&s.cloud, B, dom};
            if (spr__write_atomic(basis_out, write_basis, &bf, &err)) { fprintf(stderr, "splatref domains: %s\n", err.msg); goto done; }
            printf("domains: level %d basis (%zu regions) -> %s\n", level, dc.regions[level], basis_out);
        }
        if (dump) {
            for (size_t i = 0; i < s.cloud.n; i++) region_color(dom[i], s.cloud.color + 3 * i);
            if (spr_write_ply(dump, &s.cloud, &err)) { fprintf(stderr, "splatref domains: %s\n", err.msg); goto done; }
            printf("domains: level %d strict domains, coloured -> %s\n", level, dump);
        }
    }
    rc = 0;
done:
    free(dom);
    free(merged_from);
    spr_decomp_free(&dc);
    cli_scene_free(&s);
    return rc;
}
