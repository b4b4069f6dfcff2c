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
#include "spr_arith_c.h"
#include "spr_util.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

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
                const double r = (double)rgba[4 * i + ch] - (gd->target ? (double)gd->target[3 * i + ch] : 0.0);
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
            /* a backward rule (SPEC 10.10 item 3): a renderer that detaches the view direction gives μ no gradient through the colour */
            const float v = pf->grad.detach_dirs ? O[SPR_GOUT_MEANS + a] : O[SPR_GOUT_MEANS + a] + (float)vmu[a];
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

/* What spr_gauss_grad and spr_gauss_grad_explain share: the frame's checks, its view, its run on the backend's host
 * thread count, fn on it, its targets destroyed. */
typedef spr_result (*frame_fn)(spr__run *run, const spr_grad_desc *gd, void *user);
static spr_result with_frame(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc, const spr_grad_desc *gd,
                             frame_fn fn, void *user, spr_error *err)
{
    if (desc->algo != SPR_ALGO_GAUSS3D) return spr__fail(err, SPR_E_ARG, "grad: the backward pass is gauss3d's (SPEC 10.10), not %s's", spr_algo_name(desc->algo));
    const spr_gauss_profile *pf = spr_gauss_profile_of(desc->algo, desc->gauss_profile);
    if (!pf->grad.trains)
        return spr__fail(err, SPR_E_ARG, "grad: profile %s has no backward pass (its renderer does not train; SPEC 10.10 covers the rows whose "
                         "renderer trains: inria, gsplat, gsplat-1.5, brush, opensplat)", pf->name);
    if (desc->gauss_aa)
        return spr__fail(err, SPR_E_ARG, "grad: --gauss-aa's compensation has no backward here yet (docs/gradients.md, open questions): "
                         "leave it out");
    if (desc->source) return spr__fail(err, SPR_E_ARG, "grad: a streamed cloud (--stream) has no backward pass: leave out --stream");
    if (gd->loss == SPR_LOSS_GIVEN && !gd->dl_dimage) return spr__fail(err, SPR_E_ARG, "grad: neither a loss nor an upstream gradient");
    spr_result r = spr_render_fits(b, cloud, desc->algo, err);
    if (r) return r;
    if ((r = spr_backend_set_view(b, view))) return spr__fail(err, r, "%s backend: %s", b->name, b->err.msg);
    spr_render_result res;
    memset(&res, 0, sizeof res);
    spr__run run = {b, cloud, desc, &res, err, 0.0f, {0, 0, 0, 0}, 0, {0}, 0, {0}, NULL};
    const int omp_default = omp_get_max_threads();
    if (b->host_threads > 0) omp_set_num_threads(b->host_threads);
    r = fn(&run, gd, user);
    omp_set_num_threads(omp_default);
    for (int t = 0; t < b->n_targets; t++) spr_backend_target_destroy(b, t);
    spr_render_result_free(&res);
    return r;
}

static spr_result grad_fn(spr__run *run, const spr_grad_desc *gd, void *user) { return grad_frame(run, gd, user); }

spr_result spr_gauss_grad(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc, const spr_grad_desc *gd,
                          spr_gauss_grads *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    const spr_result r = with_frame(b, view, cloud, desc, gd, grad_fn, out, err);
    if (r) spr_gauss_grads_free(out);
    return r;
}

void spr_grad_explain_free(spr_grad_explain *x)
{
    free(x->terms), free(x->tiles);
    memset(x, 0, sizeof *x);
}

unsigned spr__grad_fp_enter(void)
{
#if defined(__SSE__)
    const unsigned old = _mm_getcsr();
    _mm_setcsr(old | 0x8040u);
    return old;
#else
    return 0;
#endif
}
void spr__grad_fp_leave(unsigned old)
{
#if defined(__SSE__)
    _mm_setcsr(old);
#else
    (void)old;
#endif
}

/* The tile whose list holds entry e: range[t] ≤ e < range[t + 1]. */
static int tile_of(const uint32_t *range, int tiles, uint32_t e)
{
    int lo = 0, hi = tiles;
    while (hi - lo > 1) {
        const int mid = lo + (hi - lo) / 2;
        if (range[mid] <= e) lo = mid;
        else hi = mid;
    }
    return lo;
}

/* G's pixels in the backward's order (sw__gauss_backward: a tile's pixels row-major from the top row, each through
 * spr_gauss_tile_bwd, its terms added to the entry's partial; then the entries' partials in tile order,
 * spr_gauss_gather).  One pixel's terms are what spr_gauss_tile_bwd adds to a zeroed partial: 0 + v is v (a
 * denormal v flushed as the backend's add flushes it), so the two levels of float additions below are the
 * backend's, bit for bit.  α and T are read from the walk's state (those the Gaussian was walked back with); acc,
 * ∂L/∂α, ∂L/∂o and ∂L/∂power are recomputed beside it with the same operations (spr_gauss_blend_bwd's recurrence,
 * spr_gauss_alpha_bwd), to be shown, and ∂L/∂o held to the backend's term (consistent). */
static spr_result explain_frame(spr__run *run, const spr_grad_desc *gd, size_t G, spr_grad_explain *out)
{
    spr_backend *b = run->b;
    const size_t n = run->cloud->n;
    const int W = b->view.width, H = b->view.height;
    spr__gauss_frame_st f;
    spr_result r = spr__gauss_prepare(run, 0, &f);
    if (r) return r;
    int target = -1;
    float *image = NULL, *up = NULL, *tmp = NULL;
    uint32_t *start = NULL, *csr = NULL;
    size_t cap_terms = 0;
    double loss = 0.0;
    if ((r = spr__gauss_raster_frame(run, 0, &f, &target))) goto done;
    if (!(image = malloc((size_t)W * H * 4 * sizeof *image)) || !(up = spr__big_alloc((size_t)W * H * 5 * sizeof *up))) {
        r = spr__fail(run->err, SPR_E_NOMEM, "grad: out of memory for a %dx%d image", W, H);
        goto done;
    }
    if ((r = spr_backend_read_plane(b, target, SPR_PLANE_COLOR, image))) {
        r = spr__fail(run->err, r, "%s backend: %s", b->name, b->err.msg);
        goto done;
    }
    if ((r = upstream(gd, image, W, H, up, &loss, run->err))) goto done;
    const int gx = (int)f.gd.prm[SPR_GPRM_GX], tiles = gx * (int)f.gd.prm[SPR_GPRM_GY];
    const size_t entries = f.range[tiles];
    if ((r = entries_of(f.list, entries, n, &start, &csr, run->err))) goto done;
    const float *g = f.gd.prm, *bg = run->desc->background;
    const uint32_t k0 = start[G], k1 = start[G + 1];
    out->G = G, out->width = W, out->height = H, out->consistent = 1;
    if (k1 > k0 && !(out->tiles = calloc(k1 - k0, sizeof *out->tiles))) {
        r = spr__fail(run->err, SPR_E_NOMEM, "grad: out of memory");
        goto done;
    }
    const unsigned fp = spr__grad_fp_enter();
    for (uint32_t k = k0; k < k1 && !r; k++) {
        const uint32_t e = csr[k];
        const int t = tile_of(f.range, tiles, e);
        const uint32_t first = f.range[t], end = f.range[t + 1], len = end - first;
        float *nt = realloc(tmp, (size_t)len * SPR_GPART_FLOATS * sizeof *tmp);
        if (nt) tmp = nt;
        if (!nt) { r = spr__fail(run->err, SPR_E_NOMEM, "grad: out of memory for a tile of %u entries", len); break; }
        spr_grad_tile *tl = &out->tiles[out->n_tiles++];
        tl->tile = t, tl->entry = e, tl->first = out->n_terms;
        float part[SPR_GPART_FLOATS] = {0};
        const int i0 = (t % gx) * 16, j0 = (t / gx) * 16;
        for (int j = j0; j < j0 + 16 && j < H && !r; j++)
            for (int i = i0; i < i0 + 16 && i < W; i++) {
                const int y = H - 1 - j;
                spr_pixel_in px = {.grec = f.rec, .granges = f.range, .glist = f.list, .gup = up, .gpart = tmp, .gpart_base = first,
                                   .i = (size_t)y * W + (size_t)i, .x = i, .y = y};
                const float fi = (float)i, fj = (float)j;
                /* the pixel through the backend's own walk (spr_gauss_tile_bwd, a zeroed partial each entry): its terms,
                 * and in its state the blended entries with the α and T each was walked back with */
                memset(tmp, 0, (size_t)len * SPR_GPART_FLOATS * sizeof *tmp);
                static _Thread_local uint32_t state[SPR_GBS_FLOATS];
                memset(state, 0, SPR_GBS_SE * sizeof *state);
                px.gbs = state;
                spr_gauss_tile_bwd_all(&px, g, bg, t, (j - j0) * 16 + (i - i0), (j - j0) * 16 + (i - i0) + 1);
                if (state[SPR_GBS_OVER]) {
                    r = spr_gauss_bwd_over(run->err, "grad", gx, t, (int)state[SPR_GBS_OVER] - 1);
                    break;
                }
                const int nb = spr_gbs_i(&px, SPR_GBS_N);
                int rank = -1;
                for (int h = 0; h < nb && rank < 0; h++)
                    if (spr_gbs_i(&px, SPR_GBS_SE + h) == (int)e) rank = h;
                if (rank < 0) continue; /* G not blended here: no term */
                const float Tf = spr_gbs(&px, SPR_GBS_TF);
                if (out->n_terms == cap_terms) {
                    const size_t c2 = cap_terms ? 2 * cap_terms : 256;
                    spr_grad_term *nt2 = realloc(out->terms, c2 * sizeof *nt2);
                    if (!nt2) { r = spr__fail(run->err, SPR_E_NOMEM, "grad: out of memory for %zu pixels", c2); break; }
                    out->terms = nt2, cap_terms = c2;
                }
                spr_grad_term *tm = &out->terms[out->n_terms++];
                memset(tm, 0, sizeof *tm);
                tm->x = i, tm->y = y, tm->tile = t, tm->rank = rank, tm->blended = nb;
                memcpy(tm->part, tmp + (size_t)(e - first) * SPR_GPART_FLOATS, sizeof tm->part);
                /* the step's intermediates, as spr_gauss_blend_bwd computes them */
                const float *u = up + 5 * px.i;
                const float bgg = spr_sum3(bg[0], u[0], bg[1], u[1], bg[2], u[2]);
                const float bt = bgg - u[3];
                float acc[4] = {0, 0, 0, 0}, behind[5] = {0, 0, 0, 0, 0};
                for (int kk = nb - 1; kk >= rank; kk--) {
                    const float ob = 1.0f - behind[4];
                    for (int ch = 0; ch < 4; ch++) {
                        const float xx = behind[4] * behind[ch];
                        const float yy = ob * acc[ch];
                        acc[ch] = xx + yy;
                    }
                    if (kk == rank) break;
                    const int Gb = (int)f.list[spr_gbs_i(&px, SPR_GBS_SE + kk)];
                    for (int ch = 0; ch < 3; ch++) behind[ch] = spr_grec(&px, Gb, SPR_GREC_COLOR + ch);
                    behind[3] = spr_grec(&px, Gb, SPR_GREC_INVZ);
                    behind[4] = spr_gbs(&px, SPR_GBS_SA + kk);
                }
                float c[4], gk[4] = {u[0], u[1], u[2], u[4]};
                for (int ch = 0; ch < 3; ch++) c[ch] = spr_grec(&px, (int)G, SPR_GREC_COLOR + ch);
                c[3] = spr_grec(&px, (int)G, SPR_GREC_INVZ);
                const float alpha = spr_gbs(&px, SPR_GBS_SA + rank), TG = spr_gbs(&px, SPR_GBS_ST + rank);
                float d = 0.0f;
                for (int ch = 0; ch < 4; ch++) {
                    const float df = c[ch] - acc[ch];
                    const float dg = df * gk[ch];
                    d = d + dg;
                }
                const float td = TG * d, oma = 1.0f - alpha, tf = Tf / oma, tb = tf * bt, va = td - tb;
                const float og = spr_grec(&px, (int)G, SPR_GREC_OPACITY);
                const float power = spr_gauss_power(spr_grec(&px, (int)G, SPR_GREC_M), spr_grec(&px, (int)G, SPR_GREC_M + 1),
                                                    spr_grec(&px, (int)G, SPR_GREC_CONIC), spr_grec(&px, (int)G, SPR_GREC_CONIC + 1),
                                                    spr_grec(&px, (int)G, SPR_GREC_CONIC + 2), fi, fj);
                float vo = 0.0f, vp = 0.0f;
                spr_gauss_alpha_bwd(g, og, power, va, &vo, &vp);
                const float oe = og * spr_exp(power);
                tm->power = power, tm->alpha = alpha, tm->T = TG, tm->Tf = Tf, tm->dl_dalpha = va, tm->dl_do = vo, tm->dl_dpower = vp;
                memcpy(tm->acc, acc, sizeof acc);
                tm->gated = oe > g[SPR_GPRM_CAP] && g[SPR_GPRM_GATE] != 0.0f;
                if (!(vo == tm->part[SPR_GPART_OPACITY]) || tm->part[SPR_GPART_COUNT] != 1.0f) out->consistent = 0;
                for (int q = 0; q < SPR_GPART_FLOATS; q++) {
                    const float v = part[q] + tm->part[q];
                    part[q] = v;
                }
            }
        tl->count = out->n_terms - tl->first;
        memcpy(tl->part, part, sizeof part);
        for (int q = 0; q < SPR_GPART_FLOATS; q++) {
            const float v = out->sum[q] + part[q];
            out->sum[q] = v;
        }
    }
    spr__grad_fp_leave(fp);
done:
    free(image), free(up), free(tmp), free(start), free(csr);
    spr__gauss_frame_free(&f);
    return r;
}

typedef struct explain_ctx { size_t G; spr_grad_explain *out; } explain_ctx;
static spr_result explain_fn(spr__run *run, const spr_grad_desc *gd, void *user)
{
    explain_ctx *x = user;
    return explain_frame(run, gd, x->G, x->out);
}

spr_result spr_gauss_grad_explain(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc,
                                  const spr_grad_desc *gd, size_t G, spr_grad_explain *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    if (strcmp(b->name, "cpu"))
        return spr__fail(err, SPR_E_ARG, "grad: explain retraces the CPU backend's backward (its order of additions), not %s's", b->name);
    if (G >= cloud->n) return spr__fail(err, SPR_E_ARG, "grad: Gaussian %zu: the cloud has %zu (0 … %zu)", G, cloud->n, cloud->n ? cloud->n - 1 : 0);
    explain_ctx x = {G, out};
    const spr_result r = with_frame(b, view, cloud, desc, gd, explain_fn, &x, err);
    if (r) spr_grad_explain_free(out);
    return r;
}

int spr_gauss_grad_compare(const spr_gauss_grads *a, const spr_gauss_grads *b, spr_grad_diff *d, int cap)
{
    spr_grad_array aa[16], ba[16];
    const int na = spr_gauss_grads_arrays(a, aa, 16);
    spr_gauss_grads_arrays(b, ba, 16);
    int m = 0;
    for (int i = 0; i < na && m < cap; i++) {
        spr_grad_diff *o = &d[m++];
        memset(o, 0, sizeof *o);
        o->name = aa[i].name;
        o->first = -1;
        const int per = aa[i].per, off = !strcmp(aa[i].name, "shN") ? 3 : 0, stride = aa[i].data == a->sh ? 3 * a->sh_k : per;
        for (size_t G = 0; G < a->n && G < b->n; G++) {
            int differ = 0;
            if (!aa[i].data) differ = a->counts[G] != b->counts[G];
            else differ = memcmp(aa[i].data + G * (size_t)stride + (size_t)off, ba[i].data + G * (size_t)stride + (size_t)off, (size_t)per * sizeof(float)) != 0;
            if (differ) {
                if (o->first < 0) {
                    o->first = (long)G;
                    for (int k = 0; k < per && k < 4; k++) {
                        o->va[k] = aa[i].data ? aa[i].data[G * (size_t)stride + (size_t)off + (size_t)k] : (float)a->counts[G];
                        o->vb[k] = ba[i].data ? ba[i].data[G * (size_t)stride + (size_t)off + (size_t)k] : (float)b->counts[G];
                    }
                }
                o->differing++;
            }
        }
        o->gaussians = a->n;
    }
    return m;
}
