/* cli_misc.c — `splatref info`, `splatref sample`, `splatref show`. */
#include "cli.h"
#include "spr__inspect.h"
#include "spr_profile_diff.h"
#include "spr__scene_opts.h"
#include "spr_image.h"

#include <math.h>
#include <unistd.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const spr__opt info_opts[] = {SPR__MODEL_OPTS, {NULL, NULL, NULL}}; /* without --model: what the library contains */

int cmd_info(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "info", info_opts, "[--model M]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    const char *model = spr__get(&a, "model");
    spr_load_desc ld;
    spr_scene sc;
    memset(&sc, 0, sizeof sc);
    if ((model && spr__model_opts(&a, &sc, &ld)) || (spr__flag(&a, "quiet"), spr__reject_unused(&a))) return 2;
    if (!model) { /* the registries: what can be rendered, composited and stored */
        printf("algorithms:\n");
        for (int al = 0; al < SPR_ALGO__COUNT; al++)
            printf("  %-12s SPEC %-4s %s\n", spr_algo_name((spr_algo)al), spr_algo_info_of((spr_algo)al)->spec,
                   spr_algo_info_of((spr_algo)al)->summary);
        printf("composite ops:\n");
        for (int op = 0; op < SPR_COMP__COUNT; op++)
            printf("  %-12s %s\n", spr_composite_info_of((spr_composite_op)op)->name, spr_composite_info_of((spr_composite_op)op)->summary);
        printf("target planes:\n");
        for (int p = 0; p < SPR_PLANE__COUNT; p++)
            printf("  %-12s %d channel%s\n", spr_plane_name((spr_plane)p), spr_plane_channels((spr_plane)p),
                   spr_plane_channels((spr_plane)p) > 1 ? "s" : "");
        printf("grouping methods:\n ");
        for (int m = 0; m < SPR_GROUP__COUNT; m++) printf(" %s", spr_group_method_name((spr_group_method)m));
        printf("\n");
        return 0;
    }
    spr_cloud c;
    spr_error err = {0};
    if (spr_load(model, &ld, &c, &err)) { fprintf(stderr, "splatref info: %s\n", err.msg); return 2; }
    spr_bounds b;
    spr_cloud_bounds(&c, &b);
    printf("model:    %s\nsplats:   %zu\n", model, c.n);
    printf("bounds:   [%g, %g, %g] .. [%g, %g, %g]\n", b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2]);
    printf("radius:   min %g  mean %g  max %g\n", b.min_radius, b.mean_radius, b.max_radius);
    const int gs = c.gauss_cut > 0.0f;
    if (c.ell) { /* elliptical splats: how flat */
        size_t ne = 0;
        double ratio = 0.0, rmin = 1.0;
        for (size_t i = 0; i < c.n; i++)
            if (c.ell[4 * i + 3] != c.radius[i]) {
                const double q = (double)c.ell[4 * i + 3] / c.radius[i];
                ne++, ratio += q, rmin = q < rmin ? q : rmin;
            }
        printf("shape:    %zu elliptical splats (r_v / r_u mean %.3g, min %.3g), %zu circles\n", ne, ne ? ratio / (double)ne : 1.0, rmin, c.n - ne);
    }
    if (gs)
        printf("capture:  Gaussian splats as surfels: the two largest axes, cut at %g sigma (--gauss-cut); colour from SH %s\n", c.gauss_cut,
               c.sh ? "up to the degree of --sh-degree, per view" : "degree 0 (DC)");
    printf("normals:  %s\n", gs ? "the smallest axis of each Gaussian" : c.flags & SPR_SRC_NORMALS ? "from the file" : c.flags & SPR_SRC_FACES ? "from mesh faces (area-weighted)" : "PCA of 10 nearest neighbours");
    printf("colours:  %s\n", gs ? "0.5 + C0*f_dc, clamped to [0,1]" : c.flags & SPR_SRC_COLORS ? "from the file" : "0.5*normal + 0.5");
    printf("radii:    %s\n", gs ? "cut x sigma of the two largest axes" : c.flags & SPR_SRC_RADII ? "from the file" : "1.0 x distance to the 8th neighbour");
    printf("opacity:  %s\n", ld.opacity > 0.0 ? "--opacity" : gs ? "sigmoid of the file's opacity" : c.flags & SPR_SRC_ALPHA ? "from the file" : "1");
    if (ld.balls > 0) printf("balls:    %d opaque balls inside (--balls), included above\n", ld.balls);
    spr_cloud_free(&c);
    return 0;
}

static const spr__opt sample_opts[] = {
    {"model", "MESH", "mesh to resample (.off, or .ply with faces)"},
    {"points", "N", "number of points"},
    {"seed", "S", "random seed (default 1)"},
    {"radius-k", "K", "radius rule r = rho*d_k: k (default 8)"},
    {"radius-scale", "RHO", "radius rule: rho (default 1.0)"},
    {"out", "F.ply", "output PLY"},
    {"gaussians", NULL, "write a 3DGS capture (SH degree 3, sigma r/3 along the surface and r/300 across it) instead of surfels"},
    {"sh-noise", NULL, "with --gaussians: random SH coefficients of degrees 1-3 (seeded by --seed), so the colour changes with the view"},
    {"quiet", NULL, "no progress on stderr"},
    {NULL, NULL, NULL}};

int cmd_sample(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "sample", sample_opts, "--model M --points N --out F.ply", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    const char *model = spr__get(&a, "model"), *out = spr__get(&a, "out");
    size_t n = 0, seed = 1;
    if (!model || !out || !spr__get(&a, "points")) { spr__error(&a, "--model, --points and --out are required"); return 2; }
    if (spr__get_size(&a, "points", &n, 2, SPR_MAX_SPLATS) < 0 || spr__get_size(&a, "seed", &seed, 0, (size_t)-1) < 0) return 2;
    spr_load_desc ld;
    spr_load_defaults(&ld);
    if (spr__get_int(&a, "radius-k", &ld.radius_k, 1, 256) < 0 || spr__get_double(&a, "radius-scale", &ld.radius_rho, 1e-6, 1e6) < 0)
        return 2;
    ld.progress = spr__progress(spr__flag(&a, "quiet"));
    ld.warn = spr__warn(&a);
    spr_cloud c;
    spr_error err = {0};
    const int gauss = spr__flag(&a, "gaussians"), noise = spr__flag(&a, "sh-noise");
    if (noise && !gauss) { spr__error(&a, "--sh-noise needs --gaussians"); return 2; }
    if (spr__reject_unused(&a)) return 2;
    if (spr_sample_mesh(model, n, seed, &ld, &c, &err) ||
        (gauss ? spr_write_gauss_ply_of_cloud(out, &c, noise ? (uint64_t)seed * 2654435761u + 1u : 0, &err) : spr_write_ply(out, &c, &err))) {
        fprintf(stderr, "splatref sample: %s\n", err.msg);
        return 2;
    }
    printf("sample: %zu points of %s -> %s%s\n", c.n, model, out, gauss ? noise ? " (3DGS capture, SH degree 3, random higher bands)" : " (3DGS capture, SH degree 3, DC only)" : "");
    spr_cloud_free(&c);
    return 0;
}

static const spr__opt show_opts[] = {
    {"out", "FILE.png", "the picture (required)"},
    {"range", "LO,HI", "map LO..HI to black..white (default: the plane's finite range; -1 = none is excluded)"},
    {NULL, NULL, NULL}};

/* `splatref show PLANE.pfm --out P.png`: a dump plane as a picture (grey for
 * 1-channel planes, colour for RGB), values mapped linearly from a range. */
int cmd_show(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "show", show_opts, "PLANE.pfm --out FILE.png [--range LO,HI]", 1, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    if (a.n_positional != 1 || !spr__get(&a, "out")) { spr__error(&a, "a PFM file and --out are required"); return 2; }
    float *im;
    int w, h, ch;
    spr_error err = {0};
    if (spr_read_pfm(a.positional[0], &im, &w, &h, &ch, &err)) { fprintf(stderr, "splatref show: %s\n", err.msg); return 2; }
    double lo = INFINITY, hi = -INFINITY;
    const char *range = spr__get(&a, "range");
    if (range) {
        char tail;
        if (sscanf(range, "%lf,%lf%c", &lo, &hi, &tail) != 2 || !(hi > lo)) { spr__error(&a, "--range: '%s' is not LO,HI with HI > LO", range); free(im); return 2; }
    } else {
        for (size_t i = 0; i < (size_t)w * h * ch; i++)
            if (isfinite(im[i]) && im[i] != -1.0f) { lo = im[i] < lo ? im[i] : lo; hi = im[i] > hi ? im[i] : hi; }
        if (!(hi > lo)) { lo = 0.0; hi = lo + 1.0; }
    }
    for (size_t i = 0; i < (size_t)w * h * ch; i++) im[i] = (float)((im[i] - lo) / (hi - lo));
    int rc = 0;
    if (spr_write_png(spr__get(&a, "out"), im, w, h, ch, &err)) { fprintf(stderr, "splatref show: %s\n", err.msg); rc = 2; }
    else printf("show: %s [%g, %g] -> %s\n", a.positional[0], lo, hi, spr__get(&a, "out"));
    free(im);
    return rc;
}

const char *cli_data_dir(void)
{
    const char *d = getenv("SPLATREF_DATA");
    if (d && *d) return d;
    if (access("data/cgal/data/meshes", F_OK) == 0) return "data/cgal/data";
    return SPR_DEFAULT_DATA; /* the source tree this binary was built from */
}

/* splatref profiles: the renderer profile table (SPEC 10.9), the one the options, scene files and Python read. */
static const spr__opt profiles_opts[] = {
    {"markdown", NULL, "the Markdown table that docs/gaussians.md embeds"},
    {"json", NULL, "the table as JSON (what Python's splatref.profiles() returns)"},
    {NULL, NULL, NULL}};

int cmd_profiles(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "profiles", profiles_opts, "[--markdown | --json]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    const int md = spr__flag(&a, "markdown"), js = spr__flag(&a, "json");
    if (md && js) { spr__error(&a, "--markdown and --json: give one"); return 2; }
    if (spr__reject_unused(&a)) return 2;
    if (md) {
        spr__profiles_markdown(stdout);
        return 0;
    }
    if (js) {
        cJSON *o = spr__profiles_json();
        char *t = o ? cJSON_Print(o) : NULL;
        cJSON_Delete(o);
        if (!t) { spr__error(&a, "out of memory"); return 2; }
        printf("%s\n", t);
        free(t);
        return 0;
    }
    for (int i = 0; i < spr_gauss_profile_count(); i++) {
        const spr_gauss_profile *p = spr_gauss_profile_at(i);
        printf("%s (%s): %s, %s\n  source: %s\n", p->name, spr_algo_name(p->skeleton), p->renderer, p->version, p->source);
        for (int r = 1; r <= 9; r++) {
            char t[256];
            spr__profile_rule_text(p, r, t, sizeof t);
            printf("  %-28s %s\n", spr__gauss_rule_names[r], t);
        }
    }
    return 0;
}
