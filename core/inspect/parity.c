/* parity.c — capture every plane of every pass on the reference backend,
 * then compare against the backend under test as its passes run. */
#include "spr_parity.h"
#include "spr_image.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *spr_parity_plane_name(int plane)
{
    return plane == SPR_PLANE_FINAL ? "final" : plane == SPR_PLANE_RECORDS ? "records" : spr_plane_name((spr_plane)plane);
}

uint64_t spr_ulp_distance(float a, float b)
{
    int32_t ia, ib;
    memcpy(&ia, &a, 4);
    memcpy(&ib, &b, 4);
    if (ia == ib) return 0;
    /* map sign-magnitude to a monotonic integer line */
    int64_t la = ia < 0 ? (int64_t)INT32_MIN - ia : ia, lb = ib < 0 ? (int64_t)INT32_MIN - ib : ib;
    return (uint64_t)(la > lb ? la - lb : lb - la);
}

typedef struct compare_ctx {
    const spr_capture *ref;
    spr_parity_report *rep;
    const char *dir, *label;
    int failed, index;
    spr_error err;
} compare_ctx;

static void ramp(double f, unsigned char rgb[3])
{ /* blue (1 ulp) → yellow → red (huge) */
    if (f < 0.5) { rgb[0] = (unsigned char)(510 * f); rgb[1] = (unsigned char)(510 * f); rgb[2] = (unsigned char)(255 * (1 - 2 * f)); }
    else { rgb[0] = 255; rgb[1] = (unsigned char)(255 * (2 - 2 * f)); rgb[2] = 0; }
}

static int add_diff(compare_ctx *cc, spr_plane_diff *out)
{
    spr_parity_report *r = cc->rep;
    spr_plane_diff *np = realloc(r->planes, (size_t)(r->n_planes + 1) * sizeof *np);
    if (!np) return -1;
    r->planes = np;
    r->planes[r->n_planes++] = *out;
    if (!out->differing_pixels) r->exact_planes++;
    if (out->max_ulp > r->max_ulp) r->max_ulp = out->max_ulp;
    return 0;
}

/* Compare one plane; heatmap pixels: grey = equal, colour = log2 of the difference. */
static void compare_plane(compare_ctx *cc, int pass, const char *pname, int group, int plane, int W, int H,
                          const void *ref, const void *test)
{
    int ch = plane == SPR_PLANE_FINAL ? 4 : plane == SPR_PLANE_RECORDS ? 1 : spr_plane_channels((spr_plane)plane);
    const spr_plane_info *pi = plane >= SPR_PLANE__COUNT ? NULL : spr_plane_info_of((spr_plane)plane);
    int is_uint = pi && spr_plane_type_uint(pi->type);
    spr_plane_diff d;
    memset(&d, 0, sizeof d);
    d.pass = pass;
    snprintf(d.pass_name, sizeof d.pass_name, "%s", pname);
    d.group = group;
    d.plane = plane;
    d.values = (size_t)W * H * ch;
    d.first_x = d.first_y = d.first_channel = -1;
    float *heat = NULL;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int pixel_differs = 0;
            double worst = 0.0;
            for (int c = 0; c < ch; c++) {
                size_t i = ((size_t)y * W + x) * ch + c;
                uint64_t u;
                double a, b;
                if (is_uint) {
                    uint32_t ua = ((const uint32_t *)ref)[i], ub = ((const uint32_t *)test)[i];
                    if (ua == ub) continue;
                    u = ua > ub ? ua - ub : ub - ua;
                    a = ua;
                    b = ub;
                } else {
                    float fa = ((const float *)ref)[i], fb = ((const float *)test)[i];
                    u = spr_ulp_distance(fa, fb);
                    if (!u) continue;
                    a = fa;
                    b = fb;
                }
                if (!pixel_differs && d.first_x < 0) {
                    d.first_x = x; d.first_y = y; d.first_channel = c; d.first_ref = a; d.first_test = b;
                }
                pixel_differs = 1;
                if (u > d.max_ulp) d.max_ulp = u;
                double ad = fabs(a - b);
                if (ad > d.max_abs || isnan(ad)) d.max_abs = isnan(ad) ? INFINITY : ad;
                if (!is_uint) { /* the 8-bit PNG value both would write (PARITY.md rule 8) */
                    int la = spr_to_u8((float)a), lb = spr_to_u8((float)b), l = la > lb ? la - lb : lb - la;
                    if (l > d.max_lsb) d.max_lsb = l;
                }
                double lu = log2((double)u + 1.0);
                if (lu > worst) worst = lu;
            }
            if (!pixel_differs) continue;
            d.differing_pixels++;
            if (cc->dir && plane != SPR_PLANE_RECORDS) { /* records: no picture */
                if (!heat) heat = calloc((size_t)W * H, sizeof(float));
                if (heat) heat[(size_t)y * W + x] = (float)worst;
            }
        }
    if (heat) {
        float *rgb = malloc((size_t)W * H * 3 * sizeof(float));
        if (rgb) {
            for (size_t i = 0; i < (size_t)W * H; i++) {
                unsigned char c3[3] = {40, 40, 40};
                if (heat[i] > 0.0f) ramp(heat[i] / 32.0 > 1.0 ? 1.0 : heat[i] / 32.0, c3);
                for (int k = 0; k < 3; k++) rgb[3 * i + k] = c3[k] / 255.0f;
            }
            const char *plane_name = spr_parity_plane_name(plane);
            if (group >= 0)
                snprintf(d.heatmap, sizeof d.heatmap, "%s_%03d_%s_k%03d_%s.png", cc->label, pass, pname, group, plane_name);
            else if (pass >= 0)
                snprintf(d.heatmap, sizeof d.heatmap, "%s_%03d_%s_%s.png", cc->label, pass, pname, plane_name);
            else
                snprintf(d.heatmap, sizeof d.heatmap, "%s_final.png", cc->label);
            char path[1024];
            snprintf(path, sizeof path, "%s/%s", cc->dir, d.heatmap);
            if (spr_write_png(path, rgb, W, H, 3, &cc->err)) cc->failed = 1;
            free(rgb);
        }
        free(heat);
    }
    if (add_diff(cc, &d)) cc->failed = 1;
}

static void compare_hook(void *user, spr_backend *b, const spr_pass_info *info)
{
    compare_ctx *cc = user;
    int i = cc->index++;
    if (cc->failed || i >= cc->ref->n) return;
    const spr_captured_pass *rp = &cc->ref->passes[i];
    if (strcmp(rp->name, info->name) || rp->group != info->group) return; /* reported via pass counts */
    if ((rp->stats.generated != info->stats.generated || rp->stats.passed != info->stats.passed) &&
        !cc->rep->stats_mismatches++)
        snprintf(cc->rep->first_stats_mismatch, sizeof cc->rep->first_stats_mismatch,
                 "pass %d %s: generated %llu vs %llu, passed %llu vs %llu", i, info->name,
                 (unsigned long long)rp->stats.generated, (unsigned long long)info->stats.generated,
                 (unsigned long long)rp->stats.passed, (unsigned long long)info->stats.passed);
    int W = b->view.width, H = b->view.height;
    void *buf = malloc((size_t)W * H * 4 * sizeof(float));
    if (!buf) { cc->failed = 1; return; }
    if (spr_backend_target_planes(b, info->target) != rp->planes) {
        cc->failed = 1;
        snprintf(cc->err.msg, sizeof cc->err.msg, "pass %d %s: the targets have different planes (0x%x vs 0x%x)", i, info->name,
                 rp->planes, spr_backend_target_planes(b, info->target));
    }
    for (int k = 0; k < SPR_PLANE__COUNT && !cc->failed; k++) {
        if (!(rp->planes & SPR_PLANE_BIT(k))) continue;
        if (spr_backend_read_plane(b, info->target, (spr_plane)k, buf)) { cc->failed = 1; cc->err = b->err; break; }
        compare_plane(cc, i, info->name, info->group, k, W, H, rp->plane[k], buf);
    }
    free(buf);
    if (!cc->failed && (rp->records || info->records)) { /* a preprocessing pass: its records, value by value */
        if (!rp->records || !info->records || rp->n_records != info->n_records) {
            cc->failed = 1;
            snprintf(cc->err.msg, sizeof cc->err.msg, "pass %d %s: %zu records vs %zu", i, info->name, rp->n_records, info->n_records);
        } else {
            compare_plane(cc, i, info->name, info->group, SPR_PLANE_RECORDS, SPR_GREC_FLOATS, (int)info->n_records, rp->records, info->records);
        }
    }
}

spr_result spr_parity_run(spr_backend *ref, spr_backend *test, const spr_view *v, const spr_cloud *c,
                          const spr_render_desc *desc_ref, const spr_render_desc *desc_test, const char *heatmap_dir,
                          const char *label, spr_parity_report *rep, spr_error *err)
{
    memset(rep, 0, sizeof *rep);
    spr_capture cp = {0};
    spr_render_desc dr = *desc_ref, dt = *desc_test;
    dr.hook = spr_capture_hook;
    dr.hook_user = &cp;
    spr_render_result rr, rt;
    /* the tested backend's limits before the reference's frame (spr_render asks the reference's itself) */
    spr_result r = spr_render_fits(test, c, desc_test->algo, err);
    if (!r) r = spr_render(ref, v, c, &dr, &rr, err);
    if (r) { spr_capture_free(&cp); return r; }
    if (cp.failed) {
        spr_capture_free(&cp);
        spr_render_result_free(&rr);
        return spr__fail(err, SPR_E_NOMEM, "parity: could not capture the reference's planes");
    }
    compare_ctx cc = {&cp, rep, heatmap_dir, label ? label : "parity", 0, 0, {0}};
    dt.hook = compare_hook;
    dt.hook_user = &cc;
    r = spr_render(test, v, c, &dt, &rt, err);
    if (!r) {
        rep->passes_ref = cp.n;
        rep->passes_test = cc.index;
        compare_plane(&cc, -1, "final", -1, SPR_PLANE_FINAL, rr.width, rr.height, rr.rgba, rt.rgba);
        spr_render_result_free(&rt);
        if (cc.failed) r = spr__fail(err, SPR_E_IO, "parity: %s", cc.err.msg[0] ? cc.err.msg : "out of memory");
    }
    spr_render_result_free(&rr);
    spr_capture_free(&cp);
    return r;
}

int spr_parity_exact(const spr_parity_report *rep)
{
    return rep->exact_planes == rep->n_planes && rep->n_planes > 0 && rep->stats_mismatches == 0 &&
           rep->passes_ref == rep->passes_test;
}

void spr_parity_report_free(spr_parity_report *rep)
{
    free(rep->planes);
    memset(rep, 0, sizeof *rep);
}
