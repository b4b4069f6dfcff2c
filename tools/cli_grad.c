/* cli_grad.c — `splatref grad`: the backward pass of gauss3d (SPEC 10.10)
 * for a scene and an upstream gradient (a loss against a target image, or
 * ∂L/∂image from a file), written as one .npz of gsplat's arrays; and what
 * `check --grads` and parity share with it: reading an upstream gradient,
 * the arrays as .npz members. */
#include "cli.h"
#include "cli_grad.h"
#include "spr__scene_opts.h"
#include "spr_image.h"
#include "spr_npy.h"
#include "spr_util.h"

#include <stdlib.h>
#include <string.h>

/* An image-shaped array of `ch` channels from a .npy (float [H, W, ch] or [H, W] for ch 1, row 0 the top) or a PFM,
 * into W·H·ch floats with row 0 the bottom; 0, or −1 after one line. */
static int read_plane_file(spr__args *a, const char *opt, const char *path, int W, int H, int ch, float **out)
{
    spr_error err = {0};
    const size_t n = strlen(path);
    *out = NULL;
    if (n > 4 && !strcmp(path + n - 4, ".npy")) {
        spr_npy m;
        if (spr_npy_read(path, &m, &err)) { fprintf(stderr, "splatref %s: --%s: %s\n", a->cmd, opt, err.msg); return -1; }
        const int ok = m.type == SPR_NPY_F4 && m.shape[0] == (size_t)H && m.shape[1] == (size_t)W &&
                       ((ch == 1 && m.ndim == 2) || (m.ndim == 3 && m.shape[2] == (size_t)ch));
        if (!ok) {
            char shape[96] = "";
            for (int d = 0, o = 0; d < m.ndim && o < (int)sizeof shape; d++) o += snprintf(shape + o, sizeof shape - (size_t)o, "%s%zu", d ? ", " : "", m.shape[d]);
            spr__error(a, "--%s: %s is a %s array of shape [%s]; the scene needs float32 [%d, %d%s] (row 0 the top row)", opt, path,
                       m.type == SPR_NPY_F4 ? "float" : "integer", shape, H, W, ch == 1 ? "" : ch == 3 ? ", 3" : ", 4");
            spr_npy_free(&m);
            return -1;
        }
        float *img = malloc((size_t)W * H * (size_t)ch * sizeof *img);
        if (!img) { spr_npy_free(&m); spr__error(a, "out of memory"); return -1; }
        const float *src = m.data;
        for (int j = 0; j < H; j++) memcpy(img + (size_t)(H - 1 - j) * W * ch, src + (size_t)j * W * ch, (size_t)W * ch * sizeof *img);
        spr_npy_free(&m);
        *out = img;
        return 0;
    }
    float *img = NULL;
    int w, h, c;
    if (spr_read_image(path, &img, &w, &h, &c, &err)) { fprintf(stderr, "splatref %s: --%s: %s\n", a->cmd, opt, err.msg); return -1; }
    if (w != W || h != H || (ch == 1 && c != 1) || (ch == 3 && c < 3)) {
        spr__error(a, "--%s: %s is %dx%d with %d channel%s; the scene needs %dx%d with %d", opt, path, w, h, c, c == 1 ? "" : "s", W, H, ch);
        free(img);
        return -1;
    }
    if (ch == 3 && c != 3) { /* RGBA: the first three */
        for (size_t i = 0; i < (size_t)W * H; i++) memmove(img + 3 * i, img + (size_t)c * i, 3 * sizeof *img);
    }
    *out = img;
    return 0;
}

void cli_grad_claim(spr__args *a)
{
    static const char *const names[] = {"loss", "loss-target", "dl-dimage", "dl-dalpha", "dl-ddepth", "grad-batch"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) spr__get(a, names[i]);
}

int cli_grad_upstream(spr__args *a, int W, int H, spr_grad_desc *gd, cli_grad_inputs *in)
{
    memset(gd, 0, sizeof *gd);
    memset(in, 0, sizeof *in);
    const char *loss = spr__get(a, "loss"), *target = spr__get(a, "loss-target"), *dl = spr__get(a, "dl-dimage");
    const char *da = spr__get(a, "dl-dalpha"), *dd = spr__get(a, "dl-ddepth");
    if (loss && dl) { spr__error(a, "--loss and --dl-dimage both give the upstream gradient: give one"); return -1; }
    if (!loss && !dl) { spr__error(a, "give the upstream gradient: --loss l1|l2 [--loss-target IMG], or --dl-dimage G.npy|G.pfm"); return -1; }
    if (loss) {
        if (!strcmp(loss, "l1")) gd->loss = SPR_LOSS_L1;
        else if (!strcmp(loss, "l2")) gd->loss = SPR_LOSS_L2;
        else { spr__error(a, "--loss: '%s' is not l1 or l2", loss); return -1; }
        if (target && read_plane_file(a, "loss-target", target, W, H, 3, &in->target)) return -1; /* none: a black target */
        gd->target = in->target;
    } else {
        if (target) { spr__error(a, "--loss-target goes with --loss"); return -1; }
        if (read_plane_file(a, "dl-dimage", dl, W, H, 3, &in->dl)) return -1;
        gd->dl_dimage = in->dl;
    }
    if (da && read_plane_file(a, "dl-dalpha", da, W, H, 1, &in->da)) return -1;
    if (dd && read_plane_file(a, "dl-ddepth", dd, W, H, 1, &in->dd)) return -1;
    gd->dl_dalpha = in->da, gd->dl_ddepth = in->dd;
    size_t batch = 0;
    if (spr__get_size(a, "grad-batch", &batch, 1, (size_t)1 << 40) < 0) return -1;
    gd->batch = batch;
    return 0;
}

int cli_grad_frame(spr__args *a, const char *bname, const spr_gl_desc *gld, spr_scene *s, spr_render_desc *rd, spr_grad_desc *gd,
                   cli_grad_inputs *in, spr_backend **b, spr_gauss_grads *g)
{
    spr_error err = {0};
    cli_grad_claim(a);
    if (spr__scene_setup(a, s, rd, 0) || cli_grad_upstream(a, s->view.width, s->view.height, gd, in)) return -1;
    if (!(*b = spr__backend(a, bname, s->threads, gld))) return -1;
    if (spr_gauss_grad(*b, &s->view, &s->cloud, rd, gd, g, &err)) {
        fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg);
        return -1;
    }
    return 0;
}

void cli_grad_inputs_free(cli_grad_inputs *in)
{
    free(in->target), free(in->dl), free(in->da), free(in->dd);
    memset(in, 0, sizeof *in);
}

int cli_grad_npz(const spr_gauss_grads *g, spr_npy *arr, int cap, float **sh0, float **shN)
{
    spr_grad_array ga[16];
    const int na = spr_gauss_grads_arrays(g, ga, 16);
    const size_t n = g->n, K = (size_t)g->sh_k;
    *sh0 = calloc(n * 3 + 1, sizeof **sh0), *shN = calloc(n * (K > 1 ? K - 1 : 0) * 3 + 1, sizeof **shN);
    if (!*sh0 || !*shN) return -1;
    for (size_t G = 0; G < n; G++) {
        if (K > 0) memcpy(*sh0 + 3 * G, g->sh + G * K * 3, 3 * sizeof(float));
        if (K > 1) memcpy(*shN + G * (K - 1) * 3, g->sh + G * K * 3 + 3, (K - 1) * 3 * sizeof(float));
    }
    int m = 0;
    for (int i = 0; i < na && m < cap; i++) {
        spr_npy *o = &arr[m++];
        memset(o, 0, sizeof *o);
        snprintf(o->name, sizeof o->name, "%s", ga[i].name);
        o->type = SPR_NPY_F4;
        o->shape[0] = n;
        o->data = ga[i].data;
        if (!strcmp(ga[i].name, "sh0")) o->ndim = 3, o->shape[1] = 1, o->shape[2] = 3, o->data = *sh0;
        else if (!strcmp(ga[i].name, "shN")) o->ndim = 3, o->shape[1] = K > 1 ? K - 1 : 0, o->shape[2] = 3, o->data = *shN;
        else if (!strcmp(ga[i].name, "counts")) o->ndim = 1, o->type = SPR_NPY_I4, o->data = g->counts;
        else if (ga[i].per == 1) o->ndim = 1;
        else o->ndim = 2, o->shape[1] = (size_t)ga[i].per;
    }
    return m;
}

static const spr__opt grad_opts[] = {
    CLI_GRAD_OPTS,
    {"out", "F.npz", "the gradients, gsplat's names and shapes (default grads.npz)"},
    {"backend", "NAME", "cpu (default) | gl"},
    {"gl-device", "N", "GL backend: the N-th EGL device instead of the surfaceless platform"},
    SPR__SCENE_OPTS,
    {NULL, NULL, NULL}};

int cmd_grad(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "grad", grad_opts, "--scene S.json | [scene options]  --loss l1|l2 [--loss-target IMG] | --dl-dimage G.npy|G.pfm  [--out grads.npz]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    const char *out = spr__get(&a, "out") ? spr__get(&a, "out") : "grads.npz", *bname = spr__get(&a, "backend") ? spr__get(&a, "backend") : "cpu";
    spr_gl_desc gld;
    spr_gl_defaults(&gld);
    if (strcmp(bname, "cpu") && strcmp(bname, "gl")) { spr__error(&a, "--backend: '%s' is not cpu or gl", bname); return 2; }
    if (!strcmp(bname, "gl") && spr__gl_opts(&a, &gld) < 0) return 2;
    spr_scene s;
    spr_render_desc rd;
    spr_grad_desc gd;
    cli_grad_inputs in = {0};
    spr_gauss_grads g = {0};
    spr_backend *b = NULL;
    spr_error err = {0};
    float *sh0 = NULL, *shN = NULL;
    int rc = 2;
    memset(&s, 0, sizeof s);
    if (cli_grad_frame(&a, bname, &gld, &s, &rd, &gd, &in, &b, &g)) goto done;
    spr_npy arr[16];
    const int m = cli_grad_npz(&g, arr, 16, &sh0, &shN);
    if (m < 0) { spr__error(&a, "out of memory"); goto done; }
    if (spr_npz_write(out, arr, m, &err)) { fprintf(stderr, "splatref grad: %s\n", err.msg); goto done; }
    size_t reached = 0;
    for (size_t G = 0; G < g.n; G++) reached += g.counts[G] > 0;
    const spr_gauss_profile *pf = spr_gauss_profile_of(rd.algo, rd.gauss_profile);
    printf("grad: %s, %zu Gaussians (%zu reach a pixel), gauss3d under %s, %dx%d, %s backend", s.model, g.n, reached, pf->name, g.width, g.height, b->name);
    if (gd.loss != SPR_LOSS_GIVEN) printf(", loss %s %.9g", gd.loss == SPR_LOSS_L1 ? "l1" : "l2", g.loss);
    printf(", forward %.1f ms, backward %.1f ms -> %s (", g.ms_forward, g.ms_backward, out);
    for (int i = 0; i < m; i++) printf("%s%s", i ? ", " : "", arr[i].name);
    printf(")\n");
    rc = 0;
done:
    free(sh0), free(shN);
    spr_gauss_grads_free(&g);
    cli_grad_inputs_free(&in);
    if (b) spr_backend_destroy(b);
    spr_scene_free(&s);
    return rc;
}

int cli_grad_parity(FILE *f, spr_backend *cpu, spr_backend *gl, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *rd,
                    const spr_grad_desc *gd, spr_error *err)
{
    spr_gauss_grads a, b;
    if (spr_gauss_grad(cpu, view, cloud, rd, gd, &a, err)) return -1;
    if (spr_gauss_grad(gl, view, cloud, rd, gd, &b, err)) {
        spr_gauss_grads_free(&a);
        return -1;
    }
    spr_grad_diff d[16];
    const int m = spr_gauss_grad_compare(&a, &b, d, 16);
    int exact = 1;
    for (int i = 0; i < m; i++) {
        if (!d[i].differing) continue;
        exact = 0;
        fprintf(f, "  gradient %s: %zu of %zu Gaussians differ, first %ld: cpu %.9g, gl %.9g\n", d[i].name, d[i].differing, d[i].gaussians,
                d[i].first, d[i].va[0], d[i].vb[0]);
    }
    if (exact) fprintf(f, "  gradients (%d arrays, %zu Gaussians): BIT-EXACT\n", m, a.n);
    spr_gauss_grads_free(&a);
    spr_gauss_grads_free(&b);
    return exact;
}
