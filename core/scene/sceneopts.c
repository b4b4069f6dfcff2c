/* sceneopts.c — reading and checking a scene's options (the command line's
 * and a scene file's values, spr__options.h) into the scene, the render
 * description and a plan of the work; nothing is loaded, grouped or built
 * here, so a bad value is refused before any work and the whole phase can be
 * fuzzed (tests/fuzz, fuzz_scene). */
#include "spr_util.h"
#include "spr__options.h"
#include "spr__scene_opts.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* --shade, --light, --material (SPR_USES_SHADE) and --env, --env-size, --eta,
 * --env-layers (SPR_USES_ENV) into rd->shade; the cube map asked for into p. */
static int shading_opts(spr__args *a, spr__scene_plan *p, unsigned uses, spr_render_desc *rd)
{
    spr_shading *sh = &rd->shade;
    spr_shading_defaults(sh);
    const char *model = uses & SPR_USES_SHADE ? spr__get(a, "shade") : NULL;
    if (model && strcmp(model, "none") && strcmp(model, "phong")) { spr__error(a, "--shade: '%s' is not none or phong", model); return -1; }
    sh->model = model && !strcmp(model, "phong") ? SPR_SHADE_PHONG : SPR_SHADE_NONE;
    if (sh->model == SPR_SHADE_PHONG) {
        const char *mat = spr__get(a, "material");
        if (spr__get_vec3(a, "light", sh->light_eye) < 0) return -1;
        if (sh->light_eye[0] == 0.0 && sh->light_eye[1] == 0.0 && sh->light_eye[2] == 0.0) { spr__error(a, "--light: the direction is zero"); return -1; }
        if (mat) {
            double ka, kd, ks;
            int e;
            char tail;
            if (sscanf(mat, "%lf,%lf,%lf,%d%c", &ka, &kd, &ks, &e, &tail) != 4 || !(ka >= 0 && ka <= 16) || !(kd >= 0 && kd <= 16) ||
                !(ks >= 0 && ks <= 16) || e < 1 || e > 1024) {
                spr__error(a, "--material: '%s' is not KA,KD,KS,EXP with coefficients in [0,16] and a whole exponent 1..1024", mat);
                return -1;
            }
            sh->ka = ka, sh->kd = kd, sh->ks = ks, sh->exponent = e;
        }
    }
    const char *env = uses & SPR_USES_ENV ? spr__get(a, "env") : NULL;
    if (env && strcmp(env, "none")) {
        int size = 256;
        const char *eta = spr__get(a, "eta"), *layers = spr__get(a, "env-layers");
        if (spr__get_int(a, "env-size", &size, 1, 4096) < 0) return -1;
        if (eta) {
            double e[3];
            char tail;
            int n = sscanf(eta, "%lf,%lf,%lf%c", &e[0], &e[1], &e[2], &tail);
            if (n == 1) e[1] = e[2] = e[0];
            if ((n != 1 && n != 3) || !(e[0] > 0 && e[0] <= 4) || !(e[1] > 0 && e[1] <= 4) || !(e[2] > 0 && e[2] <= 4)) {
                spr__error(a, "--eta: '%s' is not one or three ratios in (0,4]", eta);
                return -1;
            }
            memcpy(sh->eta, e, sizeof e);
        }
        if (layers && strcmp(layers, "multi") && strcmp(layers, "single")) { spr__error(a, "--env-layers: '%s' is not multi or single", layers); return -1; }
        sh->multilayer = !layers || !strcmp(layers, "multi");
        p->env = env; /* the cube map is made (or read) once every option is checked: spr__scene_setup */
        p->env_size = size;
    }
    if ((uses & SPR_USES_LAYERS) && spr__get_int(a, "layers", &rd->layers, 1, 64) < 0) return -1;
    return 0;
}

/* An enum option from a list of names; −1 after an error line. */
static int pick(spr__args *a, const char *opt, const char *v, int value, const char *allowed)
{
    if (value < 0) spr__error(a, "--%s: '%s' is not %s", opt, v, allowed);
    return value;
}

int spr__parse_group_opts(spr__args *a, const char *method_opt, spr_grouping_desc *gd, const char **hash_near)
{
    spr_grouping_defaults(gd);
    *hash_near = NULL;
    const char *m = spr__get(a, method_opt), *file = spr__get(a, "groups-file");
    if (m && file) { spr__error(a, "--%s and --groups-file both choose the groups: give one", method_opt); return -1; }
    if (file) {
        gd->method = SPR_GROUP_FILE;
        gd->file = file;
        return 0; /* nothing else applies to groups read from a file */
    }
    if (m && (int)(gd->method = (spr_group_method)pick(a, method_opt, m, spr_group_method_from_name(m), "none, mgc, wgc or hash")) < 0)
        return -1;
    if (gd->method == SPR_GROUP_FILE) { spr__error(a, "--%s: use --groups-file F for groups from a file", method_opt); return -1; }
    if (gd->method == SPR_GROUP_MGC) {
        const char *relax = spr__get(a, "relax");
        if (spr__get_double(a, "c", &gd->mgc.c, 0.0, 1.0) < 0) return -1;
        if (relax) {
            static const char *const ok[] = {"none", "coplanar", "opposite", "coplanar,opposite", "opposite,coplanar", NULL};
            int i = 0;
            while (ok[i] && strcmp(ok[i], relax)) i++;
            if (!ok[i]) { spr__error(a, "--relax: '%s' is not coplanar,opposite | coplanar | opposite | none", relax); return -1; }
            gd->mgc.relax_coplanar = strstr(relax, "coplanar") != NULL;
            gd->mgc.relax_opposite = strstr(relax, "opposite") != NULL;
        }
    } else if (gd->method == SPR_GROUP_WGC) {
        if (spr__get_int(a, "k", &gd->wgc.K, 1, SPR_MAX_GROUPS) < 0) return -1;
    } else if (gd->method == SPR_GROUP_HASH) {
        const char *axis = spr__get(a, "hash-axis");
        if (spr__get_int(a, "k", &gd->hash.K, 1, SPR_MAX_GROUPS) < 0 || spr__get_int(a, "mode", &gd->hash.mode, 1, 3) < 0) return -1;
        if (axis && strcmp(axis, "bsp") && strcmp(axis, "normal")) { spr__error(a, "--hash-axis: '%s' is not bsp or normal", axis); return -1; }
        gd->hash.axis = axis && !strcmp(axis, "normal") ? SPR_HASH_AXIS_NORMAL : SPR_HASH_AXIS_BSP;
        if (gd->hash.mode == 3) {
            *hash_near = spr__get(a, "hash-near");
            if (!*hash_near) { spr__error(a, "--mode 3 needs --hash-near DIST (eye distance below which collisions are handled)"); return -1; }
            if (strcmp(*hash_near, "centre") && spr__get_double(a, "hash-near", &gd->hash.near_dist, 0.0, 1e30) < 0) return -1;
        }
    }
    const char *ext = gd->method != SPR_GROUP_NONE ? spr__get(a, "extend") : NULL;
    if (ext && (int)(gd->extend = (spr_group_extend)pick(a, "extend", ext, spr_group_extend_from_name(ext), "dup, radius or hash-radius")) < 0)
        return -1;
    return 0;
}

int spr__model_opts(spr__args *a, spr_scene *s, spr_load_desc *ld)
{
    spr_load_defaults(ld);
    const char *model = a->cloud_in ? "arrays" : spr__get(a, "model") ? spr__get(a, "model") : "builtin:torus";
    snprintf(s->model, sizeof s->model, "%s", model);
    if ((!strncmp(model, "builtin:", 8) && spr__get_size(a, "points", &ld->points, 16, SPR_MAX_SPLATS) < 0) ||
        spr__get_int(a, "radius-k", &ld->radius_k, 1, 256) < 0 || spr__get_double(a, "radius-scale", &ld->radius_rho, 1e-6, 1e6) < 0 ||
        spr__get_int(a, "threads", &s->threads, 0, 1024) < 0 || spr__get_double(a, "opacity", &ld->opacity, 1e-6, 1.0) < 0 ||
        spr__get_int(a, "balls", &ld->balls, 1, 64) < 0 || spr__get_double(a, "gauss-cut", &ld->gauss_cut, 1e-3, 3.0) < 0 ||
        spr__get_int(a, "sh-degree", &ld->sh_degree, 0, 3) < 0)
        return -1;
    ld->columns = spr__get(a, "columns");
    const char *frame = spr__get(a, "spz-frame");
    if (frame && strcmp(frame, "rub") && strcmp(frame, "raw")) {
        spr__error(a, "--spz-frame: \"%s\" is neither rub nor raw", frame);
        return -1;
    }
    ld->spz_raw = frame && !strcmp(frame, "raw");
    ld->threads = s->threads;
    ld->progress = spr__progress(spr__flag(a, "quiet"));
    ld->warn = spr__warn(a);
    return 0;
}

/* --view-matrix and --projection-matrix: both or neither, not with eye/target/up/fov/ortho. */
static int camera_matrices(spr__args *a, spr_camera_desc *c)
{
    const char *vm = spr__get(a, "view-matrix"), *pm = spr__get(a, "projection-matrix");
    if (!vm && !pm) return 0;
    if (!vm || !pm) { spr__error(a, "--view-matrix and --projection-matrix go together"); return -1; }
    static const char *const lookat[] = {"eye", "target", "up", "fov", "ortho", NULL};
    for (int i = 0; lookat[i]; i++)
        if (spr__get(a, lookat[i])) { spr__error(a, "--%s and the raw matrices both place the camera: give one form", lookat[i]); return -1; }
    for (int m = 0; m < 2; m++) {
        const char *v = m ? pm : vm;
        double *out = m ? c->P : c->V;
        const char *p = v;
        for (int i = 0; i < 16; i++) {
            char *e;
            errno = 0;
            out[i] = strtod(p, &e);
            if (e != p && !errno && isfinite(out[i]) && i < 15 && !*e) {
                spr__error(a, "--%s: '%s' has %d numbers: give 16, row by row", m ? "projection-matrix" : "view-matrix", v, i + 1);
                return -1;
            }
            if (e == p || errno || !isfinite(out[i]) || (i < 15 && *e != ',') || (i == 15 && *e)) {
                spr__error(a, "--%s: element %d of '%s' is not a number: give 16 finite numbers, row by row", m ? "projection-matrix" : "view-matrix", i + 1, v);
                return -1;
            }
            p = e + (i < 15);
        }
    }
    c->have_matrices = 1;
    return 0;
}

/* Parse n comma-separated finite numbers of option `name` into out; −1 after an error. */
static int numbers(spr__args *a, const char *name, const char *v, int n, double *out, const char *what)
{
    const char *p = v;
    for (int i = 0; i < n; i++) {
        char *e;
        errno = 0;
        out[i] = strtod(p, &e);
        if (e == p || errno || !isfinite(out[i]) || (i < n - 1 && *e != ',') || (i == n - 1 && *e)) {
            spr__error(a, "--%s: '%s': give %s, %d finite numbers separated by commas", name, v, what, n);
            return -1;
        }
        p = e + (i < n - 1);
    }
    return 0;
}

/* The pinhole camera (SPEC §10.2): --intrinsics with --world-to-camera, or
 * --cameras F.json with --camera ID; not with another form of camera. */
static int camera_pinhole(spr__args *a, spr_camera_desc *c)
{
    const char *in = spr__get(a, "intrinsics"), *wc = spr__get(a, "world-to-camera"), *file = spr__get(a, "cameras"), *id = spr__get(a, "camera");
    if (!in && !wc && !file && !id) return 0;
    if ((in || wc) && (file || id)) { spr__error(a, "--intrinsics/--world-to-camera and --cameras both place the camera: give one form"); return -1; }
    if ((in || wc) && !(in && wc)) { spr__error(a, "--intrinsics and --world-to-camera go together"); return -1; }
    if ((file || id) && !(file && id)) { spr__error(a, "--cameras and --camera go together"); return -1; }
    static const char *const other[] = {"eye", "target", "up", "fov", "ortho", "view-matrix", "projection-matrix", NULL};
    for (int i = 0; other[i]; i++)
        if (spr__get(a, other[i])) { spr__error(a, "--%s and the pinhole camera both place the camera: give one form", other[i]); return -1; }
    spr_pinhole *p = &c->pinhole;
    spr_error err = {0};
    if (in) {
        double k[4], m[12];
        if (numbers(a, "intrinsics", in, 4, k, "fx,fy,cx,cy") || numbers(a, "world-to-camera", wc, 12, m, "[R|t] row by row")) return -1;
        for (int r = 0; r < 3; r++) {
            for (int j = 0; j < 3; j++) p->R[3 * r + j] = m[4 * r + j];
            p->t[r] = m[4 * r + 3];
        }
        p->fx = k[0], p->fy = k[1], p->cx = k[2], p->cy = k[3];
        if (spr_pinhole_check(p, "--intrinsics/--world-to-camera", &err)) { spr__error(a, "%s", err.msg); return -1; }
    } else if (!strcmp(id, "all")) { /* every view (check --images): the scene is set up with the first */
        if (!a->camera_all) { spr__error(a, "--camera all: only check takes every view (with --images DIR)"); return -1; }
        if (spr__get(a, "save")) { spr__error(a, "--camera all: a scene file holds one camera; save one view's scene with --camera ID"); return -1; }
        spr_camera_entry *v;
        size_t n;
        if (spr_cameras_json_all(file, &v, &n, &err)) { spr__error(a, "--cameras: %s", err.msg); return -1; }
        spr__camera_pinhole_sized(c, &v[0].pinhole, v[0].width, v[0].height, spr__get(a, "size") != NULL);
        free(v);
    } else {
        char *e;
        errno = 0;
        long n = strtol(id, &e, 10);
        if (e == id || *e || errno) { spr__error(a, "--camera: '%s' is neither a whole-number id nor all", id); return -1; }
        int w, h;
        spr_pinhole q;
        if (spr_cameras_json(file, n, &q, &w, &h, &err)) { spr__error(a, "--cameras: %s", err.msg); return -1; }
        spr__camera_pinhole_sized(c, &q, w, h, spr__get(a, "size") != NULL);
    }
    c->have_pinhole = 1;
    return 0;
}

void spr__camera_pinhole_sized(spr_camera_desc *c, const spr_pinhole *q, int w, int h, int size_given)
{
    spr_pinhole *p = &c->pinhole;
    *p = *q;
    c->have_pinhole = 1;
    if (!size_given) c->width = w, c->height = h;
    else { /* another size: the same field of view, as the training code's --resolution scales its cameras */
        const double sx = (double)c->width / w, sy = (double)c->height / h;
        p->fx *= sx, p->cx *= sx, p->fy *= sy, p->cy *= sy;
    }
}

int spr__scene_opts(spr__args *a, spr_scene *s, spr_render_desc *rd, spr__scene_plan *p, int allow_all)
{
    memset(s, 0, sizeof *s);
    memset(rd, 0, sizeof *rd);
    memset(p, 0, sizeof *p);
    spr_error err = {0};
    spr_camera_defaults(&s->cam);
    double bg[3] = {0, 0, 0};
    p->quiet = spr__flag(a, "quiet");
    const char *aname = spr__get(a, "algo");
    if (spr__model_opts(a, s, &p->ld) || spr__get_vec3(a, "eye", s->cam.eye) < 0 || spr__get_vec3(a, "target", s->cam.target) < 0 ||
        spr__get_vec3(a, "up", s->cam.up) < 0 || spr__get_double(a, "fov", &s->cam.fov_deg, 1e-3, 179.0) < 0 ||
        spr__get_double(a, "ortho", &s->cam.ortho_height, 1e-12, 1e30) < 0 || spr__get_double(a, "near", &s->cam.near_plane, 0.0, 1e30) < 0 ||
        spr__get_double(a, "far", &s->cam.far_plane, 0.0, 1e30) < 0 || spr__get_wh(a, "size", &s->cam.width, &s->cam.height) < 0 ||
        spr__get_vec3(a, "background", bg) < 0)
        return -1;
    s->cam.have_eye = spr__get(a, "eye") != NULL;
    s->cam.have_target = spr__get(a, "target") != NULL;
    if (camera_matrices(a, &s->cam) || camera_pinhole(a, &s->cam)) return -1;
    p->save = spr__get(a, "save-scene");
    const char *save_form = p->save ? spr__get(a, "scene-camera") : NULL;
    if (save_form && strcmp(save_form, "lookat") && strcmp(save_form, "matrices")) {
        spr__error(a, "--scene-camera: '%s' is not lookat or matrices", save_form);
        return -1;
    }
    p->save_matrices = save_form && !strcmp(save_form, "matrices");
    for (int k = 0; k < 3; k++) {
        if (bg[k] < 0.0 || bg[k] > 1.0) { spr__error(a, "--background: components must lie in [0,1]"); return -1; }
        rd->background[k] = (float)bg[k];
    }
    if (spr__get(a, "ortho")) s->cam.fov_deg = 0.0;
    /* --gauss-profile P (alias --gauss-flavor, its name before SPEC 10.9): one row of the profile table; alone it
     * picks the row's skeleton, with another --algo it is refused */
    const char *pname = spr__get(a, "gauss-profile"), *fname = spr__get(a, "gauss-flavor");
    const char *popt = pname ? "--gauss-profile" : "--gauss-flavor";
    if (pname && fname) { spr__error(a, "--gauss-flavor is the old name of --gauss-profile: give one"); return -1; }
    if (!pname) pname = fname;
    const int prow = pname ? spr_gauss_profile_from_name(pname) : -1;
    rd->gauss_profile = prow + 1;
    if (pname && prow < 0) {
        spr__error(a, "%s: '%s' is not a profile (%s)", popt, pname, spr_gauss_profile_names(", "));
        return -1;
    }
    s->all_algos = allow_all && (!aname || !strcmp(aname, "all")) && !pname;
    if (aname && strcmp(aname, "all") && (int)(rd->algo = (spr_algo)spr_algo_from_name(aname)) < 0) {
        spr__error(a, "--algo: '%s' is not %s%s", aname, spr_algo_names(", "), allow_all ? " or all" : "");
        return -1;
    }
    if (pname) {
        const spr_gauss_profile *pf = spr_gauss_profile_at(prow);
        if (!aname || !strcmp(aname, "all")) rd->algo = pf->skeleton;
        else if (!spr_gauss_profile_fits(pf, rd->algo)) {
            spr__error(a, "%s %s belongs to --algo %s%s, not %s", popt, pname, spr_algo_name(pf->skeleton),
                       pf->skeleton == SPR_ALGO_GAUSS3D ? " (or gauss2d)" : "", aname);
            return -1;
        }
    }
    /* The options the algorithm(s) read: the registry says which. */
    unsigned uses = 0;
    for (int al = 0; al < SPR_ALGO__COUNT; al++)
        if (s->all_algos || al == (int)rd->algo) uses |= spr_algo_info_of((spr_algo)al)->uses;
    p->uses = uses;
    const char *kname = uses & SPR_USES_KERNEL ? spr__get(a, "kernel") : NULL;
    if (kname && (int)(rd->kernel = (spr_kernel)spr_kernel_from_name(kname)) < 0) {
        spr__error(a, "--kernel: '%s' is not gauss, constant, linear or epanechnikov", kname);
        return -1;
    }
    if ((uses & SPR_USES_EPS) && spr__get_double(a, "eps", &rd->eps, 1e-30, 1e30) < 0) return -1;
    rd->voronoi = (uses & SPR_USES_VORONOI) && spr__flag(a, "voronoi");
    if ((rd->voronoi || (uses & SPR_USES_LOWRES)) && spr__get_double(a, "lowres-n", &rd->lowres_n, 1.0, 16777216.0) < 0) return -1;
    const char *order = uses & SPR_USES_ORDER ? spr__get(a, "order") : NULL;
    if (order && strcmp(order, "bsp") && strcmp(order, "sort")) { spr__error(a, "--order: '%s' is not bsp or sort", order); return -1; }
    rd->order = order && !strcmp(order, "sort") ? SPR_ORDER_SORT : SPR_ORDER_BSP;
    double alpha = 0.0;
    if ((uses & SPR_USES_ALPHA) && spr__get_double(a, "alpha", &alpha, 1e-6, 1.0) < 0) return -1;
    rd->alpha = (float)alpha;
    if (shading_opts(a, p, uses, rd)) return -1;
    if (uses & SPR_USES_RECTS) {
        const char *smp = spr__get(a, "sampling");
        if (smp && strcmp(smp, "nearest") && strcmp(smp, "linear") && strcmp(smp, "hardware")) {
            spr__error(a, "--sampling: '%s' is not nearest, linear or hardware", smp);
            return -1;
        }
        rd->sampling = !smp || !strcmp(smp, "linear") ? SPR_SAMPLE_LINEAR : !strcmp(smp, "nearest") ? SPR_SAMPLE_NEAREST : SPR_SAMPLE_HARDWARE;
        if (spr__domain_opts(a, &s->dom)) return -1;
    }
    double aref = 0.1;
    if ((uses & SPR_USES_ALPHAREF) && spr__get_double(a, "alpha-ref", &aref, 0.0, 1.0) < 0) return -1;
    rd->alpha_ref = (float)aref;
    if (uses & SPR_USES_GAUSS) {
        rd->gauss_aa = spr__flag(a, "gauss-aa");
    }
    rd->progress = spr__progress(p->quiet);
    spr_grouping_desc *gd = &p->gd;
    if ((uses & SPR_USES_GROUPS) && spr__parse_group_opts(a, "groups", gd, &p->hash_near)) return -1;
    const int stream = p->stream = spr__flag(a, "stream");
    if (!stream && spr__get(a, "chunk")) { spr__error(a, "--chunk goes with --stream"); return -1; }
    if (stream && spr__get_size(a, "chunk", &s->stream_chunk, 1, (size_t)1 << 26) < 0) return -1;
    for (int al = 0; stream && al < SPR_ALGO__COUNT; al++)
        if ((s->all_algos || al == (int)rd->algo) &&
            spr_stream_check((spr_algo)al, 0, &err)) {
            spr__error(a, "%s", err.msg);
            return -1;
        }
    if (stream && (uses & SPR_USES_GROUPS)) {
        if (gd->method == SPR_GROUP_MGC || gd->method == SPR_GROUP_WGC) {
            spr__error(a, "--stream: %s grouping builds the overlap graph of the whole cloud in memory; use --groups hash "
                          "(--mode 1 reads centres, normals and radii: 28 bytes a splat), none or --groups-file",
                       spr_group_method_name(gd->method));
            return -1;
        }
        s->stream_keep = gd->method == SPR_GROUP_HASH;
    }
    return spr__reject_unused(a);
}
