/* cli_domains.c — `splatref domains`: the multi-scale soft decomposition of
 * a model (SPEC §7.1–7.4), its levels with their domains and support
 * rectangles, and files that let a reader or another tool check them. */
#include "spr_util.h"
#include "cli.h"
#include "spr__scene_opts.h"
#include "spr_domain.h"
#include "spr_swrast.h"
#include "spr_image.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const spr__opt domains_opts[] = {
    SPR__MODEL_OPTS,
    SPR__DOMAIN_OPTS,
    {"stats", NULL, "print [R] Table 5.2's columns, one row per level (--level: that level only)"},
    {"basis-out", "F", "one line per point of --level, in input order: x y z strict_domain j:phi ... (phi > 0)"},
    {"dump", "F.ply", "the strict domains of --level as a colour-coded point cloud, and F.ply's textures as F-atlas.png"},
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

/* Primitives per pixel and render time of one level's primitives on the
 * CPU backend, 256×256 framing the model: the mean count of rectangles
 * covering a covered pixel (blendall's count plane), and domain-overlap's
 * milliseconds (the method [R] timed). */
static int render_stats(const spr_cloud *c, const spr_rects *rs, int threads, double *ppp, double *ms, spr_error *err)
{
    spr_camera_desc cam;
    spr_camera_defaults(&cam);
    cam.width = cam.height = 256;
    spr_bounds bd;
    spr_cloud_bounds(c, &bd);
    spr_camera_frame(&cam, &bd);
    spr_view v;
    if (spr_view_make(&cam, &v, err)) return -1;
    spr_backend *b = spr_swrast_create(threads, err);
    if (!b) return -1;
    spr_render_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.rects = rs;
    rd.sampling = SPR_SAMPLE_LINEAR;
    spr_render_result out;
    int rc = -1, t = -1;
    uint32_t *cnt = malloc((size_t)256 * 256 * sizeof *cnt);
    spr_rect_draw_desc d;
    memset(&d, 0, sizeof d);
    d.rects = rs;
    spr_pass_state_defaults(&d.state);
    d.state.depth_func = SPR_FUNC_ALWAYS;
    d.state.write_mask = SPR_WRITE_COUNT;
    if (!cnt || spr_backend_set_view(b, &v) || spr_backend_target_create(b, SPR_PLANES_OPAQUE, &t) || spr_backend_draw_rects(b, t, &d, NULL) ||
        spr_backend_read_plane(b, t, SPR_PLANE_COUNT, cnt)) {
        *err = b->err;
    } else {
        double sum = 0.0, covered = 0.0;
        for (size_t i = 0; i < (size_t)256 * 256; i++)
            if (cnt[i]) sum += cnt[i], covered += 1.0;
        *ppp = covered > 0.0 ? sum / covered : 0.0;
        spr_backend_target_destroy(b, t);
        rd.algo = SPR_ALGO_DOMAIN_OVERLAP;
        double t0 = spr_now_ms();
        if (!spr_render(b, &v, c, &rd, &out, err)) {
            *ms = spr_now_ms() - t0;
            spr_render_result_free(&out);
            rc = 0;
        }
    }
    free(cnt);
    spr_backend_destroy(b);
    return rc;
}

/* The textures of a level side by side (spr_rects_atlas, rows of at most
 * 1024 texels), colour with the basis function as alpha. */
static int write_atlas(const char *path, const spr_rects *rs, spr_error *err)
{
    int32_t *org = malloc((rs->n ? rs->n : 1) * 2 * sizeof *org);
    float *img = NULL;
    int W, H;
    if (!org) return spr__fail(err, SPR_E_NOMEM, "domains: out of memory for the atlas");
    spr_result r = spr_rects_atlas(rs, 1024, &img, &W, &H, org, err);
    if (!r) r = spr_write_png_rgba(path, img, W, H, err);
    free(img);
    free(org);
    return r;
}

int cmd_domains(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "domains", domains_opts, "--model M [--stats] [--level L --basis-out F --dump F.ply] [options]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    spr_scene s;
    memset(&s, 0, sizeof s);
    spr_load_desc ld;
    spr_scene_domain o;
    int rc = 2;
    const char *basis_out = spr__get(&a, "basis-out"), *dump = spr__get(&a, "dump");
    const int stats = spr__flag(&a, "stats");
    if (spr__model_opts(&a, &s, &ld) || spr__domain_opts(&a, &o) || (spr__flag(&a, "quiet"), spr__reject_unused(&a))) return 2;
    if ((basis_out || dump) && o.level < 0) { spr__error(&a, "--basis-out and --dump need --level"); return 2; }
    if (!stats && !basis_out && !dump) { spr__error(&a, "nothing to do: give --stats, --basis-out or --dump"); return 2; }
    o.dd.threads = o.pd.threads = s.threads;
    o.dd.progress = ld.progress;
    spr_error err = {0};
    spr_decomp dc = {0};
    int32_t *dom = NULL;
    size_t *merged_from = NULL;
    spr_rects rs = {0};
    if (spr__load_model(&a, &s, &ld)) goto done;
    double t0 = spr_now_ms();
    if (spr_decompose(&s.cloud, &o.dd, &dc, &err)) { fprintf(stderr, "splatref domains: %s: %s\n", s.model, err.msg); goto done; }
    const double ms_decomp = spr_now_ms() - t0;
    if (o.level >= dc.levels) { spr__error(&a, "--level %d: the decomposition has levels 0..%d", o.level, dc.levels - 1); goto done; }
    merged_from = calloc((size_t)dc.levels, sizeof *merged_from);
    if (!merged_from) { spr__error(&a, "out of memory"); goto done; }
    double ms_merge = 0.0;
    for (int l = 0; l < dc.levels; l++) { /* every level's basis replaced by its merged one */
        double t1 = spr_now_ms();
        if (spr__domain_merge(&a, &s.cloud, &o, &dc, l, &merged_from[l])) goto done;
        ms_merge += spr_now_ms() - t1;
    }
    printf("domains: %s, %zu points, %d levels (local analysis %.0f ms, coarsening and basis %.0f ms, all %.0f ms%s)\n", s.model, s.cloud.n,
           dc.levels, dc.ms_analysis, dc.ms_coarsen, ms_decomp, o.merge ? ", merging below" : "");
    if (o.merge) printf("  merging at flatness < %g and normal dot > %g: %.0f ms for all levels\n", o.mflat, o.mdot, ms_merge);
    if (stats) {
        if (o.merge) printf("  (regions before merging in brackets)\n");
        printf("  %5s %9s %8s %11s %11s %11s %9s %10s %9s %9s %9s\n", "level", "regions", "polygons", "points/poly", "error", "norm.error",
               "texels", "tex.bytes", "prim/pix", "render", "build");
        for (int l = 0; l < dc.levels; l++) {
            if (o.level >= 0 && l != o.level) continue;
            spr_prims_stats st;
            double ppp = 0.0, rms = 0.0;
            if (spr_domain_prims(&s.cloud, &dc.basis[l], &o.pd, &rs, &st, &err) || render_stats(&s.cloud, &rs, s.threads, &ppp, &rms, &err)) {
                fprintf(stderr, "splatref domains: %s level %d: %s\n", s.model, l, err.msg[0] ? err.msg : "out of memory");
                goto done;
            }
            spr_rects_free(&rs);
            char reg[48];
            if (o.merge) snprintf(reg, sizeof reg, "%zu(%zu)", dc.regions[l], merged_from[l]);
            else snprintf(reg, sizeof reg, "%zu", dc.regions[l]);
            printf("  %5d %9s %8zu %11.1f %11.4g %11.4g %9zu %10zu %9.2f %7.1fms %7.0fms\n", l, reg, st.polygons, st.points, st.error,
                   st.error_norm, st.texels, 4 * st.texels, ppp, rms, st.ms);
        }
        const spr_texture_desc *td = &o.pd.tex;
        printf("  (%s domains%s; error: mean distance point-projection per polygon, normalised by the mean radius;\n"
               "   %s%s textures, width %g, texel %g x mean radius, normalised where %s, RGBA 8-bit bytes;\n"
               "   prim/pix: rectangles covering a covered pixel on average and render: domain-overlap on the CPU backend,\n"
               "   both at 256x256 framing the model; build: polygons, textures and neighbours)\n",
               o.pd.strict ? "strict" : "thresholded", o.pd.strict ? "" : " at phi >= K", o.pd.affine ? "affine (radial where no triangle) + radial " : "radial ",
               td->shape == SPR_RBF_CONSTANT ? "constant" : td->shape == SPR_RBF_LINEAR ? "linear" : "gauss", td->width, td->texel_factor,
               td->normalize == SPR_NORM_GE1 ? "f >= 1" : "f > 0");
    }
    if (basis_out || dump) {
        const spr_csr *B = &dc.basis[o.level];
        dom = malloc(s.cloud.n * sizeof *dom);
        if (!dom) { spr__error(&a, "out of memory"); goto done; }
        spr_domain_strict(B, dom);
        if (basis_out) {
            basis_file bf = {&s.cloud, B, dom};
            if (spr__write_atomic(basis_out, write_basis, &bf, &err)) { fprintf(stderr, "splatref domains: %s\n", err.msg); goto done; }
            printf("domains: level %d basis (%zu regions) -> %s\n", o.level, dc.regions[o.level], basis_out);
        }
        if (dump) {
            spr_prims_stats st;
            char atlas[1100];
            size_t L = strlen(dump);
            snprintf(atlas, sizeof atlas, "%.*s-atlas.png", (int)(L > 4 && !strcmp(dump + L - 4, ".ply") ? L - 4 : L), dump);
            if (spr_domain_prims(&s.cloud, B, &o.pd, &rs, &st, &err) || write_atlas(atlas, &rs, &err)) {
                fprintf(stderr, "splatref domains: %s\n", err.msg);
                goto done;
            }
            for (size_t i = 0; i < s.cloud.n; i++) region_color(dom[i], s.cloud.color + 3 * i);
            if (spr_write_ply(dump, &s.cloud, &err)) { fprintf(stderr, "splatref domains: %s\n", err.msg); goto done; }
            printf("domains: level %d strict domains, coloured -> %s; %zu textures -> %s\n", o.level, dump, rs.n, atlas);
        }
    }
    rc = 0;
done:
    spr_rects_free(&rs);
    free(dom);
    free(merged_from);
    spr_decomp_free(&dc);
    spr_scene_free(&s);
    return rc;
}
