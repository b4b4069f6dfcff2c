/* gauss.c — what the Gaussian splatting references share (SPEC §10): the
 * frame's parameters from the view and the options, the Gaussians of the
 * cloud (a capture's own, or each surfel seen as a flat Gaussian), their
 * colours, and the host's sorting — per-tile lists for gauss3d and gauss2d,
 * the back-to-front order of gauss-blend — then the passes:
 *
 *   "preprocess"  the backend: one record per Gaussian (SPEC 10.3; 10.5)
 *   "sort"        the host: every kept Gaussian into each 16×16 tile its
 *                 rectangle covers, in file order, then each tile's list
 *                 sorted by t.z (a stable radix sort: ties keep file order);
 *                 gauss-blend: the kept Gaussians by |μ − eye|, farthest
 *                 first, ties in file order
 *   "raster"      the backend: every pixel's front-to-back loop (SPEC 10.4)
 *   "blend"       gauss-blend: the ellipses drawn in that order (SPEC 10.7)
 *
 * Sorting is host code shared by both backends, as SPEC §10 allows; every
 * float operation that reaches a plane runs in the backend, in the shared
 * arithmetic (core/render/arith/gauss.h).
 */
#include "spr_algo.h"
#include "spr_util.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* SPEC §10.2: the view's pinhole rounded to float once; the flavour's constants. */
static void frame_params(const spr_view *v, int mode, const spr_render_desc *desc, float *g)
{
    const spr_pinhole *p = &v->cv;
    memset(g, 0, SPR_GPRM_COUNT * sizeof *g);
    for (int i = 0; i < 9; i++) g[SPR_GPRM_R + i] = (float)p->R[i];
    for (int i = 0; i < 3; i++) g[SPR_GPRM_T + i] = (float)p->t[i];
    g[SPR_GPRM_FX] = (float)p->fx;
    g[SPR_GPRM_FY] = (float)p->fy;
    g[SPR_GPRM_CX] = (float)(p->cx - 0.5); /* pixel-index coordinates: pixel i's centre at i */
    g[SPR_GPRM_CY] = (float)(p->cy - 0.5);
    /* the training code: tan(fov/2) in double, rounded to float, then 1.3f times it in float */
    const float tanx = (float)(0.5 * v->width / p->fx), tany = (float)(0.5 * v->height / p->fy);
    g[SPR_GPRM_LX] = 1.3f * tanx;
    g[SPR_GPRM_LY] = 1.3f * tany;
    g[SPR_GPRM_W] = (float)v->width;
    g[SPR_GPRM_H] = (float)v->height;
    g[SPR_GPRM_GX] = (float)((v->width + 15) / 16);
    g[SPR_GPRM_GY] = (float)((v->height + 15) / 16);
    const int gsplat = desc->gauss_flavor == SPR_FLAVOR_GSPLAT;
    g[SPR_GPRM_NEAR] = gsplat ? 0.01f : 0.2f;
    g[SPR_GPRM_NEAR_LT] = gsplat ? 1.0f : 0.0f;
    g[SPR_GPRM_EPS2D] = 0.3f;
    g[SPR_GPRM_DET_LE] = gsplat ? 1.0f : 0.0f;
    g[SPR_GPRM_AA] = desc->gauss_aa ? 1.0f : 0.0f;
    g[SPR_GPRM_AA_MIN] = gsplat ? 0.0f : 0.000025f;
    g[SPR_GPRM_EXT_MIN] = 0.1f;
    g[SPR_GPRM_EXT2D_MIN] = 1e-4f;
    g[SPR_GPRM_R2D_MIN] = 3.0f * 0.707106f; /* hbb1: cutoff · FilterSize, in float */
    g[SPR_GPRM_CAP] = gsplat ? 0.999f : 0.99f;
    g[SPR_GPRM_ALPHA_MIN] = 1.0f / 255.0f;
    /* ln(1/255) − 0.01: e^power is then below 0.99/255, which spr_exp's 1 ulp cannot lift to 1/255, so the
     * skip of SPEC 10.4 is decided without the exponential (an o ≤ 1 only; the note still gives α) */
    g[SPR_GPRM_POWER_MIN] = (float)(log(1.0 / 255.0) - 0.01);
    g[SPR_GPRM_T_MIN] = 0.0001f;
    g[SPR_GPRM_STOP_LE] = gsplat ? 1.0f : 0.0f;
    g[SPR_GPRM_MODE] = mode == 1 ? SPR_GMODE_2D : SPR_GMODE_3D;
}

spr_result spr__gauss_of_cloud(const spr_cloud *c, float *q, float *s)
{
#pragma omp parallel for schedule(static)
    for (long li = 0; li < (long)c->n; li++) {
        const size_t i = (size_t)li;
        if (c->gauss) {
            const float *G = c->gauss + SPR_GAUSS_FLOATS * i;
            memcpy(q + 4 * i, G, 4 * sizeof *q);
            memcpy(s + 3 * i, G + 4, 3 * sizeof *s);
            continue;
        }
        /* a surfel as a flat Gaussian: σ a third of its radii along (u, v), 0 along n (the gauss kernel's σ, SPEC 3.1) */
        double qd[4], ru, rv;
        spr__surfel_frame(c, i, qd, &ru, &rv);
        for (int k = 0; k < 4; k++) q[4 * i + k] = (float)qd[k];
        s[3 * i] = (float)(ru / 3.0), s[3 * i + 1] = (float)(rv / 3.0), s[3 * i + 2] = 0.0f;
    }
    return SPR_OK;
}

/* ---- the host's sorting ---- */

static uint32_t depth_key(const float *rec, uint32_t G)
{
    uint32_t k;
    memcpy(&k, rec + (size_t)G * SPR_GREC_FLOATS + SPR_GREC_DEPTH, 4); /* t.z > 0: the bits order as the values */
    return k;
}

/* Sort a[0 … m−1] (Gaussian ids in file order) by t.z, stably (LSD radix
 * on the float's bits, 8 bits a pass; insertion sort for short lists). */
static void sort_tile(const float *rec, uint32_t *a, uint32_t m, uint32_t *tmp)
{
    if (m < 48) {
        for (uint32_t i = 1; i < m; i++) {
            uint32_t x = a[i], kx = depth_key(rec, x), j = i;
            while (j > 0 && depth_key(rec, a[j - 1]) > kx) a[j] = a[j - 1], j--;
            a[j] = x;
        }
        return;
    }
    for (int shift = 0; shift < 32; shift += 8) {
        uint32_t cnt[257] = {0};
        for (uint32_t i = 0; i < m; i++) cnt[(depth_key(rec, a[i]) >> shift & 255u) + 1]++;
        for (int b = 0; b < 256; b++) cnt[b + 1] += cnt[b];
        for (uint32_t i = 0; i < m; i++) tmp[cnt[depth_key(rec, a[i]) >> shift & 255u]++] = a[i];
        memcpy(a, tmp, m * sizeof *a);
    }
}

/* A Gaussian's tiles: its record's rectangle, none when culled. */
static void record_tiles(const void *user, size_t G, int r[4])
{
    const float *R = (const float *)user + G * SPR_GREC_FLOATS;
    for (int k = 0; k < 4; k++) r[k] = R[SPR_GREC_CULL] == SPR_GCULL_NONE ? (int)R[SPR_GREC_RECT + k] : 0;
}

spr_result spr__gauss_tiles(const float *rec, size_t n, int gx, int gy, int threads, uint32_t **range_out, uint32_t **list_out, spr_error *err)
{
    const size_t nt = (size_t)gx * gy;
    if (threads <= 0) threads = omp_get_max_threads();
    uint32_t *range = NULL, *list = NULL;
    spr_result br = spr__gauss_bin(n, record_tiles, rec, gx, gy, threads, &range, &list, err);
    if (br) return br;
    int failed = 0;
#pragma omp parallel num_threads(threads) reduction(| : failed)
    {
        uint32_t *tmp = NULL;
        size_t cap = 0;
#pragma omp for schedule(dynamic, 8)
        for (long t = 0; t < (long)nt; t++) {
            const uint32_t m = range[t + 1] - range[t];
            if (m > cap) {
                free(tmp);
                cap = m;
                if (!(tmp = malloc(cap * sizeof *tmp))) cap = 0, failed = 1;
            }
            if (cap >= m) sort_tile(rec, list + range[t], m, tmp);
        }
        free(tmp);
    }
    if (failed) {
        free(range), free(list);
        return spr__fail(err, SPR_E_NOMEM, "gauss: out of memory sorting the tiles");
    }
    *range_out = range;
    *list_out = list;
    return SPR_OK;
}

spr_result spr__gauss_order(const float *rec, const spr_cloud *c, const double eye[3], uint32_t **order_out, size_t *count, spr_error *err)
{
    uint64_t *key = spr__big_alloc(c->n * sizeof *key);
    uint32_t *order = spr__big_alloc(c->n * sizeof *order);
    if (!key || !order) {
        free(key), free(order);
        return spr__fail(err, SPR_E_NOMEM, "gauss-blend: out of memory ordering %zu Gaussians", c->n);
    }
    size_t m = 0;
    for (size_t G = 0; G < c->n; G++) {
        const float *R = rec + G * SPR_GREC_FLOATS;
        if (R[SPR_GREC_CULL] != SPR_GCULL_NONE || R[SPR_GREC_BOX + 2] < R[SPR_GREC_BOX] || R[SPR_GREC_BOX + 3] < R[SPR_GREC_BOX + 1]) continue;
        double d2 = 0.0;
        for (int a = 0; a < 3; a++) d2 += ((double)c->pos[3 * G + a] - eye[a]) * ((double)c->pos[3 * G + a] - eye[a]);
        const double d = sqrt(d2);
        uint64_t bits;
        memcpy(&bits, &d, sizeof bits); /* d ≥ 0: the bits order as the values */
        key[m] = ~bits, order[m] = (uint32_t)G, m++; /* farthest first; a stable sort keeps equal distances in file order */
    }
    const int bad = spr__radix_sort_u64(key, order, m);
    free(key);
    if (bad) {
        free(order);
        return spr__fail(err, SPR_E_NOMEM, "gauss-blend: out of memory ordering %zu Gaussians", c->n);
    }
    *order_out = order;
    *count = m;
    return SPR_OK;
}

/* ---- the passes ---- */

spr_result spr__gauss_run(spr__run *run, int mode, int *final_target)
{
    const spr_cloud *c = run->cloud;
    const spr_view *v = &run->b->view;
    const char *name = spr_algo_name(run->desc->algo);
    if (v->ortho)
        return spr__fail(run->err, SPR_E_ARG, "%s: orthographic cameras are refused (SPEC 10.2): the training code's camera is a pinhole", name);
    const size_t n = c->n;
    spr_gauss_desc gd = {.n = n, .mu = c->pos, .opacity = c->alpha};
    frame_params(v, mode, run->desc, gd.prm);
    float *q = spr__big_alloc(n * 4 * sizeof *q), *s = spr__big_alloc(n * 3 * sizeof *s), *col = spr__big_alloc(n * 3 * sizeof *col);
    float *rec = spr__big_alloc(n * SPR_GREC_FLOATS * sizeof *rec);
    uint32_t *range = NULL, *list = NULL, *order = NULL;
    int target = -1;
    spr_result r = q && s && col && rec ? SPR_OK : spr__fail(run->err, SPR_E_NOMEM, "%s: out of memory for %zu Gaussians", name, n);
    double eye[3];
    const spr_pinhole *p = &v->cv;
    for (int k = 0; k < 3; k++) eye[k] = -(p->R[k] * p->t[0] + p->R[3 + k] * p->t[1] + p->R[6 + k] * p->t[2]);
    if (!r) {
        spr__gauss_of_cloud(c, q, s);
        spr_cloud_gauss_colors(c, eye, col); /* SPEC 10.3 step 9: on the host, in double, rounded once */
        gd.q = q, gd.s = s, gd.color = col;
        r = spr__run_gauss_preprocess(run, &gd, rec);
    }
    const int threads = run->b->host_threads; /* the lists do not depend on it */
    double t0 = spr_now_ms();
    if (!r && mode != 2) r = spr__gauss_tiles(rec, n, (int)gd.prm[SPR_GPRM_GX], (int)gd.prm[SPR_GPRM_GY], threads, &range, &list, run->err);
    size_t count = 0;
    if (!r && mode == 2) r = spr__gauss_order(rec, c, eye, &order, &count, run->err);
    if (!r) {
        const size_t tiles = (size_t)gd.prm[SPR_GPRM_GX] * (size_t)gd.prm[SPR_GPRM_GY];
        spr_draw_stats st = {n, mode == 2 ? count : range[tiles], 0};
        r = spr__run_host_pass(run, "sort", &st, spr_now_ms() - t0);
    }
    if (!r && mode != 2) {
        if (!(r = spr__run_target(run, mode == 1 ? SPR_PLANES_GAUSS2D : SPR_PLANES_GAUSS3D, &target))) {
            spr_gauss_raster_desc rd = {rec, n, range, list, {0, 0, 0}, {0}};
            memcpy(rd.background, run->desc->background, sizeof rd.background);
            memcpy(rd.prm, gd.prm, sizeof rd.prm);
            r = spr__run_gauss_raster(run, "raster", target, &rd);
        }
    } else if (!r) {
        if (!(r = spr__run_target(run, SPR_PLANE_BIT(SPR_PLANE_COLOR), &target))) {
            const float *bg = run->desc->background;
            const float clear[4] = {bg[0], bg[1], bg[2], 0.0f};
            if ((r = spr_backend_clear(run->b, target, clear))) r = spr__fail(run->err, r, "%s backend: %s", run->b->name, run->b->err.msg);
        }
        if (!r) {
            spr_gauss_draw_desc dd = {rec, n, order, count, {0}, {0}};
            spr_pass_state_defaults(&dd.state);
            dd.state.depth_func = SPR_FUNC_ALWAYS;
            spr_pass_state_blend(&dd.state, SPR_BLEND_PREMUL);
            dd.state.write_mask = SPR_WRITE_COLOR;
            memcpy(dd.prm, gd.prm, sizeof dd.prm);
            r = spr__run_gauss_draw(run, "blend", target, &dd);
        }
    }
    free(q), free(s), free(col), free(rec), free(range), free(list), free(order);
    if (!r) *final_target = target;
    return r;
}
