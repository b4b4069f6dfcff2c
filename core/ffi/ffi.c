/* ffi.c — the flat interface of spr_ffi.h over the scene options, the
 * backends, the capture hook and the reports of spr__inspect.h. */
#include "spr_ffi.h"
#include "spr__inspect.h"
#include "spr_grad.h"
#include "spr__scene_opts.h"
#include "spr_profile_diff.h"
#include "spr_glbackend.h"
#include "spr_image.h"
#include "spr_swrast.h"
#include "spr_version.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static _Thread_local spr_error last;

static void fail_with(const spr_error *e)
{
    last = *e;
    if (!last.code) last.code = SPR_E_ARG;
}

static void fail(int code, const char *msg)
{
    last.code = code;
    snprintf(last.msg, sizeof last.msg, "%s", msg);
}

const char *spr_ffi_version(void) { return SPR_VERSION_STRING; }
const char *spr_ffi_error(void) { return last.msg; }
int spr_ffi_error_code(void) { return last.code; }
void spr_ffi_free(char *s) { free(s); }
uint8_t spr_ffi_to_u8(float v) { return spr_to_u8(v); }

char *spr_ffi_profiles(void)
{
    cJSON *o = spr__profiles_json();
    char *t = o ? cJSON_PrintUnformatted(o) : NULL;
    cJSON_Delete(o);
    if (!t) fail(SPR_E_NOMEM, "out of memory");
    return t;
}

static const spr__opt scene_opts[] = {SPR__SCENE_OPTS, {NULL, NULL, NULL}};

struct spr_ffi_scene {
    spr__args a;
    char *text[SPR__MAX_OPTS]; /* the option values a.value points to */
    spr_cloud in;
    spr_scene s;
    spr_render_desc rd;
    spr_gl_desc gl; /* the scene's gl-driver (spr__gl_opts); the device comes with each call */
    spr_error err;
};

struct spr_ffi_frame {
    char backend[8], renderer[600];
    spr_capture cap;
    spr_render_result res;
};

static char *json_text(cJSON *o)
{
    char *t = o ? cJSON_PrintUnformatted(o) : NULL;
    cJSON_Delete(o);
    if (!t) fail(SPR_E_NOMEM, "out of memory");
    return t;
}

/* The arrays as a cloud, checked as a loaded file's values are. */
static int take_arrays(spr_ffi_scene *sc, const spr_ffi_arrays *ar)
{
    spr_error err = {0};
    if (!ar->n || !ar->pos || !ar->nrm || !ar->radius) { fail(SPR_E_ARG, "arrays: n, pos, nrm and radius are required"); return -1; }
    if (ar->n > SPR_MAX_SPLATS) { fail(SPR_E_ARG, "arrays: too many splats"); return -1; }
    spr_cloud *c = &sc->in;
    if (spr_cloud_alloc(c, ar->n)) { fail(SPR_E_NOMEM, "arrays: out of memory"); return -1; }
    memcpy(c->pos, ar->pos, 3 * ar->n * sizeof(float));
    memcpy(c->nrm, ar->nrm, 3 * ar->n * sizeof(float));
    memcpy(c->radius, ar->radius, ar->n * sizeof(float));
    c->flags = SPR_SRC_NORMALS | SPR_SRC_RADII;
    if (ar->color) memcpy(c->color, ar->color, 3 * ar->n * sizeof(float)), c->flags |= SPR_SRC_COLORS;
    if (ar->alpha) memcpy(c->alpha, ar->alpha, ar->n * sizeof(float)), c->flags |= SPR_SRC_ALPHA;
    else
        for (size_t i = 0; i < ar->n; i++) c->alpha[i] = 1.0f;
    for (size_t i = 0; i < ar->n; i++)
        if (spr__normalize3(c->nrm + 3 * i)) {
            snprintf(err.msg, sizeof err.msg, "arrays: splat %zu: normal (%g, %g, %g) is zero or not finite", i, (double)ar->nrm[3 * i],
                     (double)ar->nrm[3 * i + 1], (double)ar->nrm[3 * i + 2]);
            err.code = SPR_E_VALUE;
            fail_with(&err);
            return -1;
        }
    if (spr__cloud_finish(c, "arrays", 0, 0.0, &err)) { fail_with(&err); return -1; }
    sc->a.cloud_in = c;
    return 0;
}

spr_ffi_scene *spr_ffi_scene_new(int n, const char *const *keys, const char *const *values, const spr_ffi_arrays *arrays)
{
    spr_ffi_scene *sc = calloc(1, sizeof *sc);
    if (!sc) { fail(SPR_E_NOMEM, "out of memory"); return NULL; }
    spr__args *a = &sc->a;
    a->cmd = "scene";
    a->opts = scene_opts;
    a->sink = &sc->err;
    const char *scene_file = NULL;
    for (int i = 0; i < n; i++) {
        char name[64];
        snprintf(name, sizeof name, "%s", keys[i]);
        for (char *p = name; *p; p++)
            if (*p == '_') *p = '-';
        int k = 0;
        while (scene_opts[k].name && strcmp(scene_opts[k].name, name)) k++;
        if (!scene_opts[k].name) {
            snprintf(sc->err.msg, sizeof sc->err.msg, "unknown option '%s' (the scene-file keys and render's options: docs/scene-format.md)", keys[i]);
            sc->err.code = SPR_E_ARG;
            goto bad;
        }
        free(sc->text[k]);
        if (!(sc->text[k] = strdup(values[i] ? values[i] : "1"))) { fail(SPR_E_NOMEM, "out of memory"); spr_ffi_scene_free(sc); return NULL; }
        a->value[k] = sc->text[k];
        if (!strcmp(name, "scene")) scene_file = sc->text[k];
    }
    if (arrays && take_arrays(sc, arrays)) { spr_ffi_scene_free(sc); return NULL; }
    if (scene_file && spr__scene_read(a, scene_file)) goto bad;
    if (spr__gl_opts(a, &sc->gl)) goto bad;
    /* render's default algorithm unless "all" is asked for (parity's default there) */
    const char *algo = spr__get(a, "algo");
    if (spr__scene_setup(a, &sc->s, &sc->rd, algo && !strcmp(algo, "all"))) goto bad;
    return sc;
bad:
    fail_with(&sc->err);
    spr_ffi_scene_free(sc);
    return NULL;
}

void spr_ffi_scene_free(spr_ffi_scene *sc)
{
    if (!sc) return;
    spr_scene_free(&sc->s);
    spr_cloud_free(&sc->in);
    spr__scene_forget(&sc->a);
    for (int k = 0; k < SPR__MAX_OPTS; k++) free(sc->text[k]);
    free(sc);
}

char *spr_ffi_scene_json(const spr_ffi_scene *sc)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "model", sc->s.model);
    cJSON_AddNumberToObject(o, "splats", (double)sc->s.cloud.n);
    cJSON_AddNumberToObject(o, "width", sc->s.view.width);
    cJSON_AddNumberToObject(o, "height", sc->s.view.height);
    cJSON_AddStringToObject(o, "algo", sc->s.all_algos ? "all" : spr_algo_name(sc->rd.algo));
    cJSON_AddNumberToObject(o, "groups", sc->rd.groups ? sc->rd.groups->K : 0);
    cJSON_AddNumberToObject(o, "threads", sc->s.threads);
    if (sc->rd.rects) {
        const spr_scene_domain *d = &sc->s.dom;
        const spr_prims_stats *st = &sc->s.prims;
        cJSON *p = cJSON_AddObjectToObject(o, "primitives");
        cJSON_AddNumberToObject(p, "level", d->level_used);
        cJSON_AddNumberToObject(p, "levels", d->levels);
        cJSON_AddNumberToObject(p, "regions", (double)d->regions);
        cJSON_AddNumberToObject(p, "polygons", (double)st->polygons);
        cJSON_AddNumberToObject(p, "texels", (double)st->texels);
        cJSON_AddNumberToObject(p, "error", st->error);
        cJSON_AddNumberToObject(p, "error_norm", st->error_norm);
        cJSON_AddNumberToObject(p, "points_per_polygon", st->points);
        cJSON_AddNumberToObject(p, "ms_decompose", d->ms_decomp);
        cJSON_AddNumberToObject(p, "ms_primitives", st->ms);
    }
    return json_text(o);
}

const float *spr_ffi_scene_rects(const spr_ffi_scene *sc, size_t *n, const uint32_t **ints, const float **texels, size_t *n_texels)
{
    const spr_rects *r = sc->rd.rects;
    if (!r) {
        fail(SPR_E_ARG, "primitives: the scene's algorithm draws no domain primitives (algo domain-*)");
        return NULL;
    }
    *n = r->n;
    *ints = r->i;
    *texels = r->texels;
    *n_texels = r->n_texels;
    return r->f;
}

const float *spr_ffi_scene_cloud(const spr_ffi_scene *sc, const char *field, size_t *n, int *comps)
{
    const spr_cloud *c = &sc->s.cloud;
    *n = c->n;
    *comps = 3;
    if (!strcmp(field, "pos")) return c->pos;
    if (!strcmp(field, "nrm")) return c->nrm;
    if (!strcmp(field, "color")) return c->color;
    *comps = 1;
    if (!strcmp(field, "radius")) return c->radius;
    if (!strcmp(field, "alpha")) return c->alpha;
    fail(SPR_E_ARG, "cloud: the fields are pos, nrm, color, radius and alpha");
    return NULL;
}

/* The scene's GL options on device gl_device (−1: the surfaceless platform). */
static spr_gl_desc gl_of(const spr_ffi_scene *sc, int gl_device)
{
    spr_gl_desc d = sc->gl;
    d.device = gl_device;
    return d;
}

/* A backend by name (spr__backend; its error keeps its code, SPR_E_NO_DEVICE). */
static spr_backend *backend_of(spr_ffi_scene *sc, const char *name, int gl_device, char *renderer, size_t cap)
{
    if (name && strcmp(name, "cpu") && strcmp(name, "gl")) { fail(SPR_E_ARG, "backend: not cpu or gl"); return NULL; }
    memset(&sc->err, 0, sizeof sc->err);
    const spr_gl_desc gd = gl_of(sc, gl_device);
    spr_backend *b = spr__backend(&sc->a, name ? name : "cpu", sc->s.threads, &gd);
    if (!b) { fail_with(&sc->err); return NULL; }
    if (renderer) {
        if (name && !strcmp(name, "gl")) snprintf(renderer, cap, "gl [%s]", spr_gl_renderer(b));
        else snprintf(renderer, cap, "cpu reference");
    }
    return b;
}

spr_ffi_frame *spr_ffi_render(spr_ffi_scene *sc, const char *backend, int gl_device, int passes)
{
    if (sc->s.all_algos) { fail(SPR_E_ARG, "algo 'all' is for parity; render one algorithm"); return NULL; }
    spr_ffi_frame *f = calloc(1, sizeof *f);
    if (!f) { fail(SPR_E_NOMEM, "out of memory"); return NULL; }
    snprintf(f->backend, sizeof f->backend, "%s", backend && !strcmp(backend, "gl") ? "gl" : "cpu");
    spr_backend *b = backend_of(sc, backend, gl_device, f->renderer, sizeof f->renderer);
    if (!b) { free(f); return NULL; }
    spr_render_desc rd = sc->rd;
    f->cap.as_float = 1;
    if (passes) rd.hook = spr_capture_hook, rd.hook_user = &f->cap;
    spr_error err = {0};
    spr_result r = spr_render(b, &sc->s.view, &sc->s.cloud, &rd, &f->res, &err);
    spr_backend_destroy(b);
    if (!r && f->cap.failed) err = f->cap.err, r = err.code ? err.code : SPR_E_ARG;
    if (r) {
        fail_with(&err);
        spr_ffi_frame_free(f);
        return NULL;
    }
    return f;
}

void spr_ffi_frame_free(spr_ffi_frame *f)
{
    if (!f) return;
    spr_capture_free(&f->cap);
    spr_render_result_free(&f->res);
    free(f);
}

const float *spr_ffi_frame_image(const spr_ffi_frame *f, int *w, int *h)
{
    *w = f->res.width, *h = f->res.height;
    return f->res.rgba;
}

char *spr_ffi_frame_json(const spr_ffi_frame *f)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "backend", f->backend);
    cJSON_AddStringToObject(o, "renderer", f->renderer);
    cJSON_AddNumberToObject(o, "width", f->res.width);
    cJSON_AddNumberToObject(o, "height", f->res.height);
    cJSON_AddNumberToObject(o, "K", f->res.K);
    cJSON_AddNumberToObject(o, "eps_t", f->res.eps_t);
    cJSON *arr = cJSON_AddArrayToObject(o, "passes");
    for (int i = 0; i < f->cap.n; i++) {
        const spr_captured_pass *p = &f->cap.passes[i];
        cJSON *q = cJSON_CreateObject();
        cJSON_AddNumberToObject(q, "index", p->index);
        cJSON_AddStringToObject(q, "name", p->name);
        cJSON_AddNumberToObject(q, "group", p->group);
        cJSON_AddNumberToObject(q, "target", p->target);
        cJSON_AddBoolToObject(q, "composite", p->composite);
        cJSON *pl = cJSON_AddArrayToObject(q, "planes");
        for (int k = 0; k < SPR_PLANE__COUNT; k++)
            if (p->planes & SPR_PLANE_BIT(k)) cJSON_AddItemToArray(pl, cJSON_CreateString(spr_plane_name((spr_plane)k)));
        cJSON_AddNumberToObject(q, "generated", (double)p->stats.generated);
        cJSON_AddNumberToObject(q, "passed", (double)p->stats.passed);
        cJSON_AddNumberToObject(q, "ms", p->ms);
        cJSON_AddNumberToObject(q, "records", (double)p->n_records);
        cJSON_AddItemToArray(arr, q);
    }
    return json_text(o);
}

const float *spr_ffi_frame_plane(const spr_ffi_frame *f, int i, const char *plane, int *channels)
{
    if (i < 0 || i >= f->cap.n) { fail(SPR_E_ARG, "no such pass (render with passes kept)"); return NULL; }
    const spr_captured_pass *p = &f->cap.passes[i];
    for (int k = 0; k < SPR_PLANE__COUNT; k++)
        if (!strcmp(spr_plane_name((spr_plane)k), plane)) {
            if (!(p->planes & SPR_PLANE_BIT(k))) break;
            *channels = spr_plane_channels((spr_plane)k);
            return p->plane[k];
        }
    char m[160];
    snprintf(m, sizeof m, "pass %d (%s) has no plane '%s'", p->index, p->name, plane);
    fail(SPR_E_ARG, m);
    return NULL;
}

const float *spr_ffi_frame_records(const spr_ffi_frame *f, int i, size_t *rows, int *cols)
{
    if (i < 0 || i >= f->cap.n || !f->cap.passes[i].records) { fail(SPR_E_ARG, "that pass has no records (a Gaussian preprocessing pass has)"); return NULL; }
    *rows = f->cap.passes[i].n_records;
    *cols = SPR_GREC_FLOATS;
    return f->cap.passes[i].records;
}

char *spr_ffi_check(spr_ffi_scene *sc, const void *image, int w, int h, int ch, int bits, const char *label, const char *plane, int pass,
                    const char *tier, double ulp, int lsb, int position, unsigned char *state)
{
    spr__args *a = &sc->a;
    memset(&sc->err, 0, sizeof sc->err);
    if (bits != 8 && bits != 16 && bits != 32) { fail(SPR_E_ARG, "check: an image of uint8, uint16 or float32 values"); return NULL; }
    if (w != sc->s.view.width || h != sc->s.view.height) {
        char m[200];
        snprintf(m, sizeof m, "check: the image is %dx%d, the scene renders %dx%d", w, h, sc->s.view.width, sc->s.view.height);
        fail(SPR_E_ARG, m);
        return NULL;
    }
    if (ch < 1 || ch > 4) { fail(SPR_E_ARG, "check: 1 to 4 channels"); return NULL; }
    spr_check_desc d;
    if (spr__check_tier(a, tier, ulp, lsb, position, bits, &d)) { fail_with(&sc->err); return NULL; }
    const size_t nv = (size_t)w * h * ch;
    float *test = malloc(nv * sizeof *test), *ref = NULL;
    if (!test) { fail(SPR_E_NOMEM, "out of memory"); return NULL; }
    for (size_t i = 0; i < nv; i++) /* as the PNG reader: v / 255 (or 65535), divided, correctly rounded */
        test[i] = bits == 8 ? (float)((const uint8_t *)image)[i] / 255.0f
                  : bits == 16 ? (float)((const uint16_t *)image)[i] / 65535.0f : ((const float *)image)[i];
    int tch = ch, rch;
    char what[96];
    char *out = NULL;
    if (spr__check_reference(a, &sc->s, &sc->rd, plane, pass, &ref, &rch, what, sizeof what) ||
        spr__check_channels(a, label ? label : "the image", &test, &tch, rch, w, h)) {
        fail_with(&sc->err);
        goto done;
    }
    spr_check_result r;
    spr_check_images_state(ref, test, w, h, rch, &d, &r, NULL, state);
    char ref_label[160];
    snprintf(ref_label, sizeof ref_label, "reference (cpu, %s)", spr_algo_name(sc->rd.algo));
    out = json_text(spr__check_json(ref_label, label ? label : "image", what, w, h, rch, &d, &r, NULL));
done:
    free(test);
    free(ref);
    return out;
}

char *spr_ffi_explain(spr_ffi_scene *sc, int x, int y, const char *which, int gl_device)
{
    if (!which) which = "both";
    if (strcmp(which, "both") && strcmp(which, "cpu") && strcmp(which, "gl")) { fail(SPR_E_ARG, "explain: backend is both, cpu or gl"); return NULL; }
    if (sc->s.all_algos) { fail(SPR_E_ARG, "algo 'all' is for parity; explain one algorithm"); return NULL; }
    if (x < 0 || y < 0 || x >= sc->s.view.width || y >= sc->s.view.height) {
        char m[160];
        snprintf(m, sizeof m, "explain: pixel %d,%d lies outside the %dx%d image", x, y, sc->s.view.width, sc->s.view.height);
        fail(SPR_E_ARG, m);
        return NULL;
    }
    spr__history_run runs[2];
    memset(runs, 0, sizeof runs);
    int nr = 0;
    char *out = NULL;
    spr_error err = {0};
    const spr_gl_desc gd = gl_of(sc, gl_device);
    if (strcmp(which, "gl")) {
        if (spr__history_run_one(&sc->s, &sc->rd, "cpu", &gd, x, y, &runs[nr], &err)) { fail_with(&err); goto done; }
        nr++;
    }
    if (strcmp(which, "cpu")) {
        const int r = spr__history_run_one(&sc->s, &sc->rd, "gl", &gd, x, y, &runs[nr], &err);
        if (r < 0 || (r > 0 && !strcmp(which, "gl"))) { fail_with(&err); goto done; }
        if (r == 0) nr++;
    }
    out = json_text(spr__explain_json(&sc->s, &sc->rd, x, y, runs, nr));
done:
    for (int i = 0; i < 2; i++) spr_history_free(&runs[i].h);
    return out;
}

char *spr_ffi_parity(spr_ffi_scene *sc, const char *algo, int gl_device)
{
    int want = -1;
    if (algo && strcmp(algo, "all")) {
        for (int k = 0; k < SPR_ALGO__COUNT; k++)
            if (!strcmp(spr_algo_name((spr_algo)k), algo)) want = k;
        if (want < 0) { fail(SPR_E_ARG, "parity: no such algorithm"); return NULL; }
    } else if (!algo && !sc->s.all_algos) {
        want = (int)sc->rd.algo;
    }
    spr_backend *cpu = NULL, *gl = NULL;
    spr_parity_report reps[SPR_ALGO__COUNT];
    memset(reps, 0, sizeof reps);
    int nrep = 0;
    char *out = NULL;
    if (!(gl = backend_of(sc, "gl", gl_device, NULL, 0)) || !(cpu = backend_of(sc, "cpu", -1, NULL, 0))) goto done;
    spr__parity_set set = {NULL, &sc->s, spr_gl_renderer(gl), 0, {0}, {0}};
    for (int k = 0; k < SPR_ALGO__COUNT; k++) {
        if (want >= 0 && k != want) continue;
        spr_render_desc d = sc->rd;
        d.algo = (spr_algo)k;
        if (!(spr_algo_info_of(d.algo)->uses & SPR_USES_GROUPS)) d.groups = NULL;
        spr_error err = {0};
        if (spr_parity_run(cpu, gl, &sc->s.view, &sc->s.cloud, &d, &d, NULL, spr_algo_name(d.algo), &reps[nrep], &err)) {
            fail_with(&err);
            goto done;
        }
        set.algo[nrep] = spr_algo_name(d.algo);
        set.rep[nrep] = &reps[nrep];
        set.n = ++nrep;
    }
    out = json_text(spr__parity_json(&set));
done:
    for (int i = 0; i < nrep; i++) spr_parity_report_free(&reps[i]);
    spr_backend_destroy(cpu);
    spr_backend_destroy(gl);
    return out;
}

struct spr_ffi_grads {
    char backend[8], renderer[600];
    const char *profile, *loss;
    spr_gauss_grads g;
    float *sh0, *shN; /* g.sh (coefficient-major, sh_k a Gaussian) split as grad's .npz holds it */
};

spr_ffi_grads *spr_ffi_grad(spr_ffi_scene *sc, const char *backend, int gl_device, const char *loss, const float *target,
                            const float *dl_dimage, const float *dl_dalpha, const float *dl_ddepth, size_t batch)
{
    if (sc->s.all_algos) { fail(SPR_E_ARG, "algo 'all' is for parity; grad is gauss3d's"); return NULL; }
    spr_grad_desc gd;
    memset(&gd, 0, sizeof gd);
    if (loss && dl_dimage) { fail(SPR_E_ARG, "grad: a loss and dl_dimage both give the upstream gradient: give one"); return NULL; }
    if (!loss && !dl_dimage) { fail(SPR_E_ARG, "grad: give the upstream gradient: loss l1|l2 (with a target, default black), or dl_dimage"); return NULL; }
    if (loss) {
        if (!strcmp(loss, "l1")) gd.loss = SPR_LOSS_L1;
        else if (!strcmp(loss, "l2")) gd.loss = SPR_LOSS_L2;
        else {
            char m[160];
            snprintf(m, sizeof m, "grad: loss '%.60s' is not l1 or l2", loss);
            fail(SPR_E_ARG, m);
            return NULL;
        }
        gd.target = target;
    } else {
        if (target) { fail(SPR_E_ARG, "grad: a target goes with a loss (l1 or l2), not with dl_dimage"); return NULL; }
        gd.dl_dimage = dl_dimage;
    }
    gd.dl_dalpha = dl_dalpha, gd.dl_ddepth = dl_ddepth, gd.batch = batch;
    spr_ffi_grads *f = calloc(1, sizeof *f);
    if (!f) { fail(SPR_E_NOMEM, "out of memory"); return NULL; }
    snprintf(f->backend, sizeof f->backend, "%s", backend && !strcmp(backend, "gl") ? "gl" : "cpu");
    f->loss = gd.loss == SPR_LOSS_L1 ? "l1" : gd.loss == SPR_LOSS_L2 ? "l2" : NULL;
    f->profile = spr_gauss_profile_of(sc->rd.algo, sc->rd.gauss_profile)->name;
    spr_backend *b = backend_of(sc, backend, gl_device, f->renderer, sizeof f->renderer);
    if (!b) { free(f); return NULL; }
    spr_error err = {0};
    spr_result r = spr_gauss_grad(b, &sc->s.view, &sc->s.cloud, &sc->rd, &gd, &f->g, &err);
    spr_backend_destroy(b);
    if (r) {
        fail_with(&err);
        free(f);
        return NULL;
    }
    const size_t n = f->g.n, K = f->g.sh_k > 0 ? (size_t)f->g.sh_k : 0;
    f->sh0 = calloc(n * 3 + 1, sizeof *f->sh0), f->shN = calloc(n * (K > 1 ? K - 1 : 0) * 3 + 1, sizeof *f->shN);
    if (!f->sh0 || !f->shN) {
        fail(SPR_E_NOMEM, "out of memory");
        spr_ffi_grads_free(f);
        return NULL;
    }
    for (size_t G = 0; G < n; G++) {
        if (K > 0) memcpy(f->sh0 + 3 * G, f->g.sh + G * K * 3, 3 * sizeof(float));
        if (K > 1) memcpy(f->shN + G * (K - 1) * 3, f->g.sh + G * K * 3 + 3, (K - 1) * 3 * sizeof(float));
    }
    return f;
}

void spr_ffi_grads_free(spr_ffi_grads *f)
{
    if (!f) return;
    spr_gauss_grads_free(&f->g);
    free(f->sh0), free(f->shN);
    free(f);
}

/* Array i of spr_gauss_grads_arrays as grad's .npz has it: its data, shape (n, then up to two more) and type. */
static const void *grads_member(const spr_ffi_grads *f, const spr_grad_array *ga, size_t shape[3], int *ndim, int *is_int)
{
    const size_t n = f->g.n, K = f->g.sh_k > 0 ? (size_t)f->g.sh_k : 0;
    shape[0] = n, *ndim = 1, *is_int = 0;
    if (!strcmp(ga->name, "sh0")) { shape[1] = 1, shape[2] = 3, *ndim = 3; return f->sh0; }
    if (!strcmp(ga->name, "shN")) { shape[1] = K > 1 ? K - 1 : 0, shape[2] = 3, *ndim = 3; return f->shN; }
    if (!strcmp(ga->name, "counts")) { *is_int = 1; return f->g.counts; }
    if (ga->per > 1) shape[1] = (size_t)ga->per, *ndim = 2;
    return ga->data;
}

char *spr_ffi_grads_json(const spr_ffi_grads *f)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "backend", f->backend);
    cJSON_AddStringToObject(o, "renderer", f->renderer);
    cJSON_AddStringToObject(o, "profile", f->profile);
    cJSON_AddNumberToObject(o, "gaussians", (double)f->g.n);
    cJSON_AddNumberToObject(o, "sh_k", f->g.sh_k);
    cJSON_AddNumberToObject(o, "width", f->g.width);
    cJSON_AddNumberToObject(o, "height", f->g.height);
    if (f->loss) cJSON_AddStringToObject(o, "loss", f->loss);
    else cJSON_AddNullToObject(o, "loss");
    cJSON_AddNumberToObject(o, "loss_value", f->g.loss);
    cJSON_AddNumberToObject(o, "ms_forward", f->g.ms_forward);
    cJSON_AddNumberToObject(o, "ms_backward", f->g.ms_backward);
    cJSON *arr = cJSON_AddArrayToObject(o, "arrays");
    spr_grad_array ga[16];
    const int na = spr_gauss_grads_arrays(&f->g, ga, 16);
    for (int i = 0; i < na && i < 16; i++) {
        size_t shape[3];
        int nd, is_int;
        grads_member(f, &ga[i], shape, &nd, &is_int);
        cJSON *q = cJSON_CreateObject(), *sh = cJSON_AddArrayToObject(q, "shape");
        cJSON_AddStringToObject(q, "name", ga[i].name);
        for (int d = 0; d < nd; d++) cJSON_AddItemToArray(sh, cJSON_CreateNumber((double)shape[d]));
        cJSON_AddStringToObject(q, "dtype", is_int ? "int32" : "float32");
        cJSON_AddItemToArray(arr, q);
    }
    return json_text(o);
}

const void *spr_ffi_grads_array(const spr_ffi_grads *f, const char *name, size_t *count)
{
    spr_grad_array ga[16];
    const int na = spr_gauss_grads_arrays(&f->g, ga, 16);
    for (int i = 0; i < na && i < 16; i++) {
        if (strcmp(ga[i].name, name)) continue;
        size_t shape[3];
        int nd, is_int;
        const void *p = grads_member(f, &ga[i], shape, &nd, &is_int);
        *count = 1;
        for (int d = 0; d < nd; d++) *count *= shape[d];
        return p;
    }
    char m[200];
    snprintf(m, sizeof m, "grad: no array '%.40s' (means, quats, scales, opacities, sh0, shN, means2d, conics, colors, absgrad, counts)", name);
    fail(SPR_E_ARG, m);
    return NULL;
}

const float *spr_ffi_grads_image(const spr_ffi_grads *f, int *w, int *h)
{
    *w = f->g.width, *h = f->g.height;
    return f->g.image;
}

int spr_ffi_write_image(const char *path, const float *img, int w, int h, int ch)
{
    spr_error err = {0};
    const size_t n = strlen(path);
    const int pfm = n > 4 && !strcmp(path + n - 4, ".pfm");
    if (!(n > 4 && (pfm || !strcmp(path + n - 4, ".png")))) { fail(SPR_E_ARG, "write_image: a .png or .pfm name"); return -1; }
    if ((pfm ? spr_write_pfm(path, img, w, h, ch, &err) : spr_write_png(path, img, w, h, ch, &err))) { fail_with(&err); return -1; }
    return 0;
}
