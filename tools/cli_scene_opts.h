/* cli_scene_opts.h — the option table entries shared by render and parity. */
#ifndef CLI_SCENE_OPTS_H
#define CLI_SCENE_OPTS_H

/* Options shared by render and parity: the scene, the algorithm, the groups. */
#define CLI_SCENE_OPTS \
    {"model", "PATH|builtin:NAME", "model file (.ply .off .xyz .pwn) or builtin:sphere|torus|octahedron|planes|cube (default builtin:torus)"}, \
    {"points", "N", "size of a built-in model (default 20000)"}, \
    {"radius-k", "K", "k of the radius rule r = rho*d_k when the file has no radii (default 8)"}, \
    {"radius-scale", "RHO", "rho of the radius rule (default 1.0)"}, \
    {"eye", "X,Y,Z", "camera position (default: frame the model from +z)"}, \
    {"target", "X,Y,Z", "point looked at (default: model centre)"}, \
    {"up", "X,Y,Z", "up vector (default 0,1,0)"}, \
    {"fov", "DEG", "vertical field of view, perspective (default 30)"}, \
    {"ortho", "HEIGHT", "orthographic camera with this view height"}, \
    {"near", "N", "near plane (default: tight around the model)"}, \
    {"far", "F", "far plane (default: tight around the model)"}, \
    {"size", "WxH", "image size (default 512x512)"}, \
    {"background", "R,G,B", "background colour in [0,1] (default 0,0,0)"}, \
    {"algo", "NAME", "pbr2p1 | deferred (default deferred)"}, \
    {"groups", "METHOD", "deferred grouping: none | mgc | wgc | hash (default mgc)"}, \
    {"groups-file", "F", "read one group per splat (input order) from F"}, \
    {"c", "C", "MGC overlap relaxation factor in (0,1] (default 1.0)"}, \
    {"relax", "LIST", "MGC relaxations: coplanar,opposite | coplanar | opposite | none (default both)"}, \
    {"k", "K", "wgc/hash grouping: number of groups (default 8)"}, \
    {"mode", "M", "hash: 1 no collision handling, 2 collisions handled, 3 mixed (default 1)"}, \
    {"hash-axis", "AXIS", "hash: bsp (leaf average normal, default) | normal (own normal)"}, \
    {"hash-near", "DIST", "hash mode 3: handle collisions within this eye distance ('centre': eye to model centre)"}, \
    {"extend", "HOW", "extended grouping: dup (duplication) | radius (Eq. 13) | hash-radius (sqrt(50)/4 for K=8)"}, \
    {"kernel", "NAME", "gauss | constant | linear | epanechnikov (default gauss)"}, \
    {"eps", "E", "depth tolerance in world units (default 2 x mean radius)"}, \
    {"voronoi", NULL, "deferred: Voronoi depth [ZP] Eq. 14"}, \
    {"lowres-n", "N", "quantisation steps n of the low-precision depth (default from eps)"}, \
    {"threads", "N", "CPU threads (default: all cores)"}, \
    {"quiet", NULL, "no progress on stderr"}

#endif
