/* spr_ffi.h — splatref for other languages (the Python package, python/):
 * opaque handles, plain C types, and structured results as JSON text with
 * the keys of the command line's reports, computed by the same library
 * functions as `splatref check`, `explain --json` and `parity --report`.
 *
 *   const char *keys[] = {"model", "algo", "size"}, *vals[] = {"builtin:torus", "deferred", "256x256"};
 *   spr_ffi_scene *s = spr_ffi_scene_new(3, keys, vals, NULL);      // NULL: spr_ffi_error()
 *   spr_ffi_frame *f = spr_ffi_render(s, "cpu", -1, 1);              // every plane of every pass
 *   const float *rgba = spr_ffi_frame_image(f, &w, &h);               // row 0 = bottom
 *   char *report = spr_ffi_check(s, ...);  spr_ffi_free(report);
 *
 * Options are the scene-file keys and render's options, by their command
 * line names ("radius-scale"; "radius_scale" is read the same), values as
 * the command line writes them; a flag's value is "1".  Every call that
 * fails returns NULL (or −1) and leaves one line in spr_ffi_error() (per
 * thread) and its code (spr_result) in spr_ffi_error_code().  Images handed
 * in and planes handed out are row 0 = bottom, as every plane of the
 * library; the Python package turns them to row 0 = top.
 */
#ifndef SPR_FFI_H
#define SPR_FFI_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct spr_ffi_scene spr_ffi_scene;
typedef struct spr_ffi_frame spr_ffi_frame;

/* A cloud given as arrays instead of a model file (copied; checked as a
 * loaded file is: finite values, unit normals, positive radii). */
typedef struct spr_ffi_arrays {
    size_t n;
    const float *pos;    /* 3n */
    const float *nrm;    /* 3n */
    const float *radius; /* n */
    const float *color;  /* 3n in [0,1], or NULL: white */
    const float *alpha;  /* n in [0,1], or NULL: 1 */
} spr_ffi_arrays;

const char *spr_ffi_version(void);
/* The renderer profile table (SPEC 10.9) as JSON, as `splatref profiles --json` prints it (free with spr_ffi_free). */
char *spr_ffi_profiles(void);
/* The last failure of this thread: one line, and its spr_result code. */
const char *spr_ffi_error(void);
int spr_ffi_error_code(void);
/* Free a string this interface returned. */
void spr_ffi_free(char *s);

/* A scene from n options (keys[i] = values[i]; "scene" reads a scene file,
 * whose values fill the options not given), loaded, framed and grouped as
 * `splatref render` does; arrays: the cloud instead of --model (NULL: the
 * model option). */
spr_ffi_scene *spr_ffi_scene_new(int n, const char *const *keys, const char *const *values, const spr_ffi_arrays *arrays);
void spr_ffi_scene_free(spr_ffi_scene *s);
/* {"model", "splats", "width", "height", "algo", "groups" (K, 0: none), "threads"}, and for a domain-*
 * algorithm "primitives": {"level", "levels", "regions", "polygons", "texels", "error", "error_norm",
 * "points_per_polygon", "ms_decompose", "ms_primitives"} (SPEC §7; `splatref domains --stats`' columns). */
char *spr_ffi_scene_json(const spr_ffi_scene *s);
/* The loaded cloud: field "pos", "nrm" (3 floats a splat), "radius",
 * "alpha" (1), "color" (3); *n the splats, *comps the floats a splat. */
const float *spr_ffi_scene_cloud(const spr_ffi_scene *s, const char *field, size_t *n, int *comps);

/* The domain primitives a domain-* scene draws (SPEC §7.4, §7.5): *n
 * rectangles of SPR_RECT_FLOATS (17) floats each, the returned array: centre
 * c, normal n, axes u and v (3 each), umin, umax, vmin, vmax, texel side h;
 * *ints: SPR_RECTI_COUNT (4) integers each: texels along u (tw) and v (th),
 * the first texel, the domain (region) number; *texels: RGBA (colour, alpha
 * = the basis function), *n_texels of them, texel (x, y) of a rectangle at
 * first + y·tw + x, y = 0 at vmin.  NULL after an error when the scene
 * draws none. */
const float *spr_ffi_scene_rects(const spr_ffi_scene *s, size_t *n, const uint32_t **ints, const float **texels, size_t *n_texels);

/* Render on "cpu" or "gl" (gl_device −1: the surfaceless platform);
 * passes: keep every plane of every pass.  GL without a device fails with
 * code SPR_E_NO_DEVICE. */
spr_ffi_frame *spr_ffi_render(spr_ffi_scene *s, const char *backend, int gl_device, int passes);
void spr_ffi_frame_free(spr_ffi_frame *f);
/* The final image, w·h·4 floats. */
const float *spr_ffi_frame_image(const spr_ffi_frame *f, int *w, int *h);
/* {"backend", "renderer", "width", "height", "K", "eps_t", "passes": [{"index", "name", "group", "target",
 * "composite", "planes": [names], "generated", "passed", "ms", "records"}]} */
char *spr_ffi_frame_json(const spr_ffi_frame *f);
/* Plane `plane` (its name) of the i-th kept pass: w·h·*channels floats
 * (ids and counts as floats, none = −1), NULL when that pass has none. */
const float *spr_ffi_frame_plane(const spr_ffi_frame *f, int i, const char *plane, int *channels);
/* A Gaussian preprocessing pass's records: *rows of *cols floats. */
const float *spr_ffi_frame_records(const spr_ffi_frame *f, int i, size_t *rows, int *cols);

/* `splatref check`: image (w·h·ch values, row 0 = bottom; bits 8 → uint8,
 * 16 → uint16, 32 → float) against the scene's reference plane (plane
 * NULL: the final colour; pass −1: the last pass that has it) under tier
 * "A" | "B" | "C" (NULL: A, or B when a bound is given; ulp < 0, lsb < 0:
 * no bound).  label names the image in the report.  state: NULL or w·h
 * bytes receiving 0 equal, 1 within bounds, 2 passing only within one
 * pixel, 3 failing.  The report as check's report.json. */
char *spr_ffi_check(spr_ffi_scene *s, const void *image, int w, int h, int ch, int bits, const char *label, const char *plane, int pass,
                    const char *tier, double ulp, int lsb, int position, unsigned char *state);
/* `splatref explain --json` of pixel (x, y) (y from the bottom) on
 * backend "cpu", "gl" or "both" (both without a GL device: the CPU alone). */
char *spr_ffi_explain(spr_ffi_scene *s, int x, int y, const char *backend, int gl_device);
/* `splatref parity --report`'s report.json: the CPU reference against GL;
 * algo NULL: the scene's algorithm, "all": every one. */
char *spr_ffi_parity(spr_ffi_scene *s, const char *algo, int gl_device);

/* `splatref grad`: the gradients of the scene's gauss3d frame (SPEC 10.10; docs/gradients.md) on "cpu" or "gl",
 * for an upstream gradient: loss "l1" | "l2" (the mean over pixels and channels of |C − target| or (C − target)²;
 * target w·h·3 floats, NULL: black), or loss NULL and dl_dimage (w·h·3, ∂L/∂C); dl_dalpha, dl_ddepth: w·h or NULL.
 * Every image row 0 = bottom.  batch: list entries a backend holds at once (0: its own; grad's --grad-batch). */
typedef struct spr_ffi_grads spr_ffi_grads;
spr_ffi_grads *spr_ffi_grad(spr_ffi_scene *s, const char *backend, int gl_device, const char *loss, const float *target,
                            const float *dl_dimage, const float *dl_dalpha, const float *dl_ddepth, size_t batch);
void spr_ffi_grads_free(spr_ffi_grads *g);
/* {"backend", "renderer", "profile", "gaussians", "sh_k", "width", "height", "loss" (null for a given gradient),
 * "loss_value", "ms_forward", "ms_backward", "arrays": [{"name", "shape": [n, ...], "dtype": "float32" | "int32"}]}:
 * the arrays in SPEC 10.10's order, gsplat's names and shapes, as grad's .npz members. */
char *spr_ffi_grads_json(const spr_ffi_grads *g);
/* Array `name` (means, quats, scales, opacities, sh0, shN, means2d, conics, colors, absgrad: floats; counts: int32),
 * *count values, contiguous per Gaussian (sh0 n·3, shN n·(sh_k − 1)·3, coefficient-major as grad's .npz). */
const void *spr_ffi_grads_array(const spr_ffi_grads *g, const char *name, size_t *count);
/* The forward's image, w·h·4 floats, row 0 = bottom. */
const float *spr_ffi_grads_image(const spr_ffi_grads *g, int *w, int *h);

/* Save a float image (w·h·ch, row 0 = bottom) as PNG (8-bit, spr_to_u8)
 * or PFM, by the name's extension, through a temporary file.  0 or −1. */
int spr_ffi_write_image(const char *path, const float *img, int w, int h, int ch);
/* The 8-bit value of a float (PARITY rule 8), as PNG files are written. */
uint8_t spr_ffi_to_u8(float v);

#ifdef __cplusplus
}
#endif

#endif
