/* gauss_grad.c — the backward pass of gauss3d (SPEC 10.10; the operations
 * restated in docs/gradients.md):
 *
 *   pass "preprocess", "sort", "raster"   the forward frame (gauss.c)
 *   host                                  the upstream gradient ∂L/∂C from the
 *                                         loss and the forward's image, and
 *                                         each Gaussian's list entries (CSR)
 *   pass "backward"                       the backend: per tile, every pixel's
 *                                         reverse walk into its entries'
 *                                         partials; per Gaussian their sums in
 *                                         tile order, then the chain to μ, q,
 *                                         σ, o (arith/gauss.h)
 *   host "colour"                         the SH's backward in double, rounded
 *                                         once: sh0, shN, and μ's share through
 *                                         the view direction
 *
 * Every float operation of the backward that depends on the backend runs in
 * the shared arithmetic; the host's parts are the same code for both.
 */
#include "spr_grad.h"
#include "spr_util.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

void spr_gauss_grads_free(spr_gauss_grads *g)
{
    free(g->means), free(g->quats), free(g->scales), free(g->opacities), free(g->sh), free(g->means2d), free(g->conics);
    free(g->colors), free(g->absgrad), free(g->counts), free(g->image);
    memset(g, 0, sizeof *g);
}

int spr_gauss_grads_arrays(const spr_gauss_grads *g, spr_grad_array *a, int cap)
{
    const spr_grad_array all[] = {
        {"means", 3, g->means}, {"quats", 4, g->quats}, {"scales", 3, g->scales}, {"opacities", 1, g->opacities},
        {"sh0", g->sh_k > 0 ? 3 : 0, g->sh}, {"shN", g->sh_k > 1 ? 3 * (g->sh_k - 1) : 0, g->sh},
        {"means2d", 2, g->means2d}, {"conics", 3, g->conics}, {"colors", 3, g->colors}, {"absgrad", 2, g->absgrad},
        {"counts", 1, NULL},
    };
    const int n = (int)(sizeof all / sizeof all[0]);
    for (int i = 0; i < n && i < cap; i++) a[i] = all[i];
    return n;
}

/* Each Gaussian's list entries, ascending: csr[start[G] … start[G + 1]). */
static spr_result entries_of(const uint32_t *list, size_t entries, size_t n, uint32_t **start_out, uint32_t **csr_out, spr_error *err)
{
    uint32_t *start = calloc(n + 1, sizeof *start), *csr = spr__big_alloc((entries ? entries : 1) * sizeof *csr);
    if (!start || !csr) {
        free(start), free(csr);
        return spr__fail(err, SPR_E_NOMEM, "grad: out of memory for %zu list entries", entries);
    }
    for (size_t e = 0; e < entries; e++) start[list[e] + 1]++;
    for (size_t G = 0; G < n; G++) start[G + 1] += start[G];
    uint32_t *at = malloc((n ? n : 1) * sizeof *at);
    if (!at) {
        free(start), free(csr);
        return spr__fail(err, SPR_E_NOMEM, "grad: out of memory for %zu Gaussians", n);
    }
    memcpy(at, start, n * sizeof *at);
    for (size_t e = 0; e < entries; e++) csr[at[list[e]]++] = (uint32_t)e;
    free(at);
    *start_out = start;
    *csr_out = csr;
    return SPR_OK;
}

/* ∂L/∂C (and ∂L/∂A, ∂L/∂D) per pixel, 5 values a pixel; the loss. */
static spr_result upstream(const spr_grad_desc *gd, const float *rgba, int W, int H, float *up, double *loss, spr_error *err)
{
    const size_t np = (size_t)W * H;
    const double inv = 1.0 / (3.0 * (double)np);
    double L = 0.0;
    for (size_t i = 0; i < np; i++) {
        for (int ch = 0; ch < 3; ch++) {
            double g;
            if (gd->loss == SPR_LOSS_GIVEN) g = gd->dl_dimage[3 * i + ch];
            else {
                const double r = (double)rgba[4 * i + ch] - (double)gd->target[3 * i + ch];
                if (gd->loss == SPR_LOSS_L1) L += fabs(r), g = (r > 0.0 ? 1.0 : r < 0.0 ? -1.0 : 0.0) * inv;
                else L += r * r, g = 2.0 * r * inv;
            }
            up[5 * i + ch] = (float)g;
        }
        up[5 * i + 3] = gd->dl_dalpha ? gd->dl_dalpha[i] : 0.0f;
        up[5 * i + 4] = gd->dl_ddepth ? gd->dl_ddepth[i] : 0.0f;
        if (!isfinite(up[5 * i]) || !isfinite(up[5 * i + 1]) || !isfinite(up[5 * i + 2]) || !isfinite(up[5 * i + 3]) || !isfinite(up[5 * i + 4]))
            return spr__fail(err, SPR_E_ARG, "grad: the upstream gradient at pixel (%d, %d) (row 0 the top) is not finite", (int)(i % (size_t)W),
                             H - 1 - (int)(i / (size_t)W));
    }
    *loss = gd->loss == SPR_LOSS_GIVEN ? 0.0 : L * inv;
    return SPR_OK;
}

static spr_result grad_frame(spr__run *run, const spr_grad_desc *gd, spr_gauss_grads *out)
{
    spr_backend *b = run->b;
    const spr_cloud *c = run->cloud;
    const size_t n = c->n;
    const int W = b->view.width, H = b->view.height;
    double t0 = spr_now_ms();
    spr__gauss_frame_st f;
    spr_result r = spr__gauss_prepare(run, 0, &f);
    if (r) return r;
    const spr_gauss_profile *pf = f.pf;
    int target = -1;
    float *up = NULL, *sums = NULL, *chain = NULL;
    uint32_t *start = NULL, *csr = NULL;
    if ((r = spr__gauss_raster_frame(run, 0, &f, &target))) goto done;
    if (!(out->image = malloc((size_t)W * H * 4 * sizeof *out->image)) || !(up = spr__big_alloc((size_t)W * H * 5 * sizeof *up))) {
        r = spr__fail(run->err, SPR_E_NOMEM, "grad: out of memory for a %dx%d image", W, H);
        goto done;
    }
    if ((r = spr_backend_read_plane(b, target, SPR_PLANE_COLOR, out->image))) {
        r = spr__fail(run->err, r, "%s backend: %s", b->name, b->err.msg);
        goto done;
    }
    out->ms_forward = spr_now_ms() - t0;
    t0 = spr_now_ms();
    if ((r = upstream(gd, out->image, W, H, up, &out->loss, run->err))) goto done;
    const size_t tiles = (size_t)f.gd.prm[SPR_GPRM_GX] * (size_t)f.gd.prm[SPR_GPRM_GY], entries = f.range[tiles];
    if ((r = entries_of(f.list, entries, n, &start, &csr, run->err))) goto done;
    sums = spr__big_alloc((n ? n : 1) * SPR_GPART_FLOATS * sizeof *sums), chain = spr__big_alloc((n ? n : 1) * SPR_GOUT_FLOATS * sizeof *chain);
    const int K = c->sh && c->sh_k > 0 ? (c->sh_k < (pf->colour.sh_max + 1) * (pf->colour.sh_max + 1) ? c->sh_k : (pf->colour.sh_max + 1) * (pf->colour.sh_max + 1)) : 1;
    out->n = n, out->sh_k = K, out->width = W, out->height = H;
    const size_t m = n ? n : 1;
    out->means = malloc(m * 3 * sizeof(float)), out->quats = malloc(m * 4 * sizeof(float)), out->scales = malloc(m * 3 * sizeof(float));
    out->opacities = malloc(m * sizeof(float)), out->sh = calloc(m * (size_t)K * 3, sizeof(float)), out->means2d = malloc(m * 2 * sizeof(float));
    out->conics = malloc(m * 3 * sizeof(float)), out->colors = malloc(m * 3 * sizeof(float)), out->absgrad = malloc(m * 2 * sizeof(float));
    out->counts = malloc(m * sizeof(int32_t));
    if (!sums || !chain || !out->means || !out->quats || !out->scales || !out->opacities || !out->sh || !out->means2d || !out->conics ||
        !out->colors || !out->absgrad || !out->counts) {
        r = spr__fail(run->err, SPR_E_NOMEM, "grad: out of memory for the gradients of %zu Gaussians", n);
        goto done;
    }
    spr_gauss_bwd_desc bd = {f.rec, n, f.range, f.list, start, csr, up, f.gd.mu, f.gd.q, f.gd.s, {0, 0, 0}, {0}, gd->batch};
    memcpy(bd.background, run->desc->background, sizeof bd.background);
    memcpy(bd.prm, f.gd.prm, sizeof bd.prm);
    double tb = spr_now_ms();
    if ((r = spr_backend_gauss_backward(b, &bd, sums, chain))) {
        r = spr__fail(run->err, r, "%s backend: %s", b->name, b->err.msg);
        goto done;
    }
    spr_draw_stats st = {n, entries, 0};
    for (size_t G = 0; G < n; G++) st.passed += (uint64_t)sums[G * SPR_GPART_FLOATS + SPR_GPART_COUNT];
    if ((r = spr__run_host_pass(run, "backward", &st, spr_now_ms() - tb))) goto done;
    double eye[3];
    spr_pinhole_eye(&b->view.cv, eye);
#pragma omp parallel for schedule(static)
    for (long li = 0; li < (long)n; li++) {
        const size_t G = (size_t)li;
        const float *S = sums + G * SPR_GPART_FLOATS, *O = chain + G * SPR_GOUT_FLOATS;
        double vsh[48], vmu[3];
        spr_cloud_gauss_colors_bwd(c, eye, pf->colour.sh_max, G, S + SPR_GPART_COLOR, vsh, vmu);
        for (int a = 0; a < 3; a++) {
            const float v = O[SPR_GOUT_MEANS + a] + (float)vmu[a];
            out->means[3 * G + a] = v;
            out->scales[3 * G + a] = O[SPR_GOUT_SCALES + a];
            out->conics[3 * G + a] = S[SPR_GPART_CONIC + a];
            out->colors[3 * G + a] = S[SPR_GPART_COLOR + a];
        }
        /* the quaternion as given: the unit one's tangent part over the norm it was given with */
        const float qn = c->gauss && c->gauss[SPR_GAUSS_FLOATS * G + 7] > 0.0f ? c->gauss[SPR_GAUSS_FLOATS * G + 7] : 1.0f;
        for (int a = 0; a < 4; a++) out->quats[4 * G + a] = O[SPR_GOUT_QUATS + a] / qn;
        out->opacities[G] = O[SPR_GOUT_OPACITY];
        for (int a = 0; a < 2; a++) out->means2d[2 * G + a] = S[SPR_GPART_M + a], out->absgrad[2 * G + a] = S[SPR_GPART_ABS + a];
        out->counts[G] = (int32_t)S[SPR_GPART_COUNT];
        if (c->sh && c->sh_k > 0)
            for (int k = 0; k < 3 * K; k++) out->sh[G * (size_t)K * 3 + (size_t)k] = (float)vsh[k];
    }
    out->ms_backward = spr_now_ms() - t0;
done:
    free(up), free(sums), free(chain), free(start), free(csr);
    spr__gauss_frame_free(&f);
    return r;
}

spr_result spr_gauss_grad(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc, const spr_grad_desc *gd,
                          spr_gauss_grads *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    if (desc->algo != SPR_ALGO_GAUSS3D) return spr__fail(err, SPR_E_ARG, "grad: the backward pass is gauss3d's (SPEC 10.10), not %s's", spr_algo_name(desc->algo));
    const spr_gauss_profile *pf = spr_gauss_profile_of(desc->algo, desc->gauss_profile);
    if (!pf->grad.trains)
        return spr__fail(err, SPR_E_ARG, "grad: profile %s has no backward pass (its renderer does not train; SPEC 10.10 covers inria, gsplat, "
                         "gsplat-1.5, brush)", pf->name);
    if (desc->gauss_aa)
        return spr__fail(err, SPR_E_ARG, "grad: --gauss-aa's compensation has no backward here yet (docs/gradients.md, open questions): "
                         "leave it out");
    if (desc->source) return spr__fail(err, SPR_E_ARG, "grad: a streamed cloud (--stream) has no backward pass: leave out --stream");
    if (gd->loss != SPR_LOSS_GIVEN && !gd->target) return spr__fail(err, SPR_E_ARG, "grad: a loss without a target image");
    if (gd->loss == SPR_LOSS_GIVEN && !gd->dl_dimage) return spr__fail(err, SPR_E_ARG, "grad: neither a loss nor an upstream gradient");
    spr_result r = spr_render_fits(b, cloud, desc->algo, err);
    if (r) return r;
    if ((r = spr_backend_set_view(b, view))) return spr__fail(err, r, "%s backend: %s", b->name, b->err.msg);
    spr_render_result res;
    memset(&res, 0, sizeof res);
    spr__run run = {b, cloud, desc, &res, err, 0.0f, {0, 0, 0, 0}, 0, {0}, 0, {0}, NULL};
    const int omp_default = omp_get_max_threads();
    if (b->host_threads > 0) omp_set_num_threads(b->host_threads);
    r = grad_frame(&run, gd, out);
    omp_set_num_threads(omp_default);
    for (int t = 0; t < b->n_targets; t++) spr_backend_target_destroy(b, t);
    spr_render_result_free(&res);
    if (r) spr_gauss_grads_free(out);
    return r;
}
