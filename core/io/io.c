/* io.c — spr_load(): format dispatch and completion of missing attributes. */
#include "spr_io.h"
#include "spr_pca.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void spr_load_defaults(spr_load_desc *d)
{
    memset(d, 0, sizeof *d);
    d->points = 20000;
    d->radius_k = 8;
    d->radius_rho = 1.0;
    d->normal_k = 10;
}

static const char *ext_of(const char *path)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    return dot && (!slash || dot > slash) ? dot + 1 : "";
}

static int ieq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if ((*a | 32) != (*b | 32)) return 0;
    return *a == *b;
}

size_t spr__mesh_normals(const spr__mesh *m, spr_cloud *c)
{
    double *acc = calloc(3 * c->n, sizeof(double));
    if (!acc) return c->n;
    for (size_t t = 0; t < m->nt; t++) {
        const uint32_t *v = m->tri + 3 * t;
        const float *a = c->pos + 3 * (size_t)v[0], *b = c->pos + 3 * (size_t)v[1], *d = c->pos + 3 * (size_t)v[2];
        double e1[3] = {(double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2]};
        double e2[3] = {(double)d[0] - a[0], (double)d[1] - a[1], (double)d[2] - a[2]};
        /* |e1 × e2| = 2·area: summing raw cross products weights by area. */
        double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++) acc[3 * (size_t)v[k] + j] += n[j];
    }
    size_t missing = 0;
    for (size_t i = 0; i < c->n; i++) {
        double l = sqrt(acc[3 * i] * acc[3 * i] + acc[3 * i + 1] * acc[3 * i + 1] + acc[3 * i + 2] * acc[3 * i + 2]);
        if (l > 0.0 && isfinite(l)) {
            for (int j = 0; j < 3; j++) c->nrm[3 * i + j] = (float)(acc[3 * i + j] / l);
        } else {
            c->nrm[3 * i] = c->nrm[3 * i + 1] = c->nrm[3 * i + 2] = 0.0f;
            missing++;
        }
    }
    free(acc);
    return missing;
}

/* The k nearest neighbours of every splat, computed once and shared by the
 * PCA normals and the radius rule when a file lacks both. */
typedef struct knn_table {
    int k;
    uint32_t *idx;
    double *dist;
} knn_table;

static void knn_table_free(knn_table *t)
{
    free(t->idx);
    free(t->dist);
    t->idx = NULL;
    t->dist = NULL;
}

static spr_result knn_table_make(const spr_cloud *c, int k, int threads, const spr_progress *prog, knn_table *t, spr_error *err)
{
    t->idx = NULL;
    t->dist = NULL;
    t->k = (size_t)k >= c->n ? (int)c->n - 1 : k;
    spr_knn *kn;
    spr_result r = spr_knn_build(c->pos, c->n, &kn, err);
    if (r) return r;
    t->idx = malloc(c->n * (size_t)t->k * sizeof(uint32_t));
    t->dist = malloc(c->n * (size_t)t->k * sizeof(double));
    if (!t->idx || !t->dist) r = spr__fail(err, SPR_E_NOMEM, "neighbours: out of memory");
    else r = spr_knn_query_all(kn, t->k, threads, t->idx, t->dist, prog, err);
    spr_knn_free(kn);
    if (r) knn_table_free(t);
    return r;
}

/* PCA normals from the first k neighbours of the table. */
static spr_result pca_from(spr_cloud *c, const knn_table *t, int k, int all, spr_error *err)
{
    if (k > t->k) k = t->k;
    spr_bounds b;
    spr_cloud_bounds(c, &b);
    for (size_t i = 0; i < c->n; i++) {
        float *nv = c->nrm + 3 * i;
        if (!all && (nv[0] != 0.0f || nv[1] != 0.0f || nv[2] != 0.0f)) continue;
        double ev[3], evec[9];
        spr_pca_local(c->pos, i, t->idx + i * (size_t)t->k, k, ev, evec);
        /* Orientation [decision, SPEC §1]: away from the bounding-box centre. */
        double out = 0.0;
        for (int d = 0; d < 3; d++) out += evec[d] * (c->pos[3 * i + d] - 0.5 * (b.lo[d] + b.hi[d]));
        double s = out < 0.0 ? -1.0 : 1.0;
        for (int d = 0; d < 3; d++) nv[d] = (float)(s * evec[d]);
        if (spr__normalize3(nv)) return spr__fail(err, SPR_E_VALUE, "normals: splat %zu: PCA gave no normal", i);
    }
    return SPR_OK;
}

/* r_i = ρ·d_k(i) from the table (exact search: the k-th distance does not
 * depend on how many neighbours the table holds). */
static void radii_from(spr_cloud *c, const knn_table *t, int k, double rho)
{
    if (k > t->k) k = t->k;
    double floor_r = INFINITY;
    for (size_t i = 0; i < c->n; i++) {
        double d = rho * t->dist[i * (size_t)t->k + (size_t)k - 1];
        if (d > 0.0 && d < floor_r) floor_r = d;
        c->radius[i] = (float)d;
    }
    /* Points whose k-th neighbour coincides with them (duplicates) get the
     * smallest positive radius of the cloud instead of 0. */
    for (size_t i = 0; i < c->n; i++)
        if (!(c->radius[i] > 0.0f)) c->radius[i] = isfinite(floor_r) ? (float)floor_r : 1.0f;
}

spr_result spr__pca_normals(spr_cloud *c, int k, int all, int threads, const spr_progress *prog, spr_error *err)
{
    if (c->n < 3) return spr__fail(err, SPR_E_VALUE, "normals: %zu points are too few for PCA", c->n);
    knn_table t;
    spr_result r = knn_table_make(c, k, threads, prog, &t, err);
    if (!r) r = pca_from(c, &t, k, all, err);
    knn_table_free(&t);
    return r;
}

spr_result spr__knn_radii(spr_cloud *c, int k, double rho, int threads, const spr_progress *prog, spr_error *err)
{
    if (c->n < 2) return spr__fail(err, SPR_E_VALUE, "radii: %zu points: no neighbour to size a splat", c->n);
    knn_table t;
    spr_result r = knn_table_make(c, k, threads, prog, &t, err);
    if (!r) radii_from(c, &t, k, rho);
    knn_table_free(&t);
    return r;
}

static spr_result complete(spr_cloud *c, const spr__mesh *mesh, const spr_load_desc *d, const char *path, spr_error *err)
{
    spr_result r = SPR_OK;
    int need_normals = 0, need_radii = !(c->flags & SPR_SRC_RADII);
    if (!(c->flags & SPR_SRC_NORMALS)) {
        size_t missing = c->n;
        if (mesh && mesh->nt) {
            missing = spr__mesh_normals(mesh, c);
            c->flags |= SPR_SRC_FACES;
        }
        need_normals = missing > 0;
    }
    if (need_normals && c->n < 3) return spr__fail(err, SPR_E_VALUE, "%s: %zu points are too few for PCA normals", path, c->n);
    if (need_radii && c->n < 2) return spr__fail(err, SPR_E_VALUE, "%s: %zu points: no neighbour to size a splat", path, c->n);
    if (need_normals || need_radii) { /* one neighbour search for both */
        knn_table t;
        int k = need_normals ? d->normal_k : 0;
        if (need_radii && d->radius_k > k) k = d->radius_k;
        if ((r = knn_table_make(c, k, d->threads, &d->progress, &t, err))) return r;
        if (need_normals) r = pca_from(c, &t, d->normal_k, 0, err);
        if (!r && need_radii) radii_from(c, &t, d->radius_k, d->radius_rho);
        knn_table_free(&t);
        if (r) return r;
    }
    return spr__cloud_finish(c, path, 0, d->opacity, err);
}

/* Read a file once and run the reader of its extension over it (mesh gets
 * the faces of OFF and PLY files). */
static spr_result load_file(const char *path, const char *ext, spr_cloud *c, spr__mesh *mesh, const spr_load_desc *d, spr_error *err)
{
    int ply = ieq(ext, "ply"), off = ieq(ext, "off"), xyz = ieq(ext, "xyz") || ieq(ext, "pwn"),
        txt = ieq(ext, "txt") || ieq(ext, "asc") || ieq(ext, "csv") || ieq(ext, "pts"), splat = ieq(ext, "splat"), spz = ieq(ext, "spz"),
        glb = ieq(ext, "glb"), sog = ieq(ext, "sog");
    const char *base = strrchr(path, '/');
    const int sog_folder = !strcmp(base ? base + 1 : path, "meta.json"); /* a SOG unzipped: meta.json beside its images */
    if (ieq(ext, "ksplat"))
        return spr__fail(err, SPR_E_FORMAT, "%s: .ksplat (GaussianSplats3D's compressed format) is not read: convert it to .ply or .spz with "
                         "splat-transform (docs/formats.md)", path);
    if (!ply && !off && !xyz && !txt && !splat && !spz && !glb && !sog && !sog_folder)
        return spr__fail(err, SPR_E_FORMAT, "%s: unknown file type \".%s\" (expected .ply, .off, .xyz, .pwn, .txt, .asc, .csv, .pts, .splat, .spz, .glb, "
                         ".sog or a SOG's meta.json)", path, ext);
    if (d && d->columns && !(xyz || txt))
        return spr__fail(err, SPR_E_ARG, "%s: --columns names the columns of text point files (.xyz .pwn .txt .asc .csv .pts), not .%s", path, ext);
    spr__gauss_opts go;
    spr__gauss_defaults(&go);
    if (d && d->gauss_cut > 0.0) go.cut = d->gauss_cut;
    if (d) go.sh_degree = d->sh_degree, go.spz_raw = d->spz_raw;
    char *buf;
    size_t len;
    int mapped;
    spr_result r = spr__map_file(path, &buf, &len, &mapped, err);
    if (r) return r;
    const spr_progress *prog = d ? &d->progress : NULL;
    const spr_warn *warn = d ? &d->warn : NULL;
    if (ply) r = spr__parse_ply(path, buf, len, c, mesh, prog, warn, &go, err);
    else if (off) r = spr__parse_off(path, buf, len, c, mesh, err);
    else if (splat) r = spr__parse_splat(path, buf, len, &go, c, err);
    else if (spz) r = spr__parse_spz(path, buf, len, &go, c, err);
    else if (glb) r = spr__parse_glb(path, buf, len, &go, c, err);
    else if (sog) r = spr__parse_sog(path, buf, len, &go, c, err);
    else if (sog_folder) r = spr__parse_sog_folder(path, buf, len, &go, c, err);
    else r = spr__parse_xyz(path, buf, len, d ? d->columns : NULL, c, err);
    spr__unmap_file(buf, len, mapped);
    return r;
}

spr_result spr_load(const char *path, const spr_load_desc *din, spr_cloud *c, spr_error *err)
{
    spr_load_desc d;
    if (din) d = *din; else spr_load_defaults(&d);
    if (!d.points) d.points = 20000;
    if (d.radius_k <= 0) d.radius_k = 8;
    if (!(d.radius_rho > 0.0)) d.radius_rho = 1.0;
    if (d.normal_k <= 0) d.normal_k = 10;
    if (d.gauss_cut < 0.0 || d.gauss_cut > 3.0 || d.sh_degree < 0 || d.sh_degree > 3)
        return spr__fail(err, SPR_E_ARG, "%s: --gauss-cut must lie in (0, 3] and --sh-degree in 0..3", path);
    spr__mesh mesh = {0};
    spr_result r;
    memset(c, 0, sizeof *c);
    spr_progress_report(&d.progress, "reading", 0, 1);
    if (strncmp(path, "builtin:", 8) == 0) {
        r = spr__builtin(path + 8, d.points, c, err);
    } else {
        r = load_file(path, ext_of(path), c, &mesh, &d, err);
    }
    spr_progress_report(&d.progress, "reading", 1, 1);
    if (r) return r;
    if (c->n == 0) { spr_cloud_free(c); spr__mesh_free(&mesh); return spr__fail(err, SPR_E_FORMAT, "%s: no points", path); }
    r = complete(c, &mesh, &d, path, err);
    spr__mesh_free(&mesh);
    if (!r && d.balls > 0 && (r = spr__add_balls(c, d.balls, err))) {
        spr_error inner = *err;
        spr__fail(err, r, "%s: %s", path, inner.msg);
    }
    if (r) spr_cloud_free(c);
    return r;
}


spr_result spr_sample_mesh(const char *path, size_t n, uint64_t seed, const spr_load_desc *din, spr_cloud *out, spr_error *err)
{
    spr_load_desc d;
    if (din) d = *din; else spr_load_defaults(&d);
    if (d.radius_k <= 0) d.radius_k = 8;
    if (!(d.radius_rho > 0.0)) d.radius_rho = 1.0;
    memset(out, 0, sizeof *out);
    if (n < 2 || n > SPR_MAX_SPLATS) return spr__fail(err, SPR_E_ARG, "sample: --points %zu outside 2..%u", n, SPR_MAX_SPLATS);
    spr_cloud m;
    spr__mesh mesh;
    const char *e = ext_of(path);
    spr_result r = ieq(e, "off") || ieq(e, "ply") ? load_file(path, e, &m, &mesh, din, err)
                                                  : spr__fail(err, SPR_E_FORMAT, "%s: sampling needs a mesh (.off or .ply with faces)", path);
    if (r) return r;
    if (!mesh.nt) { spr_cloud_free(&m); return spr__fail(err, SPR_E_FORMAT, "%s: mesh has no faces to sample", path); }
    double *cum = malloc(mesh.nt * sizeof(double));
    if (!cum || (r = spr_cloud_alloc(out, n))) {
        free(cum);
        spr_cloud_free(&m);
        spr__mesh_free(&mesh);
        return spr__fail(err, SPR_E_NOMEM, "sample: out of memory");
    }
    double total = 0.0;
    for (size_t t = 0; t < mesh.nt; t++) {
        const float *a = m.pos + 3 * (size_t)mesh.tri[3 * t], *b = m.pos + 3 * (size_t)mesh.tri[3 * t + 1],
                    *c = m.pos + 3 * (size_t)mesh.tri[3 * t + 2];
        double e1[3] = {(double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2]};
        double e2[3] = {(double)c[0] - a[0], (double)c[1] - a[1], (double)c[2] - a[2]};
        double x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2], z = e1[0] * e2[1] - e1[1] * e2[0];
        total += 0.5 * sqrt(x * x + y * y + z * z);
        cum[t] = total;
    }
    uint64_t s = seed;
    for (size_t i = 0; i < n; i++) {
        if ((i & 0xFFFF) == 0) spr_progress_report(&d.progress, "sampling", i, n);
        double u = spr__uniform01(&s) * total;
        size_t lo = 0, hi = mesh.nt - 1;
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if (cum[mid] > u) hi = mid; else lo = mid + 1;
        }
        const uint32_t *tv = mesh.tri + 3 * lo;
        const float *a = m.pos + 3 * (size_t)tv[0], *b = m.pos + 3 * (size_t)tv[1], *c = m.pos + 3 * (size_t)tv[2];
        double r1 = sqrt(spr__uniform01(&s)), r2 = spr__uniform01(&s);
        double wa = 1.0 - r1, wb = r1 * (1.0 - r2), wc = r1 * r2;
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            out->pos[3 * i + k] = (float)(wa * a[k] + wb * b[k] + wc * c[k]);
            e1[k] = (double)b[k] - a[k];
            e2[k] = (double)c[k] - a[k];
        }
        out->nrm[3 * i] = (float)(e1[1] * e2[2] - e1[2] * e2[1]);
        out->nrm[3 * i + 1] = (float)(e1[2] * e2[0] - e1[0] * e2[2]);
        out->nrm[3 * i + 2] = (float)(e1[0] * e2[1] - e1[1] * e2[0]);
        if (spr__normalize3(out->nrm + 3 * i)) { out->nrm[3 * i] = out->nrm[3 * i + 1] = 0.0f; out->nrm[3 * i + 2] = 1.0f; }
    }
    spr_progress_report(&d.progress, "sampling", n, n);
    free(cum);
    spr_cloud_free(&m);
    spr__mesh_free(&mesh);
    out->flags = 0;
    if ((r = spr__knn_radii(out, d.radius_k, d.radius_rho, d.threads, &d.progress, err))) { spr_cloud_free(out); return r; }
    spr_cloud_color_by_normal(out);
    if ((r = spr_cloud_validate(out, path, err))) spr_cloud_free(out);
    return r;
}
