/* cli_bench.c — `splatref bench`: fixed scenes, fixed sizes, 1 vs 2 threads.
 *
 * Figures are ratios measured within one run (the machine is shared and
 * noisy): each configuration keeps the best of --reps renders.
 */
#include "spr_util.h"
#include "cli.h"
#include "spr_grad.h"
#include <unistd.h>
#include "spr__scene_opts.h"
#include "spr_glbackend.h"
#include "spr_swrast.h"
#include "spr_envmap.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static const spr__opt bench_opts[] = {
    {"scene", "NAME", "bunny | armadillo-1m | capture-1m (a 3DGS capture: pbr2p1 and the Gaussian algorithms, 1920x1080 unless --size) | all (rendering, default all) | armadillo-10m | armadillo-100m (opt-in scale scenes: pbr2p1 and deferred) | grouping (hash and WGC ratios)"},
    {"size", "WxH", "image size (default 1024x1024)"},
    {"reps", "N", "renders per configuration, best kept (default 5)"},
    {"points", "N", "size of the armadillo resampling (default 1000000)"},
    {"gl-device", "N", "GL rows on the N-th EGL device (a GPU driver) instead of the surfaceless platform"},
    SPR__BACKEND_OPTS,
    {"rows", "LIST", "only the rows of these algorithms (and pbr2p1, the /pbr2p1 column's), comma-separated registry names, e.g. transparent2,domain-overlap (default every row)"},
    {"quiet", NULL, "no progress on stderr"},
    {NULL, NULL, NULL}};

int cli_bench_grouping(spr__args *a, size_t npts, int reps, int quiet);

typedef struct bench_run {
    double ms;
    uint64_t fragments;
    uint64_t splats;     /* submitted over all draws: splats / n = passes over the data */
    char passes[512];
} bench_run;

/* Keep the fastest render: its totals, and its passes summed by name in
 * first-seen order ("geometry x8 16.5"), then the host time outside any
 * pass (ordering the splats, allocation). */
static void keep_best(bench_run *best, const spr_render_result *res, double ms)
{
    if (ms >= best->ms) return;
    best->ms = ms;
    best->fragments = 0;
    best->splats = 0;
    size_t o = 0;
    best->passes[0] = 0;
    double in_passes = 0.0;
    for (int p = 0; p < res->n_passes; p++) {
        best->fragments += res->passes[p].stats.generated;
        best->splats += res->passes[p].stats.splats;
        in_passes += res->passes[p].ms;
        int seen = 0;
        for (int q = 0; q < p && !seen; q++) seen = !strcmp(res->passes[q].name, res->passes[p].name);
        if (seen) continue;
        double sum = 0.0;
        int count = 0;
        for (int q = p; q < res->n_passes; q++)
            if (!strcmp(res->passes[q].name, res->passes[p].name)) sum += res->passes[q].ms, count++;
        char times[16] = "";
        if (count > 1) snprintf(times, sizeof times, " x%d", count);
        o += (size_t)snprintf(best->passes + o, sizeof best->passes - o, "%s%s %.1f  ", res->passes[p].name, times, sum);
        if (o >= sizeof best->passes) o = sizeof best->passes - 1;
    }
    snprintf(best->passes + o, sizeof best->passes - o, "host %.1f", ms - in_passes);
}

/* The CPU on 1 and 2 threads and the GL backend run in turn, so a burst of
 * load on the shared machine hits every configuration alike; the best of
 * each is kept. */
static int run_set(spr_backend *b[3], const spr_scene *s, const spr_render_desc *rd, int reps, bench_run best[3])
{
    best[0].ms = best[1].ms = best[2].ms = 1e300;
    for (int r = 0; r < reps; r++)
        for (int t = 0; t < 3; t++) {
            if (!b[t]) continue;
            spr_render_result res;
            spr_error err = {0};
            double t0 = spr_now_ms();
            if (spr_render(b[t], &s->view, &s->cloud, rd, &res, &err)) {
                fprintf(stderr, "splatref bench: %s\n", err.msg);
                return -1;
            }
            keep_best(&best[t], &res, spr_now_ms() - t0);
            spr_render_result_free(&res);
        }
    return 0;
}

static volatile int32_t sink;     /* results the optimiser must not drop */
static spr_backend *bench_gl;     /* NULL when no GL context could be made */
enum { BENCH_DOMAIN_LEVEL = 9 };  /* the domain rows: level 9, 465 rectangles on the bunny, near [R] Table 5.1's 383 */
static const char *bench_gl_reason;

/* The streaming pass on 1 and 2 threads, best of reps: the floor every
 * per-splat phase is reported against. */
static void stream_floor(const spr_cloud *c, int reps, double t[2])
{
    double sum;
    t[0] = t[1] = 1e300;
    for (int r = 0; r < (reps > 3 ? reps : 3); r++)
        for (int k = 0; k < 2; k++) {
            double ms = spr_cloud_stream_ms(c, k + 1, &sum);
            if (ms < t[k]) t[k] = ms;
        }
    sink = (int32_t)sum;
}

/* Loading a capture: the cloud written as a 3DGS PLY and as our own binary
 * PLY, each read back by spr_load (best of reps), against the streaming pass. */
static void bench_capture_load(const spr_cloud *c, int reps, double stream_1t)
{
    char gpath[64], opath[64];
    snprintf(gpath, sizeof gpath, "/tmp/splatref-bench-%d-3dgs.ply", (int)getpid());
    snprintf(opath, sizeof opath, "/tmp/splatref-bench-%d-own.ply", (int)getpid());
    spr_error err = {0};
    if (spr_write_gauss_ply_of_cloud(gpath, c, 0, &err) || spr_write_ply(opath, c, &err)) {
        fprintf(stderr, "splatref bench: %s\n", err.msg);
        remove(gpath);
        remove(opath);
        return;
    }
    double tg = 1e300, to = 1e300;
    for (int r = 0; r < (reps > 2 ? reps : 2); r++)
        for (int k = 0; k < 2; k++) {
            spr_cloud back;
            double t0 = spr_now_ms();
            if (spr_load(k ? opath : gpath, NULL, &back, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); break; }
            double ms = spr_now_ms() - t0;
            spr_cloud_free(&back);
            if (k) to = ms < to ? ms : to;
            else tg = ms < tg ? ms : tg;
        }
    printf("  loading a 3DGS PLY capture (62 floats a splat, 248 bytes): %.0f ms = %.1fx stream (1 thread); our binary PLY (32 bytes): "
           "%.0f ms = %.1fx stream; capture / ours %.2f\n", tg, tg / stream_1t, to, to / stream_1t, tg / to);
    remove(gpath);
    remove(opath);
}

/* What a scene's table holds: every row (bunny, armadillo-1m), the two
 * opaque algorithms (the scale scenes), or pbr2p1 and the three Gaussian
 * algorithms of SPEC 10 (the capture scene). */
typedef enum bench_mode { BENCH_ALL, BENCH_SCALE, BENCH_GAUSS } bench_mode;

static const char *bench_rows; /* --rows: comma-separated algorithm names, NULL for every row */

static int bench_row_listed(spr_algo al)
{
    if (!bench_rows || al == SPR_ALGO_PBR2P1) return 1; /* pbr2p1 always: the /pbr2p1 column divides by it */
    const char *name = spr_algo_name(al);
    const size_t n = strlen(name);
    for (const char *p = bench_rows; *p;) {
        const char *e = strchr(p, ',');
        const size_t len = e ? (size_t)(e - p) : strlen(p);
        if (len == n && !strncmp(p, name, n)) return 1;
        p += len + (e != NULL);
    }
    return 0;
}

static int bench_row_wanted(bench_mode mode, spr_algo al)
{
    if (!bench_row_listed(al)) return 0;
    if (mode == BENCH_SCALE) return al == SPR_ALGO_PBR2P1 || al == SPR_ALGO_DEFERRED;
    if (mode == BENCH_GAUSS) return al == SPR_ALGO_PBR2P1 || (spr_algo_info_of(al)->uses & SPR_USES_GAUSS);
    return 1;
}

static void bench_backward(const spr_scene *s, int reps);

static int bench_scene(spr__args *a, const char *label, spr_scene *s, int reps, int quiet, bench_mode mode, double load_ms)
{
    const int scale = mode != BENCH_ALL; /* no grouping, domains, BSP or capture loading */
    spr_bounds bd;
    spr_cloud_bounds(&s->cloud, &bd);
    spr_camera_frame(&s->cam, &bd);
    spr_error err = {0};
    if (spr_view_make(&s->cam, &s->view, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); return -1; }
    double floor_ms[2];
    stream_floor(&s->cloud, reps, floor_ms);
    spr_grouping_desc gd; /* hash K = 8, mode 1, BSP axes: the dynamic-scene grouping */
    spr_grouping_defaults(&gd);
    gd.method = SPR_GROUP_HASH;
    gd.progress = spr__progress(quiet);
    gd.threads = 2;
    double t0g = spr_now_ms();
    if (mode != BENCH_GAUSS && spr__make_groups(a, s, &gd, NULL)) return -1;
    const double group_ms = spr_now_ms() - t0g;
    printf("\nscene %s: %zu splats, %dx%d\n", label, s->cloud.n, s->view.width, s->view.height);
    printf("  streaming pass (every attribute of every splat read once): %.3g ms on 1 thread, %.3g ms on 2 (%.2fx);"
           " the x-stream column below divides by it\n", floor_ms[0], floor_ms[1], floor_ms[0] / floor_ms[1]);
    if (mode == BENCH_GAUSS)
        printf("  loading the capture %.0f ms = %.1fx stream (1 thread); no grouping (none of these rows uses groups)\n", load_ms, load_ms / floor_ms[0]);
    else
        printf("  %s %.0f ms = %.1fx stream (1 thread); hash grouping K=8 mode 1 with BSP axes, 2 threads: %.0f ms = %.1fx stream (2 threads)\n",
               load_ms > 0 ? "loading/sampling" : "loading", load_ms > 0 ? load_ms : 0.0, (load_ms > 0 ? load_ms : 0.0) / floor_ms[0], group_ms,
               group_ms / floor_ms[1]);
    if (!scale) bench_capture_load(&s->cloud, reps, floor_ms[0]);
    /* which of the table's inputs the wanted rows read (--rows) */
    int want_rects = 0, want_order = 0;
    for (int al = 0; al < SPR_ALGO__COUNT; al++)
        if (bench_row_wanted(mode, (spr_algo)al)) {
            want_rects |= (spr_algo_info_of((spr_algo)al)->uses & SPR_USES_RECTS) != 0;
            want_order |= (spr_algo_info_of((spr_algo)al)->uses & SPR_USES_ORDER) != 0;
        }
    /* the domain pipeline (SPEC 7) for the domain-* rows: its phases timed */
    if (!scale && want_rects) {
        spr_decomp_desc dd;
        spr_decomp_defaults(&dd);
        dd.progress = spr__progress(quiet);
        spr_decomp dc = {0};
        double t0 = spr_now_ms();
        if (spr_decompose(&s->cloud, &dd, &dc, &err)) { fprintf(stderr, "splatref bench: %s: %s\n", label, err.msg); return -1; }
        const double ms_decomp = spr_now_ms() - t0;
        spr_prims_desc pd;
        spr_prims_defaults(&pd);
        pd.tex.extend_color = 1;
        pd.threads = 0;
        const int l = dc.levels > BENCH_DOMAIN_LEVEL ? BENCH_DOMAIN_LEVEL : dc.levels - 1;
        int r = spr_domain_prims(&s->cloud, &dc.basis[l], &pd, &s->rects, &s->prims, &err);
        if (!r)
            printf("  domain pipeline (SPEC 7, CPU, all cores): local analysis %.0f ms, coarsening and basis %.0f ms (%d levels, all %.0f ms);\n"
                   "    level %d: %zu regions -> %zu textured rectangles, %zu texels, in %.0f ms (polygons, textures, neighbours)\n",
                   dc.ms_analysis, dc.ms_coarsen, dc.levels, ms_decomp, l, dc.regions[l], s->prims.polygons, s->prims.texels, s->prims.ms);
        spr_decomp_free(&dc);
        if (r) { fprintf(stderr, "splatref bench: %s: %s\n", label, err.msg); return -1; }
    }
    printf("  %-32s %7s %10s %9s %12s %14s %7s %9s  %s\n", "algorithm", "backend", "ms", "x stream", "splats/s", "fragments/s", "passes",
           "/pbr2p1", "ms per pass");
    /* every algorithm of the registry, then the variants the transparency
     * figures of [ZP] §6.3 compare: 3-layer peeling, Algorithm-2 with
     * environment effects and Phong */
    enum { N_EXTRA = 2, N_ROWS = SPR_ALGO__COUNT + N_EXTRA };
    bench_run run[N_ROWS][3];
    char names[N_ROWS][64];
    spr_envmap sky = {0};
    if (spr_envmap_builtin("sky", 256, &sky, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); return -1; }
    /* the BSP tree of the transparent algorithms' order: preprocessing, as the hash axes ([ZP] §5.2.1) */
    spr_bsp bsp = {0};
    double t0b = spr_now_ms();
    if (!scale && want_order && spr_bsp_build(&s->cloud, &bsp, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); spr_envmap_free(&sky); return -1; }
    if (!scale && want_order) printf("  BSP tree (kept across frames for the back-to-front orders): %.0f ms = %.1fx stream (2 threads)\n", spr_now_ms() - t0b,
                       (spr_now_ms() - t0b) / floor_ms[1]);
    int rc = 0;
    int done[N_ROWS] = {0};
    for (int row = 0; row < N_ROWS && !rc; row++) {
        const spr_algo al = row < SPR_ALGO__COUNT ? (spr_algo)row : row == SPR_ALGO__COUNT ? SPR_ALGO_DEPTHPEEL : SPR_ALGO_TRANSPARENT2;
        if ((scale && row >= SPR_ALGO__COUNT) || !bench_row_wanted(mode, al)) continue;
        done[row] = 1;
        const spr_algo_info *ai = spr_algo_info_of(al);
        spr_render_desc rd = {0};
        rd.algo = al;
        rd.voronoi = (ai->uses & SPR_USES_VORONOI) != 0;
        rd.groups = ai->uses & SPR_USES_GROUPS ? &s->g.groups : NULL;
        rd.alpha = ai->uses & SPR_USES_ALPHA ? 0.5f : 0.0f;
        spr_shading_defaults(&rd.shade);
        rd.layers = row == SPR_ALGO__COUNT ? 3 : 8;
        rd.rects = ai->uses & SPR_USES_RECTS ? &s->rects : NULL;
        rd.bsp = bsp.nodes ? &bsp : NULL;
        rd.sampling = SPR_SAMPLE_LINEAR;
        if (row == SPR_ALGO__COUNT + 1) rd.shade.model = SPR_SHADE_PHONG, rd.shade.env = &sky;
        snprintf(names[row], sizeof names[row], "%s%s%s%s%s", ai->name, rd.groups ? " hash K=8" : "", rd.voronoi ? " +vor" : "",
                 ai->uses & SPR_USES_LAYERS ? (rd.layers == 3 ? " L=3" : " L=8") : "", rd.shade.env ? " +env" : "");
        spr_backend *b[3] = {spr_swrast_create(1, &err), spr_swrast_create(2, &err), bench_gl};
        if (!b[0] || !b[1]) fprintf(stderr, "splatref bench: %s\n", err.msg), rc = -1;
        else rc = run_set(b, s, &rd, reps, run[row]);
        spr_backend_destroy(b[0]);
        spr_backend_destroy(b[1]);
    }
    spr_envmap_free(&sky);
    if (bsp.nodes) spr_bsp_free(&bsp);
    if (rc) return -1;
    for (int row = 0; row < N_ROWS; row++) {
        if (!done[row]) continue;
        for (int t = 0; t < 3; t++) {
            if (t == 2 && !bench_gl) continue;
            char who[16];
            snprintf(who, sizeof who, t < 2 ? "cpu %d" : "gl", t + 1);
            printf("  %-32s %7s %10.1f %8.1fx %12.3g %14.3g %7.2f %8.2fx  %s\n", names[row], who, run[row][t].ms,
                   run[row][t].ms / floor_ms[t == 0 ? 0 : 1], s->cloud.n / (run[row][t].ms * 1e-3), run[row][t].fragments / (run[row][t].ms * 1e-3),
                   (double)run[row][t].splats / (double)s->cloud.n, run[row][t].ms / run[SPR_ALGO_PBR2P1][t].ms, run[row][t].passes);
        }
        printf("  %-32s speed-up 2 threads / 1 thread: %.2fx", names[row], run[row][0].ms / run[row][1].ms);
        if (bench_gl) printf("; time CPU (2 threads) / GL: %.2f", run[row][1].ms / run[row][2].ms);
        printf("\n");
    }
    if (mode == BENCH_GAUSS && bench_row_wanted(mode, SPR_ALGO_GAUSS3D)) bench_backward(s, reps);
    printf("  (x stream: frame time over the streaming pass on the same thread count (gl: over 2 threads'); passes: splats\n"
           "   submitted per frame / splats in the model, the geometry passes over the data (domain-*: rectangles submitted /\n"
           "   splats); /pbr2p1: frame time over pbr2p1's on the same backend and view)\n");
    return 0;
}

/* gauss3d's backward pass (SPEC 10.10) on the CPU, 1 and 2 threads, best of reps: its forward (preprocess, sort, raster)
 * and its backward (the upstream gradient, the backend's backward, the colour's) as spr_gauss_grad times them, under
 * the inria profile and an l2 loss against a black image; and each one's peak memory, a frame run in a child process
 * (its peak resident set, the loaded capture included): spr_render's gauss3d frame against spr_gauss_grad's. */
/* This process's resident set (VmRSS) or its peak since the last reset (VmHWM), in kB, from /proc/self/status; the
 * peak reset by writing 5 to /proc/self/clear_refs (Linux 4.0); −1 where either is missing. */
static long proc_kb(const char *field)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    long kb = -1;
    const size_t n = strlen(field);
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, field, n) && line[n] == ':') kb = atol(line + n + 1);
    if (f) fclose(f);
    return kb;
}
static int reset_peak(void)
{
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (!f) return -1;
    const int bad = fputs("5", f) < 0;
    return fclose(f) || bad ? -1 : 0;
}

static void bench_backward(const spr_scene *s, int reps)
{
    double fwd[2] = {1e300, 1e300}, bwd[2] = {1e300, 1e300}, frame[2] = {1e300, 1e300};
    size_t reached = 0;
    for (int r = 0; r < reps; r++)
        for (int t = 0; t < 2; t++) {
            spr_error err = {0};
            spr_backend *b = spr_swrast_create(t + 1, &err);
            spr_render_desc rd = {.algo = SPR_ALGO_GAUSS3D};
            spr_gauss_grads g;
            const spr_grad_desc gd = {.loss = SPR_LOSS_L2};
            spr_render_result res;
            double t0 = spr_now_ms();
            if (!b || spr_render(b, &s->view, &s->cloud, &rd, &res, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); spr_backend_destroy(b); return; }
            const double ms = spr_now_ms() - t0;
            spr_render_result_free(&res);
            if (spr_gauss_grad(b, &s->view, &s->cloud, &rd, &gd, &g, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); spr_backend_destroy(b); return; }
            if (ms < frame[t]) frame[t] = ms;
            if (g.ms_forward < fwd[t]) fwd[t] = g.ms_forward;
            if (g.ms_backward < bwd[t]) bwd[t] = g.ms_backward;
            reached = 0;
            for (size_t G = 0; G < g.n; G++) reached += g.counts[G] > 0;
            spr_gauss_grads_free(&g);
            spr_backend_destroy(b);
        }
    /* peak memory: this process's peak resident set over a gauss3d frame, then over a backward (its forward included),
     * each above the resident set before it (the loaded capture) */
    long base = -1, kf = -1, kb = -1, hf = -1, hb = -1;
    {
        spr_error err = {0};
        spr_backend *b = spr_swrast_create(2, &err);
        spr_render_desc rd = {.algo = SPR_ALGO_GAUSS3D};
        spr_render_result res;
        spr_gauss_grads g;
        const spr_grad_desc gd = {.loss = SPR_LOSS_L2};
        if (b && !reset_peak() && (base = proc_kb("VmRSS")) > 0 && !spr_render(b, &s->view, &s->cloud, &rd, &res, &err)) {
            hf = proc_kb("VmHWM");
            kf = hf - base;
            spr_render_result_free(&res);
            if (!reset_peak() && (base = proc_kb("VmRSS")) > 0 && !spr_gauss_grad(b, &s->view, &s->cloud, &rd, &gd, &g, &err)) {
                hb = proc_kb("VmHWM");
                kb = hb - base;
                spr_gauss_grads_free(&g);
            }
        }
        spr_backend_destroy(b);
    }
    printf("  gauss3d backward (SPEC 10.10, inria, l2 loss, cpu): %zu Gaussians reach a pixel; forward %.1f / %.1f ms, backward %.1f / %.1f ms "
           "(1 / 2 threads); backward/forward %.2fx / %.2fx; gauss3d frame alone %.1f / %.1f ms\n",
           reached, fwd[0], fwd[1], bwd[0], bwd[1], bwd[0] / fwd[0], bwd[1] / fwd[1], frame[0], frame[1]);
    if (kf > 0 && kb > 0)
        printf("  gauss3d backward, peak memory (VmHWM, 2 threads): the process with the loaded capture %.0f MB / %.0f MB (frame / forward + "
               "backward): %.2fx; above what was resident before, %.0f MB / %.0f MB: %.2fx (the gradient arrays alone are %.0f MB)\n",
               hf / 1024.0, hb / 1024.0, (double)hb / (double)hf, kf / 1024.0, kb / 1024.0, (double)kb / (double)kf,
               (double)s->cloud.n * (3 + 4 + 3 + 1 + 3.0 * (s->cloud.sh_k > 16 ? 16 : s->cloud.sh_k > 0 ? s->cloud.sh_k : 1) + 2 + 3 + 3 + 2 + 1) * 4.0 / 1048576.0);
}

/* The capture scene: the armadillo resampled to npts points, written as a
 * 3DGS capture (SH degree 3 with random higher bands, `splatref sample
 * --gaussians --sh-noise`) and loaded back with every band, at 1920x1080. */
static int bench_capture(spr__args *a, size_t npts, int W, int H, int reps, int quiet, const spr_load_desc *ld0)
{
    char path[1200], gpath[64];
    snprintf(path, sizeof path, "%s/meshes/armadillo.off", cli_data_dir());
    snprintf(gpath, sizeof gpath, "/tmp/splatref-bench-%d-capture.ply", (int)getpid());
    spr_load_desc ld = *ld0;
    ld.sh_degree = 3;
    spr_error err = {0};
    spr_cloud c;
    if (spr_sample_mesh(path, npts, 1, &ld, &c, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); return -1; }
    spr_result r = spr_write_gauss_ply_of_cloud(gpath, &c, 2026, &err);
    spr_cloud_free(&c);
    spr_scene s;
    memset(&s, 0, sizeof s);
    spr_camera_defaults(&s.cam);
    s.cam.width = W;
    s.cam.height = H;
    double t0 = spr_now_ms();
    if (!r) r = spr_load(gpath, &ld, &s.cloud, &err);
    const double load_ms = spr_now_ms() - t0;
    if (r) { remove(gpath); fprintf(stderr, "splatref bench: %s\n", err.msg); return -1; }
    char label[96];
    snprintf(label, sizeof label, "3DGS capture of the armadillo, %zu Gaussians, SH degree 3", npts);
    int rc = bench_scene(a, label, &s, reps, quiet, BENCH_GAUSS, load_ms);
    remove(gpath);
    spr_scene_free(&s);
    return rc;
}

int cmd_bench(int argc, char **argv)
{
    spr__args a;
    int pr = spr__parse(&a, "bench", bench_opts, "[--scene bunny|armadillo-1m|capture-1m|all] [--size WxH] [--reps N]", 0, argc, argv);
    if (pr) return pr == 1 ? 0 : 2;
    int W = 1024, H = 1024, reps = 5, quiet = spr__flag(&a, "quiet");
    spr_gl_desc gd;
    size_t npts = 1000000;
    const char *scene = spr__get(&a, "scene") ? spr__get(&a, "scene") : "all";
    bench_rows = spr__get(&a, "rows");
    if ((strcmp(scene, "grouping") && spr__get_wh(&a, "size", &W, &H) < 0) || spr__get_int(&a, "reps", &reps, 1, 100) < 0 ||
        (strcmp(scene, "bunny") && spr__get_size(&a, "points", &npts, 100, SPR_MAX_SPLATS) < 0) ||
        spr__gl_opts(&a, &gd) < 0 || spr__reject_unused(&a))
        return 2;
    if (bench_rows) {
        for (const char *p = bench_rows;;) {
            const char *e = strchr(p, ',');
            char name[64];
            const size_t len = e ? (size_t)(e - p) : strlen(p);
            snprintf(name, sizeof name, "%.*s", (int)(len < sizeof name ? len : sizeof name - 1), p);
            if (len >= sizeof name || spr_algo_from_name(name) < 0) {
                spr__error(&a, "--rows: '%.*s' is not an algorithm of the registry (splatref render --help lists them)", (int)len, p);
                return 2;
            }
            if (!e) break;
            p = e + 1;
        }
    }
    if (!strcmp(scene, "grouping")) {
        if (!spr__get(&a, "points")) npts = 1100000;
        return cli_bench_grouping(&a, npts, reps, quiet);
    }
    const size_t scale_pts = !strcmp(scene, "armadillo-10m") ? 10000000 : !strcmp(scene, "armadillo-100m") ? 100000000 : 0;
    if (strcmp(scene, "all") && strcmp(scene, "bunny") && strcmp(scene, "armadillo-1m") && strcmp(scene, "capture-1m") && !scale_pts) {
        spr__error(&a, "--scene: '%s' is not bunny, armadillo-1m, capture-1m, all, armadillo-10m, armadillo-100m or grouping", scene);
        return 2;
    }
    spr_error gerr = {0};
    bench_gl = spr_gl_create(&gd, &gerr);
    bench_gl_reason = bench_gl ? NULL : gerr.msg;
    printf("splatref bench: CPU reference on 1 and 2 OpenMP threads and the GL backend [%s], best of %d\n",
           bench_gl ? spr_gl_renderer(bench_gl) : bench_gl_reason, reps);
    spr_load_desc ld;
    spr_load_defaults(&ld);
    ld.progress = spr__progress(quiet);
    spr_error err = {0};
    char path[1200];
    int rc = 0;
    if (!strcmp(scene, "all") || !strcmp(scene, "bunny")) {
        spr_scene s;
        memset(&s, 0, sizeof s);
        spr_camera_defaults(&s.cam);
        s.cam.width = W;
        s.cam.height = H;
        snprintf(path, sizeof path, "%s/meshes/bunny00.off", cli_data_dir());
        double t0 = spr_now_ms();
        if (spr_load(path, &ld, &s.cloud, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); return 2; }
        rc |= bench_scene(&a, "bunny00.off", &s, reps, quiet, BENCH_ALL, spr_now_ms() - t0);
        spr_scene_free(&s);
    }
    if (!rc && (!strcmp(scene, "all") || !strcmp(scene, "armadillo-1m") || scale_pts)) {
        if (scale_pts) npts = scale_pts;
        spr_scene s;
        memset(&s, 0, sizeof s);
        spr_camera_defaults(&s.cam);
        s.cam.width = W;
        s.cam.height = H;
        snprintf(path, sizeof path, "%s/meshes/armadillo.off", cli_data_dir());
        double t0 = spr_now_ms();
        if (spr_sample_mesh(path, npts, 1, &ld, &s.cloud, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); return 2; }
        const double sample_ms = spr_now_ms() - t0;
        printf("\n(resampled armadillo.off to %zu points in %.0f ms)\n", s.cloud.n, sample_ms);
        char label[64];
        snprintf(label, sizeof label, "armadillo resampled to %zu", npts);
        rc |= bench_scene(&a, label, &s, reps, quiet, scale_pts ? BENCH_SCALE : BENCH_ALL, sample_ms);
        spr_scene_free(&s);
    }
    if (!rc && (!strcmp(scene, "all") || !strcmp(scene, "capture-1m")))
        rc |= bench_capture(&a, npts, spr__get(&a, "size") ? W : 1920, spr__get(&a, "size") ? H : 1080, reps, quiet, &ld);
    spr_backend_destroy(bench_gl);
    bench_gl = NULL;
    return rc ? 2 : 0;
}

/* ---- grouping figures of issue 4: ratios measured in one run ---- */

int cli_bench_grouping(spr__args *a, size_t npts, int reps, int quiet)
{
    spr_load_desc ld;
    spr_load_defaults(&ld);
    ld.progress = spr__progress(quiet);
    spr_error err = {0};
    char path[1200];
    ld.radius_rho = 0.55; /* the radius rule of docs/grouping.md, whose degrees match [ZP]'s Dragon */
    snprintf(path, sizeof path, "%s/meshes/armadillo.off", cli_data_dir());
    spr_cloud c;
    if (spr_sample_mesh(path, npts, 1, &ld, &c, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); return 2; }
    int32_t *lab = malloc(c.n * sizeof *lab), *axes = malloc(c.n * sizeof *axes);
    printf("grouping benchmark: armadillo resampled to %zu points (radii %.2f d_8, as docs/grouping.md), best of %d, single-threaded hash, "
           "2-thread neighbour graph and WGC\n", c.n, ld.radius_rho, reps);
    double t_stream = 1e300, t_hash = 1e300, t_hash_normal = 1e300, t_bsp = 1e300, sum = 0.0;
    for (int r = 0; r < reps; r++) {
        double t = spr_cloud_stream_ms(&c, 1, &sum); /* the hash is single-threaded: the floor on one thread */
        if (t < t_stream) t_stream = t;
        double t0 = spr_now_ms();
        spr_hash_axes(&c, SPR_HASH_AXIS_BSP, axes, &err);
        t = spr_now_ms() - t0;
        if (t < t_bsp) t_bsp = t;
        spr_hash_desc hd;
        spr_hash_defaults(&hd);
        hd.axes = axes;
        spr_group_stats st;
        t0 = spr_now_ms();
        spr_group_hash(&c, &hd, lab, &st, &err);
        t = spr_now_ms() - t0;
        if (t < t_hash) t_hash = t;
        hd.axes = NULL;
        hd.axis = SPR_HASH_AXIS_NORMAL;
        t0 = spr_now_ms();
        spr_group_hash(&c, &hd, lab, &st, &err);
        t = spr_now_ms() - t0;
        if (t < t_hash_normal) t_hash_normal = t;
    }
    sink = (int32_t)sum;
    printf("  streaming pass (all attributes, 1 thread) %6.1f ms\n", t_stream);
    printf("  hash mode 1, axes from a kept BSP      %9.1f ms   ratio to streaming %.2f\n", t_hash, t_hash / t_stream);
    printf("  hash mode 1, axis from own normal      %9.1f ms   ratio to streaming %.2f\n", t_hash_normal, t_hash_normal / t_stream);
    printf("  (BSP build and leaf axes, once         %9.1f ms)\n", t_bsp);
    /* [ZP] Table 3: each mode on one thread with the BSP built in the call
     * (mode 3: collisions handled nearer the default eye than the model's
     * centre, as tools/grouping-tables.sh) */
    static const double zp_ms[3] = {190.0, 580.0, 330.0};
    spr_camera_desc cam;
    spr_camera_defaults(&cam);
    spr_bounds cb;
    spr_cloud_bounds(&c, &cb);
    spr_camera_frame(&cam, &cb);
    double near_dist = 0.0;
    for (int k = 0; k < 3; k++) near_dist += (0.5 * (cb.lo[k] + cb.hi[k]) - cam.eye[k]) * (0.5 * (cb.lo[k] + cb.hi[k]) - cam.eye[k]);
    near_dist = sqrt(near_dist);
    printf("  [ZP] Table 3, one thread, BSP built in the call (Dragon 1.1M, 2006 desktop: 190 / 580 / 330 ms)\n");
    for (int mode = 1; mode <= 3; mode++) {
        double best = 1e300;
        for (int r = 0; r < reps; r++) {
            spr_hash_desc hd;
            spr_hash_defaults(&hd);
            hd.mode = mode;
            hd.threads = 1;
            memcpy(hd.eye, cam.eye, sizeof hd.eye);
            hd.near_dist = near_dist;
            spr_group_stats st;
            const double t0 = spr_now_ms();
            if (spr_group_hash(&c, &hd, lab, &st, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); return 2; }
            const double t = spr_now_ms() - t0;
            if (t < best) best = t;
        }
        printf("  hash mode %d                            %9.1f ms   ratio to [ZP] %.2f\n", mode, best, best / zp_ms[mode - 1]);
    }
    /* WGC against the neighbour graph alone */
    double t0 = spr_now_ms();
    spr_bounds b;
    spr_cloud_bounds(&c, &b);
    spr_graph g;
    spr_progress prog = spr__progress(quiet);
    if (spr__pair_graph(&c, 1.0, 2, &prog, &g, &err)) {
        fprintf(stderr, "splatref bench: %s\n", err.msg);
        return 2;
    }
    spr_graph_free(&g);
    double t_graph = spr_now_ms() - t0;
    spr_wgc_desc wd;
    spr_wgc_defaults(&wd);
    wd.threads = 2;
    wd.progress = prog;
    spr_group_stats st;
    t0 = spr_now_ms();
    if (spr_group_wgc(&c, &wd, lab, &st, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); return 2; }
    double t_wgc = spr_now_ms() - t0;
    printf("  neighbour graph (grid of columns, all pairs)   %9.1f ms\n", t_graph);
    printf("  WGC K=8 (graph %.0f, colouring %.0f, optimisation %.0f)  %9.1f ms   ratio to the graph %.2f\n", st.ms_graph, st.ms_color,
           st.ms_optimise, t_wgc, t_wgc / t_graph);
    wd.threads = 1; /* [ZP] §6.1's "about 4.6 s" for WGC's basic grouping: one run, one thread */
    t0 = spr_now_ms();
    if (spr_group_wgc(&c, &wd, lab, &st, &err)) { fprintf(stderr, "splatref bench: %s\n", err.msg); return 2; }
    t_wgc = spr_now_ms() - t0;
    printf("  WGC K=8, one thread, one run             %9.1f ms   ratio to [ZP]'s 4.6 s %.2f\n", t_wgc, t_wgc / 4600.0);
    free(lab);
    free(axes);
    spr_cloud_free(&c);
    (void)a;
    return 0;
}
