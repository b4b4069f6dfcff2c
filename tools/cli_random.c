/* cli_random.c — `splatref parity --random N`: differential fuzzing of the
 * two backends on generated adversarial scenes.
 *
 * Scene i of seed S is a pure function of (S, i): image size, a camera
 * (perspective or orthographic, given in full, so a scene is replayable from
 * the command line), splats with some of these features switched on —
 * coplanar and coincident splats, centres on pixel centres and pixel edges,
 * equal depths, pairs exactly ε apart in depth, tiny and huge radii, grazing
 * and exactly edge-on normals, splats crossing the near plane, a scene scaled
 * down until its arithmetic meets denormals — random groups, kernel, Voronoi
 * and ε; and, drawn last, Gaussian captures (SPEC 10: anisotropic, needle-thin,
 * huge, on tile borders, about the near plane, deep stacks, SH degree 3,
 * --gauss-aa, gsplat's flavour).  Every scene goes through a PLY file (the
 * 3DGS layout for Gaussians) and back, so that the saved
 * file reproduces it bit for bit.  Every algorithm of the registry runs on
 * both backends; a mismatch writes the scene, its groups and the command
 * that replays it, then shrinks the splats by delta debugging (ddmin) to a
 * minimal scene that still differs, written beside it.
 */
#include "cli.h"
#include "cli_grad.h"
#include "spr_envmap.h"
#include "spr_glbackend.h"
#include "spr_parity.h"
#include "spr_swrast.h"
#include "spr_util.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int pick(uint64_t *s, int n) { return (int)(spr__splitmix64(s) % (uint64_t)n); }
static int chance(uint64_t *s, double p) { return spr__uniform01(s) < p; }

typedef struct rscene {
    spr_camera_desc cam;
    spr_view view;
    spr_cloud cloud;
    int32_t *labels;
    double eps, lowres_n;
    spr_kernel kernel;
    int voronoi;
    spr_order order;
    float alpha;
    float background[3];
    spr_shading shade;       /* Phong, light, material; environment effects with env below */
    spr_envmap env;
    const char *env_name;
    int layers;              /* depthpeel */
    spr_rects rects;         /* domain-*: primitives of one level of the scene's decomposition (n 0: none) */
    int has_rects;
    int dom_level, dom_strict; /* the level asked for (clamped to a subset's levels) and the domain kind */
    double dom_texel;
    spr_sampling sampling;
    float alpha_ref;
    /* a Gaussian capture (SPEC 10; drawn after every other choice): the file's raw values, so that the saved
     * 3DGS PLY of any subset is the scene, bit for bit */
    int gauss;
    float *g_logit, *g_logs, *g_rot, *g_sh;
    int g_sh_k;
    int gauss_aa;
    int profile_tile, profile_blend; /* spr_render_desc's gauss_profile for gauss3d/gauss2d and for gauss-blend (0: default) */
    char features[256];
} rscene;

static void rscene_free(rscene *s)
{
    free(s->g_logit), free(s->g_logs), free(s->g_rot), free(s->g_sh);
    spr_cloud_free(&s->cloud);
    spr_envmap_free(&s->env);
    spr_rects_free(&s->rects);
    free(s->labels);
    memset(s, 0, sizeof *s);
}

static void feature(rscene *s, const char *f)
{
    size_t o = strlen(s->features);
    snprintf(s->features + o, sizeof s->features - o, "%s%s", o ? "," : "", f);
}

/* World position of pixel coordinate (px, py) at ray parameter t; inv = (P·V)⁻¹ in double. */
static void unproject(const spr_view *v, const double inv[16], double px, double py, double t, double out[3])
{
    double nx = px * 2.0 / v->width - 1.0, ny = py * 2.0 / v->height - 1.0, a[3], b[3];
    for (int side = 0; side < 2; side++) {
        double z = side ? 1.0 : -1.0, h[4];
        for (int r = 0; r < 4; r++) h[r] = inv[4 * r] * nx + inv[4 * r + 1] * ny + inv[4 * r + 2] * z + inv[4 * r + 3];
        for (int k = 0; k < 3; k++) (side ? b : a)[k] = h[k] / h[3];
    }
    for (int k = 0; k < 3; k++) out[k] = a[k] + t * (b[k] - a[k]);
}

static void unit(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++) v[k] /= l;
}

/* The scene's splats as Gaussians: raw file values (log σ, logit opacity, an unnormalised rotation, SH) in s->g_*. */
static int gauss_scene(rscene *s, uint64_t *st, spr_error *err)
{
    const size_t n = s->cloud.n;
    const int deg = pick(st, 4);
    s->g_sh_k = (deg + 1) * (deg + 1);
    s->g_logit = malloc(n * sizeof(float)), s->g_logs = malloc(3 * n * sizeof(float)), s->g_rot = malloc(4 * n * sizeof(float));
    s->g_sh = malloc(n * (size_t)s->g_sh_k * 3 * sizeof(float));
    if (!s->g_logit || !s->g_logs || !s->g_rot || !s->g_sh) return spr__fail(err, SPR_E_NOMEM, "random: out of memory"), -1;
    s->gauss = 1;
    const int needles = chance(st, 0.25), huge = chance(st, 0.15), borders = chance(st, 0.3), near = chance(st, 0.25), deep = chance(st, 0.3),
              faint = chance(st, 0.3);
    s->gauss_aa = chance(st, 0.3);
    const int other_tile = chance(st, 0.3);
    /* the subnormal feature draws from a stream of its own (forked from the state, which it does not advance), so a
     * scene without it is the scene its seed and index gave before the feature existed */
    uint64_t sub_st = *st ^ 0x9e3779b97f4a7c15u;
    const int subnormal = chance(&sub_st, 0.2);
    /* the renderer profiles (SPEC 10.9), likewise from a stream of their own: a tile profile other than inria in 30%
     * of the scenes (as gsplat's flavour was), a gauss-blend profile other than khr in 70% */
    uint64_t prof_st = *st ^ 0x2545f4914f6cdd1du;
    s->profile_tile = s->profile_blend = 0;
    int tiles[16], blends[16], nt = 0, nb = 0;
    for (int i = 0; i < spr_gauss_profile_count(); i++) {
        const spr_gauss_profile *pf = spr_gauss_profile_at(i);
        if (pf->skeleton == SPR_ALGO_GAUSS3D && strcmp(pf->name, "inria") && nt < 16) tiles[nt++] = i;
        if (pf->skeleton == SPR_ALGO_GAUSS_BLEND && strcmp(pf->name, "khr") && nb < 16) blends[nb++] = i;
    }
    if (other_tile && nt) s->profile_tile = 1 + tiles[pick(&prof_st, nt)];
    if (chance(&prof_st, 0.7) && nb) s->profile_blend = 1 + blends[pick(&prof_st, nb)];
    char f[224];
    snprintf(f, sizeof f, "gaussians SH%d%s%s%s%s%s%s%s%s %s/%s", deg, needles ? " needles" : "", huge ? " huge" : "", borders ? " tile-borders" : "",
             near ? " near" : "", deep ? " deep-stack" : "", faint ? " faint" : "", subnormal ? " subnormal" : "", s->gauss_aa ? " aa" : "",
             spr_gauss_profile_of(SPR_ALGO_GAUSS3D, s->profile_tile)->name, spr_gauss_profile_of(SPR_ALGO_GAUSS_BLEND, s->profile_blend)->name);
    feature(s, f);
    const spr_pinhole *p = &s->view.cv;
    double eye[3];
    spr_pinhole_eye(p, eye);
    /* a world point at camera depth z seen at pixel-index (i, j) */
    double ray_i = pick(st, s->cam.width), ray_j = pick(st, s->cam.height);
    for (size_t k = 0; k < n; k++) {
        float *pos = s->cloud.pos + 3 * k;
        double z = -1.0, pi = 0.0, pj = 0.0;
        if (borders && chance(st, 0.5)) { /* the centre on a tile's edge or corner (16-pixel lines) */
            pi = 16.0 * pick(st, s->cam.width / 16 + 2) + (chance(st, 0.5) ? 0.0 : spr__uniform01(st) * 16.0);
            pj = 16.0 * pick(st, s->cam.height / 16 + 2);
            z = 2.0 + 3.0 * spr__uniform01(st);
        } else if (near && chance(st, 0.3)) { /* camera depth about the near test: 0.1 … 0.3 */
            pi = spr__uniform01(st) * s->cam.width, pj = spr__uniform01(st) * s->cam.height;
            z = 0.1 + 0.2 * spr__uniform01(st);
        } else if (deep && chance(st, 0.6)) { /* along one ray: a stack */
            pi = ray_i + 0.3 * (spr__uniform01(st) - 0.5), pj = ray_j + 0.3 * (spr__uniform01(st) - 0.5);
            z = 1.0 + 6.0 * spr__uniform01(st);
        }
        if (z > 0.0) { /* x/z = (i − (cx − ½))/fx */
            const double c[3] = {(pi - (p->cx - 0.5)) / p->fx * z, (pj - (p->cy - 0.5)) / p->fy * z, z};
            for (int a = 0; a < 3; a++) pos[a] = (float)(eye[a] + p->R[a] * c[0] + p->R[3 + a] * c[1] + p->R[6 + a] * c[2]);
        }
        const double r = s->cloud.radius[k] < 1e-3f ? 1e-3 : s->cloud.radius[k];
        for (int a = 0; a < 3; a++) s->g_logs[3 * k + a] = (float)log(r / 3.0 * (0.05 + 0.95 * spr__uniform01(st)));
        if (needles && chance(st, 0.5)) { /* two axes all but nothing */
            s->g_logs[3 * k + pick(st, 3)] = (float)log(1e-5 + 1e-4 * spr__uniform01(st));
            s->g_logs[3 * k + pick(st, 3)] = (float)log(1e-6 + 1e-5 * spr__uniform01(st));
        }
        if (huge && chance(st, 0.15))
            for (int a = 0; a < 3; a++) s->g_logs[3 * k + a] = (float)log(1.0 + 6.0 * spr__uniform01(st));
        if (subnormal && chance(&sub_st, 0.3)) /* σ = r·10^−(8…12): the projected covariance about 1e-20, its products about 2^-126 */
            for (int a = 0; a < 3; a++) s->g_logs[3 * k + a] = (float)log(r * pow(10.0, -8.0 - 4.0 * spr__uniform01(&sub_st)));
        double q[4], l = 0.0;
        do {
            l = 0.0;
            for (int a = 0; a < 4; a++) q[a] = spr__uniform01(st) - 0.5, l += q[a] * q[a];
        } while (l < 1e-4);
        for (int a = 0; a < 4; a++) s->g_rot[4 * k + a] = (float)(q[a] * (0.5 + 2.0 * spr__uniform01(st))); /* any length */
        s->g_logit[k] = (float)(8.0 * spr__uniform01(st) - 4.0);
        if (deep) s->g_logit[k] = (float)(1.0 + 4.0 * spr__uniform01(st));
        if (faint && chance(st, 0.2)) s->g_logit[k] = (float)(-9.0 + 3.0 * spr__uniform01(st)); /* α below 1/255 */
        float *sh = s->g_sh + k * (size_t)s->g_sh_k * 3;
        for (int ch = 0; ch < 3; ch++) sh[ch] = (float)((s->cloud.color[3 * k + ch] - 0.5) / 0.28209479177387814);
        for (int j = 3; j < 3 * s->g_sh_k; j++) sh[j] = (float)(0.6 * (spr__uniform01(st) - 0.5));
    }
    return 0;
}

/* Scene i of seed: everything drawn from one stream. */
static int generate(uint64_t seed, int i, const char *tmp_ply, rscene *s, spr_error *err)
{
    memset(s, 0, sizeof *s);
    uint64_t st = seed * 0x100000001b3ull ^ (uint64_t)i * 0x9e3779b97f4a7c15ull;
    spr__splitmix64(&st);
    const double scale = chance(&st, 0.08) ? 1e-18 : chance(&st, 0.05) ? 1e12 : 1.0;
    if (scale != 1.0) feature(s, scale < 1.0 ? "denormal-scale" : "huge-scale");
    spr_camera_desc *c = &s->cam;
    spr_camera_defaults(c);
    c->width = 8 + pick(&st, 88);
    c->height = 8 + pick(&st, 88);
    double dir[3] = {spr__uniform01(&st) - 0.5, spr__uniform01(&st) - 0.5, spr__uniform01(&st) - 0.5};
    unit(dir);
    double dist = 3.0 + 3.0 * spr__uniform01(&st);
    for (int k = 0; k < 3; k++) {
        c->eye[k] = dir[k] * dist * scale;
        c->target[k] = (spr__uniform01(&st) - 0.5) * 0.2 * scale;
    }
    c->have_eye = c->have_target = 1;
    double up[3] = {spr__uniform01(&st) - 0.5, spr__uniform01(&st) - 0.5, spr__uniform01(&st) - 0.5};
    memcpy(c->up, up, sizeof up);
    int cross_near = chance(&st, 0.15);
    if (chance(&st, 0.3)) {
        c->ortho_height = (2.0 + 2.0 * spr__uniform01(&st)) * scale;
        c->fov_deg = 0.0;
        feature(s, "ortho");
    } else {
        c->fov_deg = 20.0 + 50.0 * spr__uniform01(&st);
    }
    c->near_plane = (cross_near ? dist - 0.6 : dist - 2.0) * scale;
    c->far_plane = (dist + 2.0) * scale;
    if (cross_near) feature(s, "near-plane");
    double inv[16]; /* once per scene, for the centres placed on pixels */
    if (spr_view_make(c, &s->view, err) || spr__mat4_inverse(s->view.PV, inv)) return -1;

    size_t n = 1 + (size_t)pick(&st, chance(&st, 0.2) ? 2000 : 300);
    if (spr_cloud_alloc(&s->cloud, n)) return spr__fail(err, SPR_E_NOMEM, "random: out of memory"), -1;
    int coplanar = chance(&st, 0.25), coincident = chance(&st, 0.2), on_pixels = chance(&st, 0.25), equal_depth = chance(&st, 0.2),
        eps_apart = chance(&st, 0.2), tiny = chance(&st, 0.15), huge = chance(&st, 0.1), grazing = chance(&st, 0.2);
    if (coplanar) feature(s, "coplanar");
    if (coincident) feature(s, "coincident");
    if (on_pixels) feature(s, "pixel-centres-and-edges");
    if (equal_depth) feature(s, "equal-depths");
    if (eps_apart) feature(s, "eps-apart");
    if (tiny) feature(s, "tiny-radii");
    if (huge) feature(s, "huge-radii");
    if (grazing) feature(s, "grazing");
    s->eps = (0.002 + 0.3 * spr__uniform01(&st)) * scale;
    double plane_n[3] = {spr__uniform01(&st) - 0.5, spr__uniform01(&st) - 0.5, spr__uniform01(&st) - 0.5}, depth_t = 0.2 + 0.6 * spr__uniform01(&st);
    unit(plane_n);
    double view_dir[3] = {-dir[0], -dir[1], -dir[2]};
    for (size_t k = 0; k < n; k++) {
        double p[3], nv[3] = {spr__uniform01(&st) - 0.5, spr__uniform01(&st) - 0.5, spr__uniform01(&st) - 0.5};
        for (int a = 0; a < 3; a++) p[a] = (spr__uniform01(&st) - 0.5) * 2.0 * scale;
        if (on_pixels && chance(&st, 0.7)) { /* a pixel centre, or a pixel edge or corner */
            double px = pick(&st, c->width) + (chance(&st, 0.5) ? 0.5 : 0.0), py = pick(&st, c->height) + (chance(&st, 0.5) ? 0.5 : 0.0);
            unproject(&s->view, inv, px, py, equal_depth ? depth_t : 0.05 + 0.9 * spr__uniform01(&st), p);
        } else if (equal_depth && chance(&st, 0.6)) { /* same ray parameter, different pixels */
            unproject(&s->view, inv, spr__uniform01(&st) * c->width, spr__uniform01(&st) * c->height, depth_t, p);
        }
        if (coplanar && chance(&st, 0.6)) { /* onto the plane through the origin with normal plane_n */
            double d = p[0] * plane_n[0] + p[1] * plane_n[1] + p[2] * plane_n[2];
            for (int a = 0; a < 3; a++) p[a] -= d * plane_n[a];
            memcpy(nv, plane_n, sizeof nv);
        }
        if (grazing && chance(&st, 0.5)) { /* normal ⟂ the view direction, exactly or nearly */
            double d = nv[0] * view_dir[0] + nv[1] * view_dir[1] + nv[2] * view_dir[2];
            for (int a = 0; a < 3; a++) nv[a] -= d * view_dir[a];
            if (chance(&st, 0.5))
                for (int a = 0; a < 3; a++) nv[a] += 1e-4 * view_dir[a];
        }
        if (!(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2] > 1e-12)) nv[2] = 1.0;
        unit(nv);
        double r = (0.02 + 0.3 * spr__uniform01(&st)) * scale;
        if (tiny && chance(&st, 0.5)) r = 1e-4 * scale * spr__uniform01(&st) + 1e-30;
        if (huge && chance(&st, 0.2)) r = (5.0 + 20.0 * spr__uniform01(&st)) * scale;
        if (coincident && k > 0 && chance(&st, 0.3)) { /* an exact copy of an earlier splat */
            size_t j = (size_t)pick(&st, (int)k);
            for (int a = 0; a < 3; a++) { p[a] = s->cloud.pos[3 * j + a]; nv[a] = s->cloud.nrm[3 * j + a]; }
            r = s->cloud.radius[j];
        }
        if (eps_apart && k > 0 && chance(&st, 0.3)) { /* exactly ε farther along the view direction than an earlier splat */
            size_t j = (size_t)pick(&st, (int)k);
            for (int a = 0; a < 3; a++) p[a] = s->cloud.pos[3 * j + a] + s->eps * view_dir[a];
        }
        for (int a = 0; a < 3; a++) {
            s->cloud.pos[3 * k + a] = (float)p[a];
            s->cloud.nrm[3 * k + a] = (float)nv[a];
            s->cloud.color[3 * k + a] = (float)pick(&st, 256) / 255.0f;
        }
        s->cloud.alpha[k] = (float)pick(&st, 256) / 255.0f;
        s->cloud.radius[k] = (float)r > 0.0f ? (float)r : 1e-30f;
    }
    s->kernel = (spr_kernel)pick(&st, SPR_KERNEL__COUNT);
    s->voronoi = chance(&st, 0.5);
    s->lowres_n = chance(&st, 0.3) ? (double)(1 + pick(&st, 64)) : 0.0;
    s->order = chance(&st, 0.5) ? SPR_ORDER_SORT : SPR_ORDER_BSP;
    s->alpha = chance(&st, 0.3) ? (float)(1 + pick(&st, 255)) / 256.0f : 0.0f;
    for (int k = 0; k < 3; k++) s->background[k] = (float)pick(&st, 256) / 255.0f;
    /* shading and environment effects (SPEC 4.3, 6.3), values exact in decimal for the replay line */
    spr_shading_defaults(&s->shade);
    if (chance(&st, 0.4)) {
        s->shade.model = SPR_SHADE_PHONG;
        do {
            for (int k = 0; k < 3; k++) s->shade.light_eye[k] = (double)(pick(&st, 17) - 8) / 8.0;
        } while (s->shade.light_eye[0] == 0.0 && s->shade.light_eye[1] == 0.0 && s->shade.light_eye[2] == 0.0);
        s->shade.ka = pick(&st, 17) / 16.0;
        s->shade.kd = pick(&st, 17) / 16.0;
        s->shade.ks = pick(&st, 17) / 16.0;
        s->shade.exponent = 1 + pick(&st, chance(&st, 0.5) ? 8 : 1024);
        feature(s, "phong");
    }
    if (chance(&st, 0.4)) {
        s->env_name = chance(&st, 0.5) ? "sky" : "checker";
        if (spr_envmap_builtin(s->env_name, 1 + pick(&st, 48), &s->env, err)) return -1;
        s->shade.env = &s->env;
        for (int k = 0; k < 3; k++) s->shade.eta[k] = (double)(32 + pick(&st, 480)) / 256.0;
        if (chance(&st, 0.3)) s->shade.eta[1] = s->shade.eta[2] = s->shade.eta[0];
        s->shade.multilayer = chance(&st, 0.7);
        feature(s, "env");
    }
    s->layers = 1 + pick(&st, 8);
    int K = 1 + pick(&st, 8);
    if (!(s->labels = malloc(n * sizeof *s->labels))) return spr__fail(err, SPR_E_NOMEM, "random: out of memory"), -1;
    for (size_t k = 0; k < n; k++) s->labels[k] = pick(&st, K);
    /* elliptical splats (issue 15), drawn last so every earlier choice of a seed stays as it was */
    if (chance(&st, 0.35)) {
        if (spr_cloud_alloc_ell(&s->cloud)) return spr__fail(err, SPR_E_NOMEM, "random: out of memory"), -1;
        const int extreme = chance(&st, 0.3);
        for (size_t k = 0; k < n; k++) {
            if (chance(&st, 0.2)) continue; /* some stay circles */
            const float *nv = s->cloud.nrm + 3 * k;
            double a[3] = {spr__uniform01(&st) - 0.5, spr__uniform01(&st) - 0.5, spr__uniform01(&st) - 0.5}, d = 0.0;
            for (int q = 0; q < 3; q++) d += a[q] * nv[q];
            for (int q = 0; q < 3; q++) a[q] -= d * nv[q];
            if (!(a[0] * a[0] + a[1] * a[1] + a[2] * a[2] > 1e-12)) continue;
            unit(a);
            const double ratio = extreme ? 1e-3 + 0.05 * spr__uniform01(&st) : 0.1 + 0.9 * spr__uniform01(&st);
            float *e = s->cloud.ell + 4 * k;
            for (int q = 0; q < 3; q++) e[q] = (float)a[q];
            e[3] = (float)(ratio * s->cloud.radius[k]);
            if (!(e[3] > 0.0f) || e[3] > s->cloud.radius[k]) e[3] = s->cloud.radius[k];
        }
        feature(s, extreme ? "ellipses-thin" : "ellipses");
    }
    /* Gaussians (SPEC 10), perspective scenes only: anisotropic, needle-thin, huge, on tile borders, about the
     * near plane, stacks deep enough to stop the loop, SH degree up to 3, --gauss-aa, gsplat's flavour */
    if (!s->view.ortho && chance(&st, 0.4) && gauss_scene(s, &st, err)) return -1;
    /* through a file and back: the saved scene is this scene, bit for bit */
    spr_cloud back;
    spr_load_desc ld;
    spr_load_defaults(&ld);
    ld.sh_degree = 3;
    const spr_gauss_file gf = {n, s->cloud.pos, s->g_sh, s->g_logit, s->g_logs, s->g_rot, s->g_sh_k};
    if ((s->gauss ? spr_write_gauss_ply(tmp_ply, &gf, err) : spr_write_ply(tmp_ply, &s->cloud, err)) || spr_load(tmp_ply, &ld, &back, err)) return -1;
    spr_cloud_free(&s->cloud);
    s->cloud = back;
    return 0;
}

static void render_desc(const rscene *s, spr_algo algo, spr_groups *g, spr_render_desc *rd)
{
    memset(rd, 0, sizeof *rd);
    const spr_algo_info *ai = spr_algo_info_of(algo);
    rd->algo = algo;
    rd->kernel = ai->uses & SPR_USES_KERNEL ? s->kernel : SPR_KERNEL_GAUSS;
    rd->eps = ai->uses & SPR_USES_EPS ? s->eps : 0.0;
    rd->voronoi = (ai->uses & SPR_USES_VORONOI) && s->voronoi;
    rd->lowres_n = rd->voronoi || (ai->uses & SPR_USES_LOWRES) ? s->lowres_n : 0.0;
    rd->order = ai->uses & SPR_USES_ORDER ? s->order : SPR_ORDER_BSP;
    rd->alpha = ai->uses & SPR_USES_ALPHA ? s->alpha : 0.0f;
    rd->shade = s->shade; /* the registry's uses decide what an algorithm reads (spr_render) */
    rd->layers = ai->uses & SPR_USES_LAYERS ? s->layers : 0;
    memcpy(rd->background, s->background, sizeof rd->background);
    rd->groups = ai->uses & SPR_USES_GROUPS ? g : NULL;
    rd->rects = ai->uses & SPR_USES_RECTS ? &s->rects : NULL;
    rd->sampling = s->sampling;
    rd->alpha_ref = ai->uses & SPR_USES_ALPHAREF ? s->alpha_ref : 0.0f;
    rd->gauss_aa = (ai->uses & SPR_USES_GAUSS) && s->gauss_aa;
    rd->gauss_profile = 0;
    if (ai->uses & SPR_USES_GAUSS) rd->gauss_profile = algo == SPR_ALGO_GAUSS_BLEND ? s->profile_blend : s->profile_tile;
}

/* The domain primitives of cloud c with the scene's domain options, as
 * `render --level L --texel T [--domain strict]` builds them (the level
 * clamped to c's levels, *level set to the one used); −1 when c does not
 * decompose or yields no rectangle. */
static int build_rects(const spr_cloud *c, const rscene *s, spr_rects *out, int *level)
{
    spr_decomp_desc dd;
    spr_decomp_defaults(&dd);
    dd.threads = 1;
    spr_decomp dc = {0};
    spr_error err = {0};
    memset(out, 0, sizeof *out);
    if (c->n < 32 || spr_decompose(c, &dd, &dc, &err)) return -1;
    spr_prims_desc pd;
    spr_prims_defaults(&pd);
    pd.tex.texel_factor = s->dom_texel;
    pd.strict = s->dom_strict;
    *level = s->dom_level < dc.levels ? s->dom_level : dc.levels - 1;
    spr_prims_stats st;
    int rc = spr_domain_prims(c, &dc.basis[*level], &pd, out, &st, &err) || out->n == 0 ? -1 : 0;
    if (rc) spr_rects_free(out);
    spr_decomp_free(&dc);
    return rc;
}

/* Domain primitives of the scene (SPEC 7): a random level, texel size,
 * domain kind and sampling; none when the scene is too small or degenerate
 * to decompose (the domain-* algorithms are then left out of this scene). */
static void scene_rects(rscene *s, uint64_t seed, int i)
{
    uint64_t r = seed * 0x9E3779B97F4A7C15ull + (uint64_t)i * 7919u + 17u;
    s->dom_level = (int)(spr__splitmix64(&r) % 16);
    s->dom_texel = 0.5 + (double)(spr__splitmix64(&r) % 4) * 0.5;
    s->dom_strict = spr__splitmix64(&r) % 4 == 0;
    s->sampling = spr__splitmix64(&r) % 2 ? SPR_SAMPLE_LINEAR : SPR_SAMPLE_NEAREST;
    s->alpha_ref = (float)(spr__splitmix64(&r) % 5) * 0.05f;
    int l;
    s->has_rects = !build_rects(&s->cloud, s, &s->rects, &l);
    if (s->has_rects) {
        char f[96];
        snprintf(f, sizeof f, "%sdomains L%d %zu rects %s", s->features[0] ? ", " : "", l, s->rects.n,
                 s->sampling == SPR_SAMPLE_LINEAR ? "linear" : "nearest");
        strncat(s->features, f, sizeof s->features - strlen(s->features) - 1);
    }
}

/* The splats keep[0..m) of s as a cloud of their own, with their labels. */
static int subset(const rscene *s, const uint32_t *keep, size_t m, spr_cloud *c, int32_t **lab, spr_error *err)
{
    *lab = malloc((m ? m : 1) * sizeof **lab);
    const int K = s->cloud.sh_k;
    if (!*lab || spr_cloud_alloc(c, m) || (s->cloud.ell && spr_cloud_alloc_ell(c)) ||
        (s->cloud.gauss && !(c->gauss = malloc((m ? m : 1) * SPR_GAUSS_FLOATS * sizeof(float)))) ||
        (s->cloud.sh && !(c->sh = malloc((m ? m : 1) * (size_t)K * 3 * sizeof(float))))) {
        free(*lab);
        spr_cloud_free(c);
        return spr__fail(err, SPR_E_NOMEM, "random: out of memory"), -1;
    }
    for (size_t k = 0; k < m; k++) {
        size_t j = keep[k];
        memcpy(c->pos + 3 * k, s->cloud.pos + 3 * j, 3 * sizeof(float));
        memcpy(c->nrm + 3 * k, s->cloud.nrm + 3 * j, 3 * sizeof(float));
        memcpy(c->color + 3 * k, s->cloud.color + 3 * j, 3 * sizeof(float));
        c->alpha[k] = s->cloud.alpha[j];
        c->radius[k] = s->cloud.radius[j];
        if (s->cloud.ell) memcpy(c->ell + 4 * k, s->cloud.ell + 4 * j, 4 * sizeof(float));
        if (s->cloud.gauss) memcpy(c->gauss + SPR_GAUSS_FLOATS * k, s->cloud.gauss + SPR_GAUSS_FLOATS * j, SPR_GAUSS_FLOATS * sizeof(float));
        if (s->cloud.sh) memcpy(c->sh + (size_t)K * 3 * k, s->cloud.sh + (size_t)K * 3 * j, (size_t)K * 3 * sizeof(float));
        (*lab)[k] = s->labels[j];
    }
    c->flags = s->cloud.flags;
    c->sh_k = s->cloud.sh_k;
    c->gauss_cut = s->cloud.gauss_cut;
    c->gauss_aa = s->cloud.gauss_aa;
    return 0;
}

/* Does `algo` differ between the backends on the splats keep[0..m) of s?
 * 1 differs, 0 equal, −1 failure; the report goes to rep when given. */
/* The gradients' comparison of the last differs (its lines), and whether a frame's gradients are compared: gauss3d
 * under a profile that trains, without --gauss-aa (its compensation has no backward yet). */
static char grad_text[4096];
static int grad_checked(const spr_render_desc *rd)
{
    return rd->algo == SPR_ALGO_GAUSS3D && spr_gauss_profile_of(rd->algo, rd->gauss_profile)->grad.trains && !rd->gauss_aa;
}

static int differs(spr_backend *cpu, spr_backend *gl, const rscene *s, const uint32_t *keep, size_t m, spr_algo algo,
                   spr_parity_report *rep_out, spr_error *err)
{
    spr_cloud c;
    int32_t *lab;
    if (subset(s, keep, m, &c, &lab, err)) return -1;
    spr_groups g = {0};
    int rc = -1;
    spr_render_desc rd;
    render_desc(s, algo, &g, &rd);
    spr_rects sub = {0};
    int level;
    if (rd.rects && m != s->cloud.n) { /* a subset gets the primitives its replay command builds */
        if (build_rects(&c, s, &sub, &level)) {
            spr_cloud_free(&c);
            free(lab);
            return 0; /* no primitives: nothing to compare */
        }
        rd.rects = &sub;
    }
    spr_parity_report rep;
    if (!spr_groups_from_labels(lab, m, 0, &g, err) && !spr_parity_run(cpu, gl, &s->view, &c, &rd, &rd, NULL, "random", &rep, err)) {
        rc = !spr_parity_exact(&rep);
        grad_text[0] = 0;
        if (!rc && grad_checked(&rd)) { /* SPEC 10.10: the backward pass, under the replay's loss: l2 against a black image */
            const spr_grad_desc gd = {.loss = SPR_LOSS_L2};
            FILE *f = fmemopen(grad_text, sizeof grad_text - 1, "w");
            const int ge = f ? cli_grad_parity(f, cpu, gl, &s->view, &c, &rd, &gd, err) : -1;
            if (f) fclose(f);
            if (ge < 0) rc = -1, spr_parity_report_free(&rep);
            else rc = !ge;
        }
        if (rc < 0) {}
        else if (rep_out) *rep_out = rep;
        else spr_parity_report_free(&rep);
    }
    spr_groups_free(&g);
    spr_rects_free(&sub);
    spr_cloud_free(&c);
    free(lab);
    return rc;
}

/* Write the splats keep[0..m) of s as NAME.ply and NAME.groups and print
 * the command that replays the comparison (on the GL gd chose). */
static int save(FILE *out, const rscene *s, const uint32_t *keep, size_t m, spr_algo algo, const char *name, const spr_gl_desc *gd,
                spr_error *err)
{
    spr_cloud c;
    int32_t *lab;
    if (subset(s, keep, m, &c, &lab, err)) return -1;
    char ply[1200], grp[1200];
    snprintf(ply, sizeof ply, "%s.ply", name);
    snprintf(grp, sizeof grp, "%s.groups", name);
    int bad;
    if (s->gauss) { /* the file's own values of the subset: the 3DGS layout read back gives these Gaussians, bit for bit */
        float *lg = malloc((m ? m : 1) * sizeof *lg), *ls = malloc((m ? m : 1) * 3 * sizeof *ls), *rt = malloc((m ? m : 1) * 4 * sizeof *rt),
              *sh = malloc((m ? m : 1) * (size_t)s->g_sh_k * 3 * sizeof *sh);
        bad = !lg || !ls || !rt || !sh;
        for (size_t k = 0; !bad && k < m; k++) {
            const size_t j = keep[k];
            lg[k] = s->g_logit[j];
            memcpy(ls + 3 * k, s->g_logs + 3 * j, 3 * sizeof *ls);
            memcpy(rt + 4 * k, s->g_rot + 4 * j, 4 * sizeof *rt);
            memcpy(sh + (size_t)s->g_sh_k * 3 * k, s->g_sh + (size_t)s->g_sh_k * 3 * j, (size_t)s->g_sh_k * 3 * sizeof *sh);
        }
        const spr_gauss_file gf = {m, c.pos, sh, lg, ls, rt, s->g_sh_k};
        if (bad) spr__fail(err, SPR_E_NOMEM, "random: out of memory");
        else bad = spr_write_gauss_ply(ply, &gf, err) != SPR_OK;
        free(lg), free(ls), free(rt), free(sh);
        bad = bad || spr_groups_write(grp, lab, m, err);
    } else {
        bad = spr_write_ply(ply, &c, err) || spr_groups_write(grp, lab, m, err);
    }
    int level = -1;
    if (!bad && (spr_algo_info_of(algo)->uses & SPR_USES_RECTS)) {
        spr_rects r;
        if (!build_rects(&c, s, &r, &level)) spr_rects_free(&r);
    }
    spr_cloud_free(&c);
    free(lab);
    if (bad) return -1;
    const spr_camera_desc *cam = &s->cam;
    const spr_algo_info *ai = spr_algo_info_of(algo);
    fprintf(out, "  replay: splatref parity --model %s --algo %s", ply, ai->name);
    if (ai->uses & SPR_USES_GROUPS) fprintf(out, " --groups-file %s", grp);
    fprintf(out, " --size %dx%d --eye %.17g,%.17g,%.17g --target %.17g,%.17g,%.17g --up %.17g,%.17g,%.17g --near %.17g --far %.17g", cam->width,
           cam->height, cam->eye[0], cam->eye[1], cam->eye[2], cam->target[0], cam->target[1], cam->target[2], cam->up[0], cam->up[1],
           cam->up[2], cam->near_plane, cam->far_plane);
    if (cam->ortho_height > 0.0) fprintf(out, " --ortho %.17g", cam->ortho_height);
    else fprintf(out, " --fov %.17g", cam->fov_deg);
    fprintf(out, " --background %.9g,%.9g,%.9g", s->background[0], s->background[1], s->background[2]);
    if (ai->uses & SPR_USES_KERNEL) fprintf(out, " --kernel %s", spr_kernel_name(s->kernel));
    if (ai->uses & SPR_USES_EPS) fprintf(out, " --eps %.17g", s->eps);
    if ((ai->uses & SPR_USES_VORONOI) && s->voronoi) fprintf(out, " --voronoi");
    if (((ai->uses & SPR_USES_VORONOI) && s->voronoi) || (ai->uses & SPR_USES_LOWRES))
        if (s->lowres_n > 0.0) fprintf(out, " --lowres-n %.17g", s->lowres_n);
    if (ai->uses & SPR_USES_ORDER) fprintf(out, " --order %s", s->order == SPR_ORDER_SORT ? "sort" : "bsp");
    if ((ai->uses & SPR_USES_ALPHA) && s->alpha > 0.0f) fprintf(out, " --alpha %.9g", s->alpha);
    const spr_shading *sh = &s->shade;
    const int phong = (ai->uses & SPR_USES_SHADE) && sh->model == SPR_SHADE_PHONG, env = (ai->uses & SPR_USES_ENV) && sh->env;
    if (phong)
        fprintf(out, " --shade phong --light %.17g,%.17g,%.17g --material %.17g,%.17g,%.17g,%d", sh->light_eye[0], sh->light_eye[1], sh->light_eye[2],
               sh->ka, sh->kd, sh->ks, sh->exponent);
    if (env)
        fprintf(out, " --env %s --env-size %d --eta %.17g,%.17g,%.17g --env-layers %s", s->env_name, sh->env->size, sh->eta[0], sh->eta[1],
               sh->eta[2], sh->multilayer ? "multi" : "single");
    if (ai->uses & SPR_USES_LAYERS) fprintf(out, " --layers %d", s->layers);
    if (level >= 0)
        fprintf(out, " --level %d --texel %.17g%s --sampling %s", level, s->dom_texel, s->dom_strict ? " --domain strict" : "",
               s->sampling == SPR_SAMPLE_LINEAR ? "linear" : "nearest");
    if ((ai->uses & SPR_USES_ALPHAREF) && s->alpha_ref > 0.0f) fprintf(out, " --alpha-ref %.9g", s->alpha_ref);
    if (s->gauss && s->g_sh_k > 1) fprintf(out, " --sh-degree 3");
    if ((ai->uses & SPR_USES_GAUSS) && s->gauss_aa) fprintf(out, " --gauss-aa");
    const int prof = !(ai->uses & SPR_USES_GAUSS) ? 0 : algo == SPR_ALGO_GAUSS_BLEND ? s->profile_blend : s->profile_tile;
    if (prof > 0) fprintf(out, " --gauss-profile %s", spr_gauss_profile_at(prof - 1)->name);
    if (gd->driver != SPR_GL_DRIVER_DEFAULT) fprintf(out, " --gl-driver %s", spr_gl_driver_name(gd->driver));
    if (gd->device >= 0) fprintf(out, " --gl-device %d", gd->device);
    spr_render_desc rdg = {.algo = algo, .gauss_profile = prof, .gauss_aa = (ai->uses & SPR_USES_GAUSS) && s->gauss_aa};
    if (grad_checked(&rdg)) fprintf(out, " --loss l2"); /* the gradients' loss (parity's default, said) */
    fprintf(out, "\n");
    return 0;
}

/* ddmin over the splats: keep a smaller subset while the mismatch persists. */
static size_t minimise(spr_backend *cpu, spr_backend *gl, const rscene *s, spr_algo algo, uint32_t *keep, size_t m, spr_error *err)
{
    uint32_t *trial = malloc((m ? m : 1) * sizeof *trial);
    if (!trial) return m;
    size_t chunks = 2;
    while (m >= 2) {
        size_t size = (m + chunks - 1) / chunks;
        int reduced = 0;
        for (size_t c0 = 0; c0 < m && !reduced; c0 += size) { /* drop one chunk */
            size_t t = 0;
            for (size_t k = 0; k < m; k++)
                if (k < c0 || k >= c0 + size) trial[t++] = keep[k];
            if (t && differs(cpu, gl, s, trial, t, algo, NULL, err) == 1) {
                memcpy(keep, trial, t * sizeof *trial);
                m = t;
                chunks = chunks > 2 ? chunks - 1 : 2;
                reduced = 1;
            }
        }
        if (!reduced) {
            if (chunks >= m) break;
            chunks = chunks * 2 < m ? chunks * 2 : m;
        }
    }
    free(trial);
    return m;
}

int cli_parity_random(spr__args *a, int first, int count, uint64_t seed, const char *dir, const spr_gl_desc *gd, const char *junit)
{
    const char *out_dir = dir ? dir : "parity-random";
    spr_error err = {0};
    spr_backend *gl = spr_gl_create(gd, &err), *cpu = NULL;
    if (!gl) { fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg); return 2; }
    if (!(cpu = spr_swrast_create(0, &err))) { fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg); spr_backend_destroy(gl); return 2; }
    char tmp[1200];
    snprintf(tmp, sizeof tmp, "/tmp/splatref-random-%ld.ply", (long)getpid());
    printf("parity random: cpu reference vs gl [%s], %d scenes from seed %llu, every algorithm of the registry\n", spr_gl_renderer(gl),
           count, (unsigned long long)seed);
    if (first) printf("parity random: scenes %d to %d of the seed\n", first, first + count - 1);
    int mismatches = 0, failed = 0, made_dir = 0, gauss_scenes = 0;
    cli_junit *ju = junit ? cli_junit_new("splatref parity --random") : NULL;
    long comparisons = 0, gauss_comparisons = 0, grad_comparisons = 0;
    for (int i = first; i < first + count && !failed; i++) {
        rscene s;
        if (generate(seed, i, tmp, &s, &err)) {
            fprintf(stderr, "splatref %s: scene %d: %s\n", a->cmd, i, err.msg);
            rscene_free(&s);
            failed = 1;
            break;
        }
        scene_rects(&s, seed, i);
        gauss_scenes += s.gauss;
        uint32_t *keep = malloc(s.cloud.n * sizeof *keep);
        for (size_t k = 0; keep && k < s.cloud.n; k++) keep[k] = (uint32_t)k;
        for (int al = 0; keep && al < SPR_ALGO__COUNT && !failed; al++) {
            if ((spr_algo_info_of((spr_algo)al)->uses & SPR_USES_RECTS) && !s.has_rects) continue;
            if ((spr_algo_info_of((spr_algo)al)->uses & SPR_USES_GAUSS) && s.view.ortho) continue; /* pinhole only (SPEC 10.2) */
            spr_parity_report rep;
            const double t0 = spr_now_ms();
            int d = differs(cpu, gl, &s, keep, s.cloud.n, (spr_algo)al, &rep, &err);
            char cname[96];
            snprintf(cname, sizeof cname, "scene %d %s", i, spr_algo_name((spr_algo)al));
            comparisons++;
            gauss_comparisons += (spr_algo_info_of((spr_algo)al)->uses & SPR_USES_GAUSS) != 0;
            if (al == SPR_ALGO_GAUSS3D) {
                spr_render_desc rdg = {.algo = SPR_ALGO_GAUSS3D, .gauss_profile = s.profile_tile, .gauss_aa = s.gauss_aa};
                grad_comparisons += grad_checked(&rdg);
            }
            if (d < 0) {
                fprintf(stderr, "splatref %s: scene %d: %s\n", a->cmd, i, err.msg);
                cli_junit_add(ju, "splatref.parity_random", cname, (spr_now_ms() - t0) / 1000.0, CLI_JUNIT_ERROR, err.msg, err.msg);
                failed = 1;
                break;
            }
            if (!d) {
                spr_parity_report_free(&rep);
                cli_junit_add(ju, "splatref.parity_random", cname, (spr_now_ms() - t0) / 1000.0, CLI_JUNIT_PASS, NULL, NULL);
                continue;
            }
            mismatches++;
            cli_text tx;
            FILE *out = cli_text_begin(&tx);
            fprintf(out, "MISMATCH scene %d (%zu splats, %dx%d, %s) %s:\n", i, s.cloud.n, s.cam.width, s.cam.height, s.features[0] ? s.features : "plain",
                    spr_algo_name((spr_algo)al));
            cli_parity_summary(out, spr_algo_name((spr_algo)al), &rep);
            if (grad_text[0]) fputs(grad_text, out);
            char msg[128];
            snprintf(msg, sizeof msg, "%d/%d planes bit-exact, max ulp %llu", rep.exact_planes, rep.n_planes, (unsigned long long)rep.max_ulp);
            spr_parity_report_free(&rep);
            if (!made_dir && mkdir(out_dir, 0777) != 0 && errno != EEXIST) {
                cli_text_end(&tx);
                cli_text_free(&tx);
                spr__error(a, "--report: cannot create %s: %s", out_dir, strerror(errno));
                failed = 1;
                break;
            }
            made_dir = 1;
            char name[1100];
            snprintf(name, sizeof name, "%s/random_%llu_%d_%s", out_dir, (unsigned long long)seed, i, spr_algo_name((spr_algo)al));
            uint32_t *mk = NULL;
            if (save(out, &s, keep, s.cloud.n, (spr_algo)al, name, gd, &err)) fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg), failed = 1;
            else if (!(mk = malloc(s.cloud.n * sizeof *mk))) failed = 1;
            if (mk) {
                memcpy(mk, keep, s.cloud.n * sizeof *mk);
                size_t m = minimise(cpu, gl, &s, (spr_algo)al, mk, s.cloud.n, &err);
                fprintf(out, "  minimised to %zu of %zu splats:\n", m, s.cloud.n);
                snprintf(name, sizeof name, "%s/random_%llu_%d_%s_min", out_dir, (unsigned long long)seed, i, spr_algo_name((spr_algo)al));
                if (save(out, &s, mk, m, (spr_algo)al, name, gd, &err)) { fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg); failed = 1; }
                if (differs(cpu, gl, &s, mk, m, (spr_algo)al, &rep, &err) == 1) {
                    cli_parity_summary(out, spr_algo_name((spr_algo)al), &rep);
                    spr_parity_report_free(&rep);
                }
                free(mk);
            }
            const char *text = cli_text_end(&tx);
            cli_junit_add(ju, "splatref.parity_random", cname, (spr_now_ms() - t0) / 1000.0, CLI_JUNIT_FAILURE, msg, text);
            cli_text_free(&tx);
            if (failed) break;
        }
        free(keep);
        rscene_free(&s);
        if (isatty(2) && !spr__flag(a, "quiet") && (i & 63) == 63) fprintf(stderr, "\r\033[Kparity random: scene %d of %d", i + 1, first + count);
    }
    if (isatty(2) && !spr__flag(a, "quiet")) fprintf(stderr, "\r\033[K");
    remove(tmp);
    spr_backend_destroy(cpu);
    spr_backend_destroy(gl);
    const int jrc = cli_junit_write(a, ju, junit);
    cli_junit_free(ju);
    if (failed || jrc) return 2;
    printf("parity random: %d scenes (%d of Gaussian captures), %ld comparisons (%ld by the Gaussian algorithms, %ld with gauss3d's gradients), "
           "%d mismatches (seed %llu)\n",
           count, gauss_scenes, comparisons, gauss_comparisons, grad_comparisons, mismatches, (unsigned long long)seed);
    printf("verdict: %s\n", mismatches ? "DIFFERENT" : "BIT-EXACT (Tier A)");
    return mismatches ? 1 : 0;
}
