/* prims.c — domain primitives of one level (SPEC §7.3–7.5, §7.7): the
 * domains of a basis, each with at least 3 points, become textured support
 * rectangles (spr_rects, the primitive of the backend interface), with the
 * neighbour relation of the overlap and prefix methods: a and b are
 * neighbours when their shared points exceed `nbr_ratio` of either
 * domain's points ([R] §4.4.4).  Domains are built in parallel, each into
 * its own slot, and packed in domain order: the result does not depend on
 * the thread count. */
#include "spr_domain.h"

#include <stdlib.h>
#include <string.h>

void spr_prims_defaults(spr_prims_desc *d)
{
    memset(d, 0, sizeof *d);
    d->K = 0.01;
    d->enlarge = 0.05;
    d->tex.texel_factor = 1.0;
    d->tex.width = 1.0;
    d->tex.shape = SPR_RBF_LINEAR;
    d->tex.normalize = SPR_NORM_GT0;
    d->nbr_ratio = 0.05;
}

/* 2^25 texels a level (512 MiB of RGBA floats): the bunny's finest level takes 0.9M */
#define SPR_MAX_LEVEL_TEXELS 33554432.0

typedef struct slot {
    int ok;
    spr_polygon pg;
    spr_texture tex;
    size_t triangles;
    spr_error err;
    int failed;
} slot;

spr_result spr_domain_prims(const spr_cloud *c, const spr_csr *B, const spr_prims_desc *d, spr_rects *out, spr_prims_stats *st,
                            spr_error *err)
{
    memset(out, 0, sizeof *out);
    memset(st, 0, sizeof *st);
    const double t0 = spr_now_ms();
    spr_csr T;
    if (spr_domain_members(B, d->strict, d->K, &T, err)) return err->code;
    const size_t R = T.rows;
    slot *sl = calloc(R ? R : 1, sizeof *sl);
    if (!sl) {
        spr_csr_free(&T);
        return spr__fail(err, SPR_E_NOMEM, "domains: out of memory for %zu domains", R);
    }
    /* the polygons first, and the texels their textures will take: a level whose textures exceed
     * SPR_MAX_LEVEL_TEXELS is refused before any texture is made (a cloud of a few huge splats among
     * tiny ones would otherwise ask for gigabytes of texels, the texel being the domain's mean radius) */
    double level_texels = 0.0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(d->threads > 0 ? d->threads : 1) reduction(+ : level_texels)
    for (long jj = 0; jj < (long)R; jj++) {
        const size_t j = (size_t)jj, m = T.ptr[j + 1] - T.ptr[j];
        slot *s = &sl[j];
        if (m < 3) continue;
        if (spr_support_polygon(c, T.col + T.ptr[j], T.val + T.ptr[j], m, d->enlarge, 1, &s->pg, &s->err)) continue; /* degenerate */
        double t, w, h;
        if (spr_texture_size(c, T.col + T.ptr[j], m, &s->pg, &d->tex, &t, &w, &h, &s->err)) s->failed = 1;
        else s->ok = 1, level_texels += w * h;
    }
    if (level_texels > SPR_MAX_LEVEL_TEXELS) {
        free(sl);
        spr_csr_free(&T);
        return spr__fail(err, SPR_E_TOO_LARGE, "domains: the level's %zu textures would take %.0f texels (at most %.0f): a larger --texel, "
                         "or splats of less disparate radii", R, level_texels, SPR_MAX_LEVEL_TEXELS);
    }
#pragma omp parallel for schedule(dynamic, 1) num_threads(d->threads > 0 ? d->threads : 1)
    for (long jj = 0; jj < (long)R; jj++) {
        const size_t j = (size_t)jj, m = T.ptr[j + 1] - T.ptr[j];
        slot *s = &sl[j];
        if (!s->ok) continue;
        s->ok = 0;
        spr_result r = d->affine ? spr_texture_affine(c, T.col + T.ptr[j], T.val + T.ptr[j], m, &s->pg, &d->tex, &s->tex, &s->triangles, &s->err)
                                 : spr_texture_radial(c, T.col + T.ptr[j], T.val + T.ptr[j], m, &s->pg, &d->tex, &s->tex, &s->err);
        if (r) s->failed = 1;
        else s->ok = 1;
    }
    spr_result res = SPR_OK;
    size_t n = 0, texels = 0;
    for (size_t j = 0; j < R; j++) {
        if (sl[j].failed && !res) {
            *err = sl[j].err;
            res = err->code ? err->code : SPR_E_VALUE;
        }
        if (sl[j].ok) n++, texels += (size_t)sl[j].tex.w * (size_t)sl[j].tex.h;
    }
    uint32_t *prim_of = NULL; /* domain → primitive, UINT32_MAX: none */
    if (!res) res = spr_rects_alloc(out, n, texels, err);
    if (!res && !(prim_of = malloc((R ? R : 1) * sizeof *prim_of))) res = spr__fail(err, SPR_E_NOMEM, "domains: out of memory");
    size_t k = 0, off = 0;
    double e = 0.0, en = 0.0, pts = 0.0;
    for (size_t j = 0; !res && j < R; j++) {
        prim_of[j] = UINT32_MAX;
        if (!sl[j].ok) continue;
        const spr_polygon *pg = &sl[j].pg;
        float *f = out->f + k * SPR_RECT_FLOATS;
        uint32_t *I = out->i + k * SPR_RECTI_COUNT;
        for (int a = 0; a < 3; a++) {
            f[SPR_RECT_C + a] = (float)pg->centroid[a];
            f[SPR_RECT_N + a] = (float)pg->normal[a];
            f[SPR_RECT_U + a] = (float)pg->u[a];
            f[SPR_RECT_V + a] = (float)pg->v[a];
        }
        f[SPR_RECT_UMIN] = (float)pg->umin;
        f[SPR_RECT_UMAX] = (float)pg->umax;
        f[SPR_RECT_VMIN] = (float)pg->vmin;
        f[SPR_RECT_VMAX] = (float)pg->vmax;
        f[SPR_RECT_TEXEL] = (float)sl[j].tex.texel;
        I[SPR_RECTI_TW] = (uint32_t)sl[j].tex.w;
        I[SPR_RECTI_TH] = (uint32_t)sl[j].tex.h;
        I[SPR_RECTI_OFF] = (uint32_t)off;
        I[SPR_RECTI_DOMAIN] = (uint32_t)j;
        const size_t nt = (size_t)sl[j].tex.w * (size_t)sl[j].tex.h;
        memcpy(out->texels + 4 * off, sl[j].tex.rgba, nt * 4 * sizeof(float));
        off += nt;
        e += pg->error, en += pg->error_norm, pts += (double)pg->points;
        st->triangles += sl[j].triangles;
        prim_of[j] = (uint32_t)k++;
    }
    /* neighbours (thresholded domains; strict ones share no point): for
     * each domain, its points' other domains are B's rows filtered by K */
    for (size_t k = 0; !res && k < n; k++) spr_rects_link(out, k, k);
    size_t *shared = NULL;
    uint32_t *touched = NULL;
    if (!res && !d->strict && (!(shared = calloc(R ? R : 1, sizeof *shared)) || !(touched = malloc((R ? R : 1) * sizeof *touched))))
        res = spr__fail(err, SPR_E_NOMEM, "domains: out of memory for neighbours");
    for (size_t j = 0; !res && !d->strict && j < R; j++) {
        if (prim_of[j] == UINT32_MAX) continue;
        size_t nt = 0;
        for (size_t q = T.ptr[j]; q < T.ptr[j + 1]; q++) {
            const size_t p = T.col[q];
            for (size_t z = B->ptr[p]; z < B->ptr[p + 1]; z++) {
                const uint32_t h = B->col[z];
                if (h > j && prim_of[h] != UINT32_MAX && B->val[z] >= d->K && shared[h]++ == 0) touched[nt++] = h;
            }
        }
        const double mj = (double)(T.ptr[j + 1] - T.ptr[j]);
        for (size_t z = 0; z < nt; z++) {
            const uint32_t h = touched[z];
            const double sh = (double)shared[h], mh = (double)(T.ptr[h + 1] - T.ptr[h]);
            if (sh / mj > d->nbr_ratio || sh / mh > d->nbr_ratio) {
                spr_rects_link(out, prim_of[j], prim_of[h]);
                st->neighbour_pairs++;
            }
            shared[h] = 0;
        }
    }
    free(shared);
    free(touched);
    if (!res) {
        st->polygons = n;
        st->texels = texels;
        st->error = n ? e / (double)n : 0.0;
        st->error_norm = n ? en / (double)n : 0.0;
        st->points = n ? pts / (double)n : 0.0;
        st->ms = spr_now_ms() - t0;
    } else {
        spr_rects_free(out);
    }
    for (size_t j = 0; j < R; j++) spr_texture_free(&sl[j].tex);
    free(sl);
    free(prim_of);
    spr_csr_free(&T);
    return res;
}
