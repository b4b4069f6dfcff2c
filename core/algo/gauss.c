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

/* SPEC §10.2: the view's pinhole rounded to float once; the profile's rules (§10.9) as parameters. */
void spr__gauss_frame(const spr_view *v, int mode, const spr_render_desc *desc, const spr_gauss_profile *pf, float *g)
{
    const spr_pinhole *p = &v->cv;
    memset(g, 0, SPR_GPRM_COUNT * sizeof *g);
    for (int i = 0; i < 9; i++) g[SPR_GPRM_R + i] = (float)p->R[i];
    for (int i = 0; i < 3; i++) g[SPR_GPRM_T + i] = (float)p->t[i];
    g[SPR_GPRM_FX] = (float)p->fx;
    g[SPR_GPRM_FY] = (float)p->fy;
    /* rule 11: a renderer that ignores the principal point draws about the image's centre */
    const double pcx = pf->camera.centre ? 0.5 * v->width : p->cx, pcy = pf->camera.centre ? 0.5 * v->height : p->cy;
    g[SPR_GPRM_CX] = (float)(pcx - 0.5); /* pixel-index coordinates: pixel i's centre at i */
    g[SPR_GPRM_CY] = (float)(pcy - 0.5);
    /* the training code: tan(fov/2) in double, rounded to float, then 1.3f times it in float */
    const float tanx = (float)(0.5 * v->width / p->fx), tany = (float)(0.5 * v->height / p->fy);
    g[SPR_GPRM_LX] = g[SPR_GPRM_LXN] = 1.3f * tanx;
    g[SPR_GPRM_LY] = g[SPR_GPRM_LYN] = 1.3f * tany;
    if (pf->tan_clamp == 2) { /* gsplat: from the principal point (continuous), in float: (W − cx)/fx + 0.3·tan, cx/fx + 0.3·tan */
        const float W = (float)v->width, H = (float)v->height, fx = (float)p->fx, fy = (float)p->fy, cx = (float)pcx, cy = (float)pcy;
        const float ex = 0.3f * tanx, ey = 0.3f * tany;
        g[SPR_GPRM_LX] = (W - cx) / fx + ex, g[SPR_GPRM_LXN] = cx / fx + ex;
        g[SPR_GPRM_LY] = (H - cy) / fy + ey, g[SPR_GPRM_LYN] = cy / fy + ey;
    }
    g[SPR_GPRM_W] = (float)v->width;
    g[SPR_GPRM_H] = (float)v->height;
    g[SPR_GPRM_GX] = (float)((v->width + 15) / 16);
    g[SPR_GPRM_GY] = (float)((v->height + 15) / 16);
    /* rule 1: a negative near is the camera's own near plane (the viewers clip there) */
    g[SPR_GPRM_NEAR] = pf->cull.near < 0.0f ? (float)v->near_plane : pf->cull.near;
    g[SPR_GPRM_NEAR_LT] = (float)pf->cull.near_lt;
    g[SPR_GPRM_CLIP_K] = pf->cull.clip_k;
    g[SPR_GPRM_NDC] = (float)(2.0 * p->fx / v->width); /* clip x/w = (2fx/W)·(t.x/t.z) + (2cx/W − 1), cx continuous */
    g[SPR_GPRM_NDC + 1] = (float)(2.0 * pcx / v->width - 1.0);
    g[SPR_GPRM_NDC + 2] = (float)(2.0 * p->fy / v->height);
    g[SPR_GPRM_NDC + 3] = (float)(2.0 * pcy / v->height - 1.0);
    g[SPR_GPRM_DET_LE] = (float)pf->cull.det_le;
    g[SPR_GPRM_TCLAMP] = pf->tan_clamp ? 1.0f : 0.0f; /* rule 2 */
    g[SPR_GPRM_EPS2D] = pf->dilation.eps2d;    /* rule 3 */
    g[SPR_GPRM_AA] = desc->gauss_aa || pf->dilation.when == SPR_GCOMP_ALWAYS ? 1.0f : 0.0f;
    g[SPR_GPRM_AA_MIN] = pf->dilation.floor;
    g[SPR_GPRM_AA_FORM] = (float)pf->dilation.form;
    g[SPR_GPRM_EXT] = (float)pf->extent.kind; /* rule 4 */
    g[SPR_GPRM_EXT_K] = (float)sqrt(pf->extent.k2);
    g[SPR_GPRM_EXT_CAP] = pf->extent.cap_px;
    if (pf->extent.cap_view) { /* PlayCanvas: a half-axis at most min(1024, W, H) */
        if (g[SPR_GPRM_EXT_CAP] > (float)v->width) g[SPR_GPRM_EXT_CAP] = (float)v->width;
        if (g[SPR_GPRM_EXT_CAP] > (float)v->height) g[SPR_GPRM_EXT_CAP] = (float)v->height;
    }
    g[SPR_GPRM_EXT_MIN] = pf->extent.lambda_min;
    g[SPR_GPRM_EXT_PAD] = pf->extent.pad_px;
    g[SPR_GPRM_MIN_PX] = pf->extent.min_px;
    g[SPR_GPRM_CUT] = (float)(0.5 * pf->extent.k2); /* power < −k²/2: outside k standard deviations */
    g[SPR_GPRM_FALLOFF] = (float)pf->extent.falloff;
    g[SPR_GPRM_STRAIGHT] = pf->blend == SPR_GBLEND_STRAIGHT ? 1.0f : 0.0f; /* rule 8 */
    g[SPR_GPRM_EXT2D_MIN] = 1e-4f;
    g[SPR_GPRM_R2D_MIN] = 3.0f * 0.707106f; /* hbb1: cutoff · FilterSize, in float */
    g[SPR_GPRM_CAP] = pf->alpha.cap; /* rule 5 */
    g[SPR_GPRM_ALPHA_MIN] = pf->alpha.floor;
    /* ln(floor) − 0.01: e^power is then below 0.99·floor, which spr_exp's 1 ulp cannot lift to the floor, so the
     * skip of SPEC 10.4 is decided without the exponential (an o ≤ 1 only; the note still gives α); no floor:
     * never (spr_exp is 0 below −87 anyway) */
    g[SPR_GPRM_POWER_MIN] = pf->alpha.floor > 0.0f ? (float)(log((double)pf->alpha.floor) - 0.01) : -1e30f;
    g[SPR_GPRM_T_MIN] = pf->stop.t_min; /* rule 6 */
    g[SPR_GPRM_STOP_LE] = (float)pf->stop.le;
    g[SPR_GPRM_MODE] = mode == 1 ? SPR_GMODE_2D : SPR_GMODE_3D;
    g[SPR_GPRM_GATE] = (float)pf->grad.gate; /* the backward rules (SPEC 10.10 item 3) */
    g[SPR_GPRM_TCLAMP_BWD] = (float)pf->grad.tclamp;
    g[SPR_GPRM_CAP_BWD] = pf->grad.cap;
    g[SPR_GPRM_TDIV] = (float)pf->grad.tdiv;
    g[SPR_GPRM_HALF_B] = (float)pf->grad.half_b;
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

static uint32_t depth_key(const float *rec, const uint32_t *keys, uint32_t G)
{
    if (keys) return keys[G];
    uint32_t k;
    memcpy(&k, rec + (size_t)G * SPR_GREC_FLOATS + SPR_GREC_DEPTH, 4); /* t.z > 0: the bits order as the values */
    return k;
}

/* Sort a[0 … m−1] (Gaussian ids in file order) by t.z (keys: by keys[G]), stably (LSD radix
 * on the float's bits, 8 bits a pass; insertion sort for short lists). */
static void sort_tile(const float *rec, const uint32_t *keys, uint32_t *a, uint32_t m, uint32_t *tmp)
{
    if (m < 48) {
        for (uint32_t i = 1; i < m; i++) {
            uint32_t x = a[i], kx = depth_key(rec, keys, x), j = i;
            while (j > 0 && depth_key(rec, keys, a[j - 1]) > kx) a[j] = a[j - 1], j--;
            a[j] = x;
        }
        return;
    }
    for (int shift = 0; shift < 32; shift += 8) {
        uint32_t cnt[257] = {0};
        for (uint32_t i = 0; i < m; i++) cnt[(depth_key(rec, keys, a[i]) >> shift & 255u) + 1]++;
        for (int b = 0; b < 256; b++) cnt[b + 1] += cnt[b];
        for (uint32_t i = 0; i < m; i++) tmp[cnt[depth_key(rec, keys, a[i]) >> shift & 255u]++] = a[i];
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
    return spr__gauss_tiles_keyed(rec, NULL, n, gx, gy, threads, range_out, list_out, err);
}

/* SPR_GKEY_TILE_GLDEPTH (spr_algo.h): OpenSplat's float OpenGL depth of each Gaussian, as an unsigned key that orders
 * as the float does (negative keys below positive ones); read off its projection of znear, zfar times the float
 * world-to-camera of g, over the centres mu and the records' float t.z.  Every operation is one float operation
 * (-ffp-contract=off), in the order torch evaluates it, so the keys are its camDepths bit for bit. */
static void gldepth_keys(const float *g, const float *mu, const float *rec, size_t n, float zn, float zf, uint32_t *keys)
{
    const float fpn = zf + zn, fmn = zf - zn, a = fpn / fmn, mfz = -1.0f * zf, mfn = mfz * zn, b = mfn / fmn;
    const float p0 = a * g[SPR_GPRM_R + 6], p1 = a * g[SPR_GPRM_R + 7], p2 = a * g[SPR_GPRM_R + 8], at = a * g[SPR_GPRM_T + 2], p3 = at + b;
#pragma omp parallel for schedule(static)
    for (long li = 0; li < (long)n; li++) {
        const size_t G = (size_t)li;
        const float *m = mu + 3 * G;
        const float x = p0 * m[0], y = p1 * m[1], z = p2 * m[2], xy = x + y, xyz = xy + z, zc = xyz + p3;
        float w = rec[G * SPR_GREC_FLOATS + SPR_GREC_DEPTH];
        if (!(w >= 1e-6f)) w = 1e-6f; /* torch's clamp_min (a culled record's t.z is 0) */
        const float rw = 1.0f / w, key = zc * rw;
        uint32_t u;
        memcpy(&u, &key, 4);
        keys[G] = u & 0x80000000u ? ~u : u | 0x80000000u;
    }
}

spr_result spr__gauss_tiles_keyed(const float *rec, const uint32_t *keys, size_t n, int gx, int gy, int threads, uint32_t **range_out,
                                  uint32_t **list_out, spr_error *err)
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
            if (cap >= m) sort_tile(rec, keys, list + range[t], m, tmp);
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

/* gauss-blend's order (profile rule 7): every kept Gaussian (not culled, a non-empty box) farthest first under the
 * profile's key, a stable sort (equal keys in file order):
 *   distance  |μ − eye| in double;
 *   view z    the record's float t.z;
 *   clip int  GaussianSplats3D's integer depth: K = Σ_a round(1000·μ_a)·trunc(1000·Z_a), Z the clip-z row of the
 *             camera's projection times its view (zrow, double; no translation), K whole numbers in double; then
 *             2^bits − 1 buckets over the kept Gaussians' [Kmin, Kmax] in float: (int)(((float)(K − Kmin)·
 *             (float)(2^bits − 1))/(float)(Kmax − Kmin)) (one bucket when Kmax = Kmin). */
spr_result spr__gauss_order(const float *rec, const spr_cloud *c, const double eye[3], const double zrow[3], spr_gauss_key key, int bits,
                            uint32_t **order_out, size_t *count, spr_error *err)
{
    uint64_t *k = spr__big_alloc(c->n * sizeof *k);
    uint32_t *order = spr__big_alloc(c->n * sizeof *order);
    if (!k || !order) {
        free(k), free(order);
        return spr__fail(err, SPR_E_NOMEM, "gauss-blend: out of memory ordering %zu Gaussians", c->n);
    }
    size_t m = 0;
    /* the integer depth in double: whole numbers, exact below 2^53 (each centre rounded and clamped to ±10^12
     * thousandths, each row entry a few thousand) */
    double kmin = INFINITY, kmax = -INFINITY, *kd = key == SPR_GKEY_CLIP_INT ? spr__big_alloc(c->n * sizeof *kd) : NULL, zi[3];
    if (key == SPR_GKEY_CLIP_INT && !kd) {
        free(k), free(order);
        return spr__fail(err, SPR_E_NOMEM, "gauss-blend: out of memory ordering %zu Gaussians", c->n);
    }
    for (int a = 0; a < 3; a++) zi[a] = trunc(1000.0 * zrow[a]);
    for (size_t G = 0; G < c->n; G++) {
        const float *R = rec + G * SPR_GREC_FLOATS;
        if (R[SPR_GREC_CULL] != SPR_GCULL_NONE || R[SPR_GREC_BOX + 2] < R[SPR_GREC_BOX] || R[SPR_GREC_BOX + 3] < R[SPR_GREC_BOX + 1]) continue;
        order[m] = (uint32_t)G;
        if (kd) {
            double K = 0.0;
            for (int a = 0; a < 3; a++) {
                double r = round(1000.0 * (double)c->pos[3 * G + a]);
                r = r < -1e12 ? -1e12 : r > 1e12 ? 1e12 : r;
                K += r * zi[a];
            }
            kd[m] = K;
            if (K < kmin) kmin = K;
            if (K > kmax) kmax = K;
        }
        m++;
    }
    const float levels = (float)(ldexp(1.0, bits) - 1.0), span = kd && m ? (float)(kmax - kmin) : 0.0f;
    for (size_t e = 0; e < m; e++) {
        const size_t G = order[e];
        double d;
        if (key == SPR_GKEY_VIEW_Z) d = rec[G * SPR_GREC_FLOATS + SPR_GREC_DEPTH];
        else if (kd) {
            const float dk = (float)(kd[e] - kmin), scaled = dk * levels;
            d = kmax > kmin ? (double)(int)(scaled / span) : 0.0;
        } else {
            double d2 = 0.0;
            for (int a = 0; a < 3; a++) d2 += ((double)c->pos[3 * G + a] - eye[a]) * ((double)c->pos[3 * G + a] - eye[a]);
            d = sqrt(d2);
        }
        uint64_t bits64;
        memcpy(&bits64, &d, sizeof bits64); /* d ≥ 0 (t.z > 0 for kept Gaussians): the bits order as the values */
        k[e] = ~bits64; /* farthest first; a stable sort keeps equal keys in file order */
    }
    free(kd);
    const int bad = spr__radix_sort_u64(k, order, m);
    free(k);
    if (bad) {
        free(order);
        return spr__fail(err, SPR_E_NOMEM, "gauss-blend: out of memory ordering %zu Gaussians", c->n);
    }
    *order_out = order;
    *count = m;
    return SPR_OK;
}

/* ---- the passes ---- */

spr_result spr__gauss_prepare(spr__run *run, int mode, spr__gauss_frame_st *f)
{
    const spr_cloud *c = run->cloud;
    const spr_view *v = &run->b->view;
    const char *name = spr_algo_name(run->desc->algo);
    memset(f, 0, sizeof *f);
    if (v->ortho)
        return spr__fail(run->err, SPR_E_ARG, "%s: orthographic cameras are refused (SPEC 10.2): the training code's camera is a pinhole", name);
    const size_t n = c->n;
    const spr_gauss_profile *pf = f->pf = spr_gauss_profile_of(run->desc->algo, run->desc->gauss_profile);
    if (!spr_gauss_profile_fits(pf, run->desc->algo))
        return spr__fail(run->err, SPR_E_ARG, "%s: profile %s belongs to %s (SPEC 10.9)", name, pf->name, spr_algo_name(pf->skeleton));
    spr_gauss_desc *gd = &f->gd;
    *gd = (spr_gauss_desc){.n = n, .mu = c->pos, .opacity = c->alpha};
    spr__gauss_frame(v, mode, run->desc, pf, gd->prm);
    f->q = spr__big_alloc(n * 4 * sizeof *f->q), f->s = spr__big_alloc(n * 3 * sizeof *f->s), f->col = spr__big_alloc(n * 3 * sizeof *f->col);
    const int stores = spr_gauss_profile_stores(pf); /* rule 9: the renderer's own storage of centres and opacities */
    f->mu = stores ? spr__big_alloc(n * 3 * sizeof *f->mu) : NULL, f->op = stores ? spr__big_alloc(n * sizeof *f->op) : NULL;
    f->rec = spr__big_alloc(n * SPR_GREC_FLOATS * sizeof *f->rec);
    spr_result r = f->q && f->s && f->col && f->rec && (!stores || (f->mu && f->op)) ? SPR_OK : spr__fail(run->err, SPR_E_NOMEM, "%s: out of memory for %zu Gaussians", name, n);
    double eye[3];
    spr_pinhole_eye(&v->cv, eye);
    if (!r) {
        spr__gauss_of_cloud(c, f->q, f->s);
        /* SPEC 10.3 step 9 under the profile's colour rule: on the host, in double, rounded once */
        spr_cloud_gauss_colors_as(c, eye, pf->colour.sh_max, pf->colour.dc8, pf->colour.post8, pf->colour.clamp_hi, f->col);
        if (stores) {
#pragma omp parallel for schedule(static)
            for (long i = 0; i < (long)n; i++) spr_gauss_profile_store(pf, c, (size_t)i, eye, f->s + 3 * i, f->mu + 3 * i, f->op + i);
            gd->mu = f->mu, gd->opacity = f->op;
        }
        gd->q = f->q, gd->s = f->s, gd->color = f->col;
        r = spr__run_gauss_preprocess(run, gd, f->rec);
    }
    const int threads = run->b->host_threads; /* the lists do not depend on it */
    double t0 = spr_now_ms();
    uint32_t *keys = NULL;
    if (!r && mode != 2 && pf->order.key == SPR_GKEY_TILE_GLDEPTH) { /* rule 7: the renderer's own depth key */
        if (!(keys = spr__big_alloc((n ? n : 1) * sizeof *keys))) r = spr__fail(run->err, SPR_E_NOMEM, "%s: out of memory for %zu keys", name, n);
        else gldepth_keys(gd->prm, gd->mu, f->rec, n, pf->order.znear, pf->order.zfar, keys);
    }
    if (!r && mode != 2)
        r = spr__gauss_tiles_keyed(f->rec, keys, n, (int)gd->prm[SPR_GPRM_GX], (int)gd->prm[SPR_GPRM_GY], threads, &f->range, &f->list, run->err);
    free(keys);
    if (!r && mode == 2) {
        const double zrow[3] = {v->PV[8], v->PV[9], v->PV[10]}; /* clip z = row 2 of P·V (GL's convention) */
        r = spr__gauss_order(f->rec, c, eye, zrow, pf->order.key, pf->order.bits, &f->order, &f->count, run->err);
    }
    if (!r) {
        const size_t tiles = (size_t)gd->prm[SPR_GPRM_GX] * (size_t)gd->prm[SPR_GPRM_GY];
        spr_draw_stats st = {n, mode == 2 ? f->count : f->range[tiles], 0};
        r = spr__run_host_pass(run, "sort", &st, spr_now_ms() - t0);
    }
    if (r) spr__gauss_frame_free(f);
    return r;
}

void spr__gauss_frame_free(spr__gauss_frame_st *f)
{
    free(f->q), free(f->s), free(f->col), free(f->mu), free(f->op), free(f->rec), free(f->range), free(f->list), free(f->order);
    memset(f, 0, sizeof *f);
}

spr_result spr__gauss_raster_frame(spr__run *run, int mode, const spr__gauss_frame_st *f, int *target)
{
    spr_result r = spr__run_target(run, mode == 1 ? SPR_PLANES_GAUSS2D : SPR_PLANES_GAUSS3D, target);
    if (r) return r;
    spr_gauss_raster_desc rd = {f->rec, f->gd.n, f->range, f->list, {0, 0, 0}, {0}};
    memcpy(rd.background, run->desc->background, sizeof rd.background);
    memcpy(rd.prm, f->gd.prm, sizeof rd.prm);
    return spr__run_gauss_raster(run, "raster", *target, &rd);
}

spr_result spr__gauss_run(spr__run *run, int mode, int *final_target)
{
    spr__gauss_frame_st f;
    spr_result r = spr__gauss_prepare(run, mode, &f);
    if (r) return r;
    int target = -1;
    if (mode != 2) r = spr__gauss_raster_frame(run, mode, &f, &target);
    else {
        if (!(r = spr__run_target(run, SPR_PLANE_BIT(SPR_PLANE_COLOR), &target))) {
            const float *bg = run->desc->background;
            const float clear[4] = {bg[0], bg[1], bg[2], 0.0f};
            if ((r = spr_backend_clear(run->b, target, clear))) r = spr__fail(run->err, r, "%s backend: %s", run->b->name, run->b->err.msg);
        }
        if (!r) {
            spr_gauss_draw_desc dd = {f.rec, f.gd.n, f.order, f.count, {0}, {0}};
            spr_pass_state_defaults(&dd.state);
            dd.state.depth_func = SPR_FUNC_ALWAYS;
            spr_pass_state_blend(&dd.state, SPR_BLEND_PREMUL); /* rule 8: premultiplied over */
            if (f.pf->blend == SPR_GBLEND_STRAIGHT) dd.state.blend = SPR_BLEND_OVER; /* straight: rgb (SRC_ALPHA, ONE_MINUS_SRC_ALPHA) */
            dd.state.write_mask = SPR_WRITE_COLOR;
            memcpy(dd.prm, f.gd.prm, sizeof dd.prm);
            r = spr__run_gauss_draw(run, "blend", target, &dd);
        }
    }
    spr__gauss_frame_free(&f);
    if (!r) *final_target = target;
    return r;
}
