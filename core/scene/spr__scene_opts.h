/* spr__scene_opts.h — option table rows shared by the subcommands, in
 * groups, so each command lists only what it can use (and spr__reject_unused
 * refuses what the chosen algorithm or grouping does not read). */
#ifndef SPR__SCENE_OPTS_H
#define SPR__SCENE_OPTS_H

/* Loading a model. */
#define SPR__MODEL_OPTS \
    {"model", "PATH|builtin:NAME", "model file (.ply .off .xyz .pwn .txt .asc .csv .pts .splat .spz .glb .sog, a SOG folder's meta.json; docs/formats.md) or builtin:sphere|torus|octahedron|planes|cube|spheres (default builtin:torus)"}, \
    {"points", "N", "size of a built-in model (default 20000)"}, \
    {"radius-k", "K", "k of the radius rule r = rho*d_k when the file has no radii (default 8)"}, \
    {"radius-scale", "RHO", "rho of the radius rule (default 1.0)"}, \
    {"threads", "N", "CPU threads (default: all cores)"}, \
    {"opacity", "A", "set every splat's opacity in (0,1] as loaded, before --balls (default: the file's, else 1)"}, \
    {"balls", "N", "add N small opaque balls inside the closed model, 1..64 (the scenes of [ZP] Fig. 17-19)"}, \
    {"gauss-cut", "C", "Gaussian-splat files: cut each Gaussian at C standard deviations, in (0,3] (default 3: the gauss kernel is then the capture's Gaussian)"}, \
    {"sh-degree", "D", "Gaussian-splat files: spherical-harmonics degree of the view-dependent colour, 0..3 (default 0: the DC colour)"}, \
    {"spz-frame", "FRAME", ".spz files: rub (the format's frame, turned into the training frame; default) | raw (taken as stored: splat-transform 3.x writes the PLY frame unconverted)"}, \
    {"columns", "LIST", "text point files without a header: the column names, e.g. x,y,z,r,g,b,_,nx,ny,nz (_ skips one)"}, \
    {"quiet", NULL, "no progress on stderr"}

/* The camera and the image. */
#define SPR__CAMERA_OPTS \
    {"eye", "X,Y,Z", "camera position (default: frame the model from +z)"}, \
    {"target", "X,Y,Z", "point looked at (default: model centre)"}, \
    {"up", "X,Y,Z", "up vector (default 0,1,0)"}, \
    {"fov", "DEG", "vertical field of view, perspective (default 30)"}, \
    {"ortho", "HEIGHT", "orthographic camera with this view height"}, \
    {"near", "N", "near plane (default: tight around the model)"}, \
    {"far", "F", "far plane (default: tight around the model)"}, \
    {"size", "WxH", "image size (default 512x512)"}, \
    {"view-matrix", "M16", "raw 4x4 view matrix, 16 numbers row by row (with --projection-matrix; replaces eye/target/up)"}, \
    {"projection-matrix", "M16", "raw 4x4 projection matrix, row by row, bottom row 0,0,-1,0 or 0,0,0,1 (replaces fov/ortho)"}, \
    {"intrinsics", "FX,FY,CX,CY", "pinhole camera of the training code: focal lengths and principal point in pixels, continuous (pixel centres at i+0.5, row 0 at the top); with --world-to-camera"}, \
    {"world-to-camera", "M12", "pinhole camera: OpenCV world-to-camera [R|t], 12 numbers row by row (x right, y down, z forward); with --intrinsics"}, \
    {"cameras", "F.json", "the training code's cameras.json; with --camera ID (its size unless --size, which scales the intrinsics)"}, \
    {"camera", "ID|all", "--cameras: the entry whose id is ID (check: all, every entry, with --images DIR)"}, \
    {"background", "R,G,B", "background colour in [0,1] (default 0,0,0)"}

/* The algorithm and its parameters (which ones an algorithm reads: the registry). */
#define SPR__ALGO_OPTS \
    {"algo", "NAME", "algorithm from the registry (listed below; default deferred)"}, \
    {"kernel", "NAME", "gauss | constant | linear | epanechnikov (default gauss)"}, \
    {"eps", "E", "depth tolerance in world units (default 2 x mean radius)"}, \
    {"voronoi", NULL, "deferred: Voronoi depth [ZP] Eq. 14"}, \
    {"lowres-n", "N", "quantisation steps n of the low-precision depth (default from eps)"}, \
    {"order", "HOW", "transparent: back-to-front order by bsp (default) or sort"}, \
    {"alpha", "A", "transparent: opacity in (0,1] for every splat (default: the file's, else 1)"}, \
    {"shade", "MODEL", "deferred shading none | phong (default none; SPEC 4.3)"}, \
    {"light", "X,Y,Z", "phong: direction towards the light, eye space (default -0.4,0.5,1)"}, \
    {"material", "KA,KD,KS,EXP", "phong: ambient, diffuse, specular and whole exponent 1..1024 (default 0.2,0.8,0.4,32)"}, \
    {"env", "MAP", "transparent2: environment effects with cube map sky | checker | DIR (DIR/px,nx,py,ny,pz,nz.png)"}, \
    {"env-size", "S", "env: texels a side of a built-in cube map (default 256)"}, \
    {"eta", "E|R,G,B", "env: refraction ratio outside/inside, one, or three for dispersion (default 0.6711,0.6667,0.6579)"}, \
    {"env-layers", "HOW", "env: multi (sin T = eta^(l+1) sin I, default) | single (one interface)"}, \
    {"layers", "L", "depthpeel: layers peeled, 1..64 (default 8; 3 = the front-three variant)"}, \
    {"sampling", "HOW", "domain-*: texture sampling nearest | linear (explicit bilinear, default) | hardware (GL texture(), Tier B)"}, \
    {"alpha-ref", "A", "domain-overlap: lock pixels where alpha >= A (default 0.1)"}, \
    {"gauss-aa", NULL, "gauss*: the antialiased opacity o*sqrt(max(0.000025, det0/det)) of the training code's antialiased mode (SPEC 10.3)"}, \
    {"gauss-profile", "NAME", "gauss*: the renderer whose image to draw, a row of `splatref profiles` (SPEC 10.9; defaults: inria for gauss3d and gauss2d, khr for gauss-blend); alone it picks the row's algorithm"}, \
    {"gauss-flavor", "NAME", "the old name of --gauss-profile"}

/* Grouping parameters; the method itself is render's --groups or group's --method. */
#define SPR__GROUP_OPTS \
    {"groups-file", "F", "read the groups from F (one group per splat, or `splat group` memberships)"}, \
    {"c", "C", "mgc: overlap relaxation factor in [0,1] (default 1.0; 0: no edge, one group)"}, \
    {"relax", "LIST", "mgc: relaxations coplanar,opposite | coplanar | opposite | none (default both)"}, \
    {"k", "K", "wgc/hash: number of groups (default 8)"}, \
    {"mode", "M", "hash: 1 no collision handling, 2 collisions handled, 3 mixed (default 1)"}, \
    {"hash-axis", "AXIS", "hash: bsp (leaf average normal, default) | normal (own normal)"}, \
    {"hash-near", "DIST", "hash mode 3: handle collisions within this eye distance ('centre': eye to model centre)"}, \
    {"extend", "HOW", "extended grouping: dup (duplication) | radius (Eq. 13) | hash-radius (sqrt(50)/4 for K=8)"}

/* The domain pipeline (SPEC 7): `domains` and the domain-* algorithms. */
#define SPR__DOMAIN_OPTS \
    {"level", "L", "decomposition level, 0 = coarsest (render default 2)"}, \
    {"domain", "HOW", "thresholded (phi >= --threshold, default) | strict (largest phi)"}, \
    {"threshold", "K", "thresholded domains: phi >= K (default 0.01)"}, \
    {"knn", "K", "neighbours of the local analysis and of the coupling graph (default 10)"}, \
    {"delta", "D", "coupling 1/(D + max sigma) (default 0.01)"}, \
    {"normal-power", "P", "coupling times |n_j.n_k|^P: weak across creases (default 4; 0: sigma alone)"}, \
    {"omega", "W", "prolongation smoothing in [0,1): how much the basis functions overlap (default 0.5)"}, \
    {"enlarge", "E", "support rectangles grown by E about their centre (default 0.05)"}, \
    {"texture", "HOW", "radial (default) | affine: qhull Delaunay, barycentric inside, radial elsewhere ([R] 3.3.3)"}, \
    {"rbf", "SHAPE", "radial texture basis: constant | linear (default) | gauss ([R] 3.3.2)"}, \
    {"width", "W", "radial support W x the point radius (default 1)"}, \
    {"texel", "T", "texel side T x the domain's mean radius (default 1)"}, \
    {"normalize", "WHEN", "gt0: where f > 0 (Eq. 3.4, default) | ge1: where f >= 1 (Eq. 3.3)"}, \
    {"extend-color", NULL, "texels no point reaches take the nearest point's colour ([R] 3.3.4)"}, \
    {"merge", "FLAT,DOT", "merge overlapping domains flatter than FLAT whose normals' dot exceeds DOT ([R] 3.4), e.g. 0.05,0.9"}, \
    {"nbr-ratio", "R", "neighbours share more than R of either domain's points (default 0.05, [R] 4.4.4)"}

/* Reading the model chunk by chunk (render, parity): a run mode, not part of the scene. */
#define SPR__STREAM_OPTS \
    {"stream", NULL, "read a binary PLY chunk by chunk for every pass instead of whole (clouds larger than memory; pbr2p1, deferred, zbuffer, depthpeel; groups none, hash or a file)"}, \
    {"chunk", "N", "--stream: splats per chunk (default 1048576)"}

/* The GL backend's driver: a scene file's "backend" section (which GL the
 * scene's parity was run on); read by the commands that make a GL backend. */
#define SPR__BACKEND_OPTS \
    {"gl-driver", "NAME", "GL backend: llvmpipe | zink (Mesa's GL over Vulkan, on lavapipe) | default (EGL's choice: LIBGL_ALWAYS_SOFTWARE, GALLIUM_DRIVER as set)"}

/* Everything that determines a rendered scene (render, parity, reference). */
#define SPR__SCENE_OPTS \
    {"scene", "F.json", "read the scene from F (docs/scene-format.md); options given here override it"}, \
    {"save-scene", "F.json", "write everything that determines the image to F (camera resolved)"}, \
    {"scene-camera", "FORM", "save-scene: the camera as lookat (eye/target/up/fov, default) | matrices"}, \
    SPR__MODEL_OPTS, SPR__CAMERA_OPTS, SPR__ALGO_OPTS, SPR__DOMAIN_OPTS, \
    {"groups", "METHOD", "grouping of the algorithms that use groups: none | mgc | wgc | hash (default mgc)"}, \
    SPR__GROUP_OPTS, SPR__BACKEND_OPTS

#endif
