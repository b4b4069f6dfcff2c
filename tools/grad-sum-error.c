/* grad-sum-error.c — the summation error of gauss3d's gradients (SPEC 10.10
 * item 4, docs/gradients.md "Summation order"): for Gaussians of a capture,
 * every float32 term the backward adds (spr_gauss_grad_explain: a pixel's
 * terms, in the backward's order) summed again in float64, against the
 * float32 two-level sum the backends compute (pixels into a tile's partial,
 * tiles in tile order).  Prints, per field, the largest error over
 * Σ|terms| and in units of 2^-24·Σ|terms|, beside the classic bound
 * (n − 1)·2^-24·Σ|terms| of n terms.
 *
 *   grad_sum_error CAPTURE.ply CAMERAS.json CAMERA_ID W H PROFILE [EVERY]
 *
 * (Gaussians 0, EVERY, 2·EVERY, … that reach a pixel; upstream: l2 against a
 * black image.)  Built by CMake beside the CLI; not a test. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "spr_grad.h"
#include "spr_io.h"
#include "spr_camera.h"
#include "spr_swrast.h"

int main(int argc, char **argv)
{
    if (argc < 7) {
        fprintf(stderr, "usage: grad_sum_error CAPTURE.ply CAMERAS.json CAMERA_ID W H PROFILE [EVERY]\n");
        return 2;
    }
    spr_error err = {0};
    spr_load_desc ld;
    spr_load_defaults(&ld);
    ld.sh_degree = 3;
    spr_cloud c;
    if (spr_load(argv[1], &ld, &c, &err)) { fprintf(stderr, "%s\n", err.msg); return 2; }
    spr_camera_desc cam;
    spr_camera_defaults(&cam);
    spr_pinhole q;
    int w, h;
    if (spr_cameras_json(argv[2], atol(argv[3]), &q, &w, &h, &err)) { fprintf(stderr, "%s\n", err.msg); return 2; }
    cam.width = atoi(argv[4]), cam.height = atoi(argv[5]);
    const double sx = (double)cam.width / w, sy = (double)cam.height / h; /* the same field of view at this size */
    q.fx *= sx, q.cx *= sx, q.fy *= sy, q.cy *= sy;
    cam.pinhole = q, cam.have_pinhole = 1;
    spr_bounds bd;
    spr_cloud_bounds(&c, &bd);
    spr_camera_frame(&cam, &bd);
    spr_view v;
    if (spr_view_make(&cam, &v, &err)) { fprintf(stderr, "%s\n", err.msg); return 2; }
    const int prof = spr_gauss_profile_from_name(argv[6]);
    if (prof < 0) { fprintf(stderr, "unknown profile %s\n", argv[6]); return 2; }
    const size_t every = argc > 7 ? (size_t)atol(argv[7]) : 97;
    spr_backend *b = spr_swrast_create(2, &err);
    spr_render_desc rd = {.algo = SPR_ALGO_GAUSS3D, .gauss_profile = prof + 1};
    const spr_grad_desc gd = {.loss = SPR_LOSS_L2};
    spr_gauss_grads g;
    if (!b || spr_gauss_grad(b, &v, &c, &rd, &gd, &g, &err)) { fprintf(stderr, "%s\n", err.msg); return 2; }
    static const char *const fname[SPR_GPART_FLOATS] = {"color r", "color g", "color b", "1/t.z", "opacity", "conic A", "conic B", "conic C",
                                                        "means2d x", "means2d y", "absgrad x", "absgrad y", "count", "", "", ""};
    double worst[SPR_GPART_FLOATS] = {0}, worst_ulp[SPR_GPART_FLOATS] = {0}, bound_ratio[SPR_GPART_FLOATS] = {0};
    size_t gaussians = 0, terms = 0, maxn = 0;
    for (size_t G = 0; G < c.n; G += every) {
        if (g.counts[G] == 0) continue;
        spr_grad_explain x;
        if (spr_gauss_grad_explain(b, &v, &c, &rd, &gd, G, &x, &err)) { fprintf(stderr, "%s\n", err.msg); return 2; }
        gaussians++;
        terms += x.n_terms;
        if (x.n_terms > maxn) maxn = x.n_terms;
        for (int f = 0; f < 12; f++) {
            if (f == 3) continue; /* no ∂L/∂D here */
            double s64 = 0.0, mag = 0.0;
            for (size_t k = 0; k < x.n_terms; k++) s64 += (double)x.terms[k].part[f], mag += fabs((double)x.terms[k].part[f]);
            if (mag == 0.0) continue;
            const double e = fabs((double)x.sum[f] - s64) / mag;
            if (e > worst[f]) worst[f] = e;
            const double u = e / ldexp(1.0, -24);
            if (u > worst_ulp[f]) worst_ulp[f] = u;
            const double br = u / (double)(x.n_terms > 1 ? x.n_terms - 1 : 1);
            if (br > bound_ratio[f]) bound_ratio[f] = br;
        }
        spr_grad_explain_free(&x);
    }
    printf("grad_sum_error: %s, camera %s, %sx%s, %s: %zu Gaussians (every %zu-th that reaches a pixel), %zu terms, at most %zu a Gaussian\n", argv[1],
           argv[3], argv[4], argv[5], argv[6], gaussians, every, terms, maxn);
    printf("  %-10s %14s %16s %20s\n", "field", "max err/Σ|t|", "in 2^-24 Σ|t|", "of the (n-1) bound");
    for (int f = 0; f < 12; f++)
        if (f != 3) printf("  %-10s %14.3g %16.2f %20.3g\n", fname[f], worst[f], worst_ulp[f], bound_ratio[f]);
    spr_gauss_grads_free(&g);
    spr_backend_destroy(b);
    spr_cloud_free(&c);
    return 0;
}
