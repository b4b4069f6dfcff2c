/* spr_scene.h — a scene as the command line and scene files describe it:
 * the model, the camera and its view, the grouping, the domain primitives
 * and the render descriptor, ready for spr_render().
 *
 *   spr_scene s;
 *   spr_render_desc rd;
 *   if (spr_scene_load("s.json", 0, &s, &rd, &err)) { ... err.msg ... }
 *   spr_render(backend, &s.view, &s.cloud, &rd, &result, &err);
 *   spr_scene_free(&s);
 *
 * Scene files are specified in docs/scene-format.md (`splatref render
 * --save-scene F` writes one).  spr_scene_load() reads one exactly as
 * `splatref render --scene F` does: the same bits come out.
 */
#ifndef SPR_SCENE_H
#define SPR_SCENE_H

#include "spr_algo.h"
#include "spr_io.h"
#include "spr_domain.h"
#include "spr_group.h"
#include "spr_bsp.h"

/* The domain pipeline's options (cli_domopts.c). */
typedef struct spr_scene_domain {
    spr_decomp_desc dd;
    spr_prims_desc pd;
    int level;            /* −1: the default */
    int merge;
    double mflat, mdot;
    int level_used, levels;
    size_t regions;
    double ms_decomp;
} spr_scene_domain;

/* A loaded scene: model, camera, view and grouping. */
typedef struct spr_scene {
    spr_cloud cloud;
    spr_camera_desc cam;
    spr_camera_desc cam_given; /* the camera as the options gave it, before spr_camera_frame */
    spr_bounds bounds;      /* the model's bounds the camera was framed on */
    spr_view view;
    spr_grouping g;
    spr_bsp bsp;            /* back-to-front orders by BSP: the tree, built once (nodes NULL: none) */
    const char *group_method;
    char model[1024];
    int threads;
    int all_algos;          /* parity/reference: --algo all (the default there) */
    spr_envmap env;         /* --env's cube map (texels NULL: none) */
    spr_rects rects;        /* the domain primitives of domain-* algorithms (n 0: none) */
    spr_prims_stats prims;
    spr_scene_domain dom;
    double load_ms;
    size_t stream_chunk;    /* --stream: splats per chunk (0: 2^20) */
    int stream_keep;        /* --stream: keep centres, normals and radii for grouping until grouped */
    spr_cloud_source src;   /* --stream: the model read chunk by chunk (read NULL: loaded whole); cloud then holds
                               only n (its arrays NULL) and the render desc's source points here */
} spr_scene;

/* Read scene file `path`, load and frame its model, build its groups and
 * domain primitives; rd receives the algorithm and its parameters (no
 * hook).  threads: CPU threads for loading and grouping (0: all cores).
 * SPR_OK, or an error whose message names the file and the key. */
spr_result spr_scene_load(const char *path, int threads, spr_scene *s, spr_render_desc *rd, spr_error *err);
void spr_scene_free(spr_scene *s);

#endif
