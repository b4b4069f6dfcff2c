/* gauss_profile.c — the renderer profiles (SPEC §10.9): one row per
 * renderer version, each rule a value of spr_gauss_profile (spr_algo.h),
 * every value read at the source the row cites.  The CLI's --gauss-profile,
 * scene files' "gauss-profile", Python's Scene(gauss_profile=…), parity
 * --random and `splatref profiles` (the table in docs/gaussians.md) all read
 * this table; adding a renderer is adding a row here
 * (docs/architecture.md, "add a renderer profile").
 */
#include "spr_algo.h"
#include "spr_cloud.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define A255 (1.0f / 255.0f)

static const spr_gauss_profile rows[] = {
    {
        .name = "inria",
        .skeleton = SPR_ALGO_GAUSS3D,
        .renderer = "graphdeco-inria/diff-gaussian-rasterization",
        .version = "59f5f77 (antialiased: 077706fe)",
        .source = "cuda_rasterizer/forward.cu, auxiliary.h, rasterizer_impl.cu",
        .cull = {.near = 0.2f, .near_lt = 0, .clip_k = 0.0f, .det_le = 0},
        .tan_clamp = 1,
        .dilation = {0.3f, SPR_GCOMP_OPTION, SPR_GCOMP_ROOT_OF_MAX, 0.000025f},
        .extent = {SPR_GEXT_SQUARE, 9.0, 0.0f, 0, 0.1f, 0, 0.0f},
        .alpha = {0.99f, A255},
        .stop = {0.0001f, 0},
        .order = {SPR_GKEY_TILE_DEPTH, 32},
        .blend = SPR_GBLEND_UNDER,
        .colour = {3, SPR_Q8_NONE, SPR_Q8_NONE, SPR_Q8_NONE, 0},
        .grad = {1, 0, 1},
    },
    {
        .name = "gsplat",
        .skeleton = SPR_ALGO_GAUSS3D,
        .renderer = "nerfstudio-project/gsplat",
        .version = "main 90d7b4b (1.6.0 dev; alpha cap 0.99 since c5ff586b)",
        .source = "gsplat/cuda/_torch_impl.py, csrc/ProjectionEWA3DGSFused.cu, csrc/RasterizeToPixels3DGSFwd.cu",
        .cull = {.near = 0.01f, .near_lt = 1, .clip_k = 0.0f, .det_le = 1},
        .tan_clamp = 2,
        .dilation = {0.3f, SPR_GCOMP_OPTION, SPR_GCOMP_ROOT_OF_MAX, 0.000025f},
        .extent = {SPR_GEXT_AXES, 3.33 * 3.33, 0.0f, 0, 0.0f, 0, 0.0f},
        .alpha = {0.99f, A255},
        .stop = {0.0001f, 1},
        .order = {SPR_GKEY_TILE_DEPTH, 32},
        .blend = SPR_GBLEND_UNDER,
        .colour = {3, SPR_Q8_NONE, SPR_Q8_NONE, SPR_Q8_NONE, 0},
        .grad = {1, 1, 0},
    },
    {
        .name = "gsplat-1.5",
        .skeleton = SPR_ALGO_GAUSS3D,
        .renderer = "nerfstudio-project/gsplat",
        .version = "v1.5.3 (937e299)",
        .source = "gsplat/cuda/_torch_impl.py, csrc/ProjectionEWA3DGSFused.cu, csrc/RasterizeToPixels3DGSFwd.cu",
        .cull = {.near = 0.01f, .near_lt = 1, .clip_k = 0.0f, .det_le = 1},
        .tan_clamp = 2,
        .dilation = {0.3f, SPR_GCOMP_OPTION, SPR_GCOMP_ROOT_OF_MAX, 0.0f},
        .extent = {SPR_GEXT_AXES, 3.33 * 3.33, 0.0f, 0, 0.0f, 0, 0.0f},
        .alpha = {0.999f, A255},
        .stop = {0.0001f, 1},
        .order = {SPR_GKEY_TILE_DEPTH, 32},
        .blend = SPR_GBLEND_UNDER,
        .colour = {3, SPR_Q8_NONE, SPR_Q8_NONE, SPR_Q8_NONE, 0},
        .grad = {1, 1, 0},
    },
    {
        .name = "brush",
        .skeleton = SPR_ALGO_GAUSS3D,
        .renderer = "ArthurBrussee/brush (its extent, the ellipse where alpha = 1/255, holds every pixel the alpha floor keeps: "
                    "drawn here by gsplat's per-axis 3.33 sigma box, which holds that ellipse too)",
        .version = "8b7f5c6",
        .source = "crates/brush-render/src/kernels/*.rs, camera.rs, render.rs",
        .cull = {.near = 0.01f, .near_lt = 1, .clip_k = 0.0f, .det_le = 1},
        .tan_clamp = 2,
        .dilation = {0.3f, SPR_GCOMP_OPTION, SPR_GCOMP_ROOT_OF_MAX, 0.0f},
        .extent = {SPR_GEXT_AXES, 3.33 * 3.33, 0.0f, 0, 0.0f, 0, 0.0f},
        .alpha = {0.999f, A255},
        .stop = {0.0001f, 1},
        .order = {SPR_GKEY_TILE_DEPTH, 32},
        .blend = SPR_GBLEND_UNDER,
        .colour = {3, SPR_Q8_NONE, SPR_Q8_NONE, SPR_Q8_NONE, 0},
        .grad = {1, 1, 0},
    },
    {
        .name = "opensplat",
        .skeleton = SPR_ALGO_GAUSS3D,
        .renderer = "pierotofy/OpenSplat, its CPU rasterizer (gsplat-cpu; the backward keeps its own rules: alpha capped at 0.99 with T "
                    "recovered by division, the conic's off-diagonal gradient halved, the view directions detached)",
        .version = "15b7e80 (gsplat_cpu.cpp last changed 0aca3f0)",
        .source = "rasterizer/gsplat-cpu/gsplat_cpu.cpp:48-257, 260-372, model.cpp:35-47, 83-222",
        /* no near test (L71): only t.z ≤ 0 culled, which it draws off-screen (w clamped at 1e-6, L121); det clamped, never culled */
        .cull = {.near = 0.0f, .near_lt = 0, .clip_k = 0.0f, .det_le = 0},
        .tan_clamp = 1,
        .dilation = {0.3f, SPR_GCOMP_OPTION, SPR_GCOMP_ROOT_OF_MAX, 0.0f},
        /* no tiles: rows [max(0, floor(gY − 3√Σ'yy) − 2), min(H, ceil(gY + 3√Σ'yy) + 2)), columns likewise (L167-168, L201-204) */
        .extent = {SPR_GEXT_BOX, 9.0, 0.0f, 0, 0.0f, 0, 0.0f, 2.0f},
        .alpha = {0.999f, A255},
        .stop = {0.0001f, 1},
        /* one global std::sort by its float camDepths (L155-159), the OpenGL depth of model.cpp's projection (0.001, 1000);
         * ties in file order here (std::sort's tie permutation is libstdc++'s introsort) */
        .order = {SPR_GKEY_TILE_GLDEPTH, 32, 0.001f, 1000.0f},
        .blend = SPR_GBLEND_UNDER,
        .colour = {3, SPR_Q8_NONE, SPR_Q8_NONE, SPR_Q8_NONE, 0},
        /* backward: cap 0.99 with T by division (L338-342), v_conic.y = 0.5·v_σ·x·y (L364), dirs from means.detach() (model.cpp L176) */
        .grad = {.trains = 1, .gate = 0, .tclamp = 0, .cap = 0.99f, .tdiv = 1, .half_b = 1, .detach_dirs = 1},
        .camera = {.centre = 1}, /* u = fx·x/z + W/2 − 0.5 (L119-125, model.cpp L110-113): cx, cy never reach it */
    },
    {
        .name = "khr",
        .skeleton = SPR_ALGO_GAUSS_BLEND,
        .renderer = "KhronosGroup/glTF KHR_gaussian_splatting (release candidate; SPEC 10.7 fills in what it leaves open)",
        .version = "77b44be",
        .source = "extensions/2.0/Khronos/KHR_gaussian_splatting/README.md",
        .cull = {.near = 0.2f, .near_lt = 0, .clip_k = 0.0f, .det_le = 0},
        .tan_clamp = 1,
        .dilation = {0.3f, SPR_GCOMP_OPTION, SPR_GCOMP_ROOT_OF_MAX, 0.000025f},
        .extent = {SPR_GEXT_SQUARE, 9.0, 0.0f, 0, 0.1f, 0, 0.0f},
        .alpha = {0.99f, A255},
        .stop = {0.0f, 0},
        .order = {SPR_GKEY_DISTANCE, 64},
        .blend = SPR_GBLEND_PREMUL,
        .colour = {3, SPR_Q8_NONE, SPR_Q8_NONE, SPR_Q8_NONE, 0},
    },
    {
        .name = "gaussiansplats3d",
        .skeleton = SPR_ALGO_GAUSS_BLEND,
        .renderer = "mkkellogg/GaussianSplats3D (npm @mkkellogg/gaussian-splats-3d)",
        .version = "0.4.7",
        .source = "src/splatmesh/SplatMaterial.js:156-164, SplatMaterial3D.js:111-250, src/loaders/ply/INRIAV1PlyParser.js:157-179, "
                  "src/worker/sorter.cpp:64-167",
        /* GL clips the quad at the camera's near plane (ndc.z < −1); the shader culls outside 1.2·w */
        .cull = {.near = -1.0f, .near_lt = 1, .clip_k = 1.2f, .det_le = 0},
        .tan_clamp = 0,
        .dilation = {0.3f, SPR_GCOMP_OPTION, SPR_GCOMP_ROOT_OF_MAX, 0.0f},
        .extent = {SPR_GEXT_QUAD, 8.0, 1024.0f, 0, 0.1f, 0, 0.0f},
        .alpha = {1.0f, 0.0f},
        .stop = {0.0f, 0},
        .order = {SPR_GKEY_CLIP_INT, 16},
        .blend = SPR_GBLEND_STRAIGHT,
        .colour = {2, SPR_Q8_FLOOR, SPR_Q8_FLOOR, SPR_Q8_NONE, 1},
    },
    {
        .name = "spark",
        .skeleton = SPR_ALGO_GAUSS_BLEND,
        .renderer = "sparkjsdev/spark (npm @sparkjsdev/spark)",
        .version = "2.2.0",
        .source = "src/shaders/splatVertex.glsl:86-272, splatFragment.glsl:30-61, src/SparkRenderer.ts:474-522, rust/spark-lib/src/splat_encode.rs",
        /* culled at |clip z| ≥ w (the camera's near plane) and outside 1.4·w */
        .cull = {.near = -1.0f, .near_lt = 0, .clip_k = 1.4f, .det_le = 0},
        .tan_clamp = 0,
        .dilation = {0.3f, SPR_GCOMP_ALWAYS, SPR_GCOMP_ROOT_OF_MAX, 0.0f},
        .extent = {SPR_GEXT_QUAD, 8.0, 512.0f, 0, 0.0f, 0, 0.0f},
        .alpha = {1.0f, 0.5f / 255.0f},
        .stop = {0.0f, 0},
        .order = {SPR_GKEY_DISTANCE, 32},
        .blend = SPR_GBLEND_PREMUL,
        .colour = {3, SPR_Q8_ROUND, SPR_Q8_HALVED, SPR_Q8_ROUND, 1, SPR_GSCALE8_SPARK, 1},
    },
    {
        .name = "playcanvas",
        .skeleton = SPR_ALGO_GAUSS_BLEND,
        .renderer = "playcanvas/engine (npm playcanvas; the unified gsplat path, its default)",
        .version = "2.23.3",
        .source = "src/scene/shader-lib/glsl/chunks/gsplat/vert/gsplatCorner.js:37-76, vert/gsplatCenter.js:50-57, frag/gsplat.js:35-73, "
                  "gsplat-unified/gsplat-params.js:48-82",
        /* only behind the camera; its constants are in half-pixel units: +0.3 is 0.075 px², the 2 px size a diameter */
        .cull = {.near = 0.0f, .near_lt = 0, .clip_k = 0.0f, .det_le = 0},
        .tan_clamp = 0,
        .dilation = {0.075f, SPR_GCOMP_OPTION, SPR_GCOMP_ROOT_OF_MAX, 0.0f},
        .extent = {SPR_GEXT_QUAD, 8.0, 1024.0f, 1, 0.0f, 1, 1.0f},
        .alpha = {1.0f, A255},
        .stop = {0.0f, 0},
        .order = {SPR_GKEY_VIEW_Z, 32},
        .blend = SPR_GBLEND_PREMUL,
        .colour = {3, SPR_Q8_NONE, SPR_Q8_ROUND, SPR_Q8_NONE, 0, SPR_GSCALE8_PLAYCANVAS},
    },
    {
        .name = "babylon",
        .skeleton = SPR_ALGO_GAUSS_BLEND,
        .renderer = "BabylonJS/Babylon.js (npm @babylonjs/core; read at its source, not run here)",
        .version = "8.56.2",
        .source = "Shaders/ShadersInclude/gaussianSplatting.js:96-124, gaussianSplattingFragmentDeclaration.js:6-7, "
                  "Meshes/GaussianSplatting/gaussianSplattingMesh.js:980-1145",
        /* clip z < −w (the camera's near plane) and outside 1.2·w; half-pixel units: +0.3 is 0.075 px² */
        .cull = {.near = -1.0f, .near_lt = 1, .clip_k = 1.2f, .det_le = 0},
        .tan_clamp = 0,
        .dilation = {0.075f, SPR_GCOMP_OPTION, SPR_GCOMP_ROOT_OF_MAX, 0.0f},
        .extent = {SPR_GEXT_QUAD, 8.0, 1024.0f, 0, 0.0f, 0, 0.0f},
        .alpha = {1.0f, 0.0f},
        .stop = {0.0f, 0},
        .order = {SPR_GKEY_VIEW_Z, 32},
        .blend = SPR_GBLEND_STRAIGHT,
        .colour = {3, SPR_Q8_ROUND, SPR_Q8_ROUND, SPR_Q8_NONE, 0},
    },
};
enum { NROWS = (int)(sizeof rows / sizeof rows[0]) };

int spr_gauss_profile_count(void) { return NROWS; }
const spr_gauss_profile *spr_gauss_profile_at(int i) { return i >= 0 && i < NROWS ? &rows[i] : NULL; }

int spr_gauss_profile_from_name(const char *name)
{
    for (int i = 0; i < NROWS; i++)
        if (!strcmp(name, rows[i].name)) return i;
    return -1;
}

const char *spr_gauss_profile_names(const char *sep)
{
    static char buf[512];
    size_t o = 0;
    buf[0] = 0;
    for (int i = 0; i < NROWS && o < sizeof buf; i++) o += (size_t)snprintf(buf + o, sizeof buf - o, "%s%s", i ? sep : "", rows[i].name);
    return buf;
}

const spr_gauss_profile *spr_gauss_profile_of(spr_algo algo, int profile)
{
    if (profile > 0 && profile <= NROWS) return &rows[profile - 1];
    return &rows[spr_gauss_profile_from_name(algo == SPR_ALGO_GAUSS_BLEND ? "khr" : "inria")];
}

static float stored_scale(const spr_gauss_profile *p, float s)
{
    if (p->colour.scale8 == SPR_GSCALE8_SPARK) {
        const double t = (log((double)s) + 12.0) / 21.0, c = 1.0 + floor((t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t) * 254.0 + 0.5);
        return (float)exp(-12.0 + (c - 1.0) * 21.0 / 254.0);
    }
    if (p->colour.scale8 == SPR_GSCALE8_PLAYCANVAS) {
        if (!(s >= 1e-10f)) return 0.0f;
        double t = (log((double)s) + 12.0) * 255.0 / 21.0 + 0.5;
        t = t < 1.0 ? 1.0 : t > 255.0 ? 255.0 : t;
        return (float)exp(floor(t) * 21.0 / 255.0 - 12.0);
    }
    return s;
}

/* x rounded to the nearest IEEE half (ties to even; beyond 65504 infinite), in double: exact. */
static double to_half(double x)
{
    if (!(fabs(x) < 65520.0)) return x > 0.0 ? INFINITY : x < 0.0 ? -INFINITY : x;
    int e;
    frexp(x, &e); /* |x| in [2^(e−1), 2^e) */
    const double step = ldexp(1.0, (e - 1 < -14 ? -14 : e - 1) - 10); /* below 2^-14: the subnormals' step 2^-24 */
    return nearbyint(x / step) * step;
}

int spr_gauss_profile_stores(const spr_gauss_profile *p) { return p->colour.scale8 || p->colour.op8 || p->colour.pos16; }

void spr_gauss_profile_store(const spr_gauss_profile *p, const spr_cloud *c, size_t G, const double eye[3], float s[3], float mu[3], float *o)
{
    for (int k = 0; k < 3; k++) {
        const float m = c->pos[3 * G + k];
        mu[k] = p->colour.pos16 ? (float)(eye[k] + to_half(to_half(m) - eye[k])) : m;
        s[k] = stored_scale(p, s[k]);
    }
    *o = p->colour.op8 ? (float)spr_unorm8(c->alpha[G], p->colour.op8) : c->alpha[G];
}

int spr_gauss_profile_fits(const spr_gauss_profile *p, spr_algo algo)
{
    return p->skeleton == algo || (algo == SPR_ALGO_GAUSS2D && p->skeleton == SPR_ALGO_GAUSS3D);
}
