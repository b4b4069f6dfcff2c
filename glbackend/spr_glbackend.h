/* spr_glbackend.h — the OpenGL 4.5 core backend (EGL, any driver).
 *
 * Implements spr_backend with the real GL pipeline: one instanced screen
 * quad per splat bounding its projected disk, a fragment shader that runs
 * the shared arithmetic of core/render/arith/ (embedded verbatim, with
 * `precise` on every arithmetic variable: PARITY.md rules 1–5),
 * fixed-function depth test (gl_FragDepth into DEPTH_COMPONENT32F) and
 * blending on RGBA32F.  Composite ops are full-screen passes running the
 * composite table's per-pixel functions over the input targets' layers.
 */
#ifndef SPR_GLBACKEND_H
#define SPR_GLBACKEND_H

#include "spr_backend.h"

/* The GL drivers a backend can ask for by name (--gl-driver): Mesa's
 * software drivers, chosen through Mesa's environment (LIBGL_ALWAYS_SOFTWARE,
 * GALLIUM_DRIVER) before the display is initialised.  Columns: enum, name,
 * GALLIUM_DRIVER value, how GL_RENDERER begins on it, the Debian package it
 * needs beyond libgl1-mesa-dri.  DEFAULT changes nothing: EGL and the
 * environment as the user set it choose. */
#define SPR_GL_DRIVER_LIST(X)                                       \
    X(DEFAULT, "default", NULL, NULL, NULL)                         \
    X(LLVMPIPE, "llvmpipe", "llvmpipe", "llvmpipe", NULL)           \
    X(ZINK, "zink", "zink", "zink", "mesa-vulkan-drivers")
typedef enum spr_gl_driver {
#define SPR__GLD(e, name, gallium, renderer, package) SPR_GL_DRIVER_##e,
    SPR_GL_DRIVER_LIST(SPR__GLD)
#undef SPR__GLD
    SPR_GL_DRIVER__COUNT
} spr_gl_driver;
/* "default", "llvmpipe", "zink"; NULL out of range. */
const char *spr_gl_driver_name(spr_gl_driver d);
/* The driver of that name: 0, or −1 for a name not in the list. */
int spr_gl_driver_parse(const char *name, spr_gl_driver *out);
/* The known names, "default | llvmpipe | zink", for messages. */
const char *spr_gl_driver_names(void);

typedef struct spr_gl_desc {
    int device;   /* −1: EGL_PLATFORM_SURFACELESS_MESA (default); N ≥ 0: the N-th EGL device */
    spr_gl_driver driver; /* surfaceless only; one driver a process at a time (EGL keeps one a display) */
    int probe;    /* 1: build the debug variant of every program, which can record a pixel's
                     fragments and notes for pixel history (spr_history.h); slower */
    size_t gauss_batch; /* Gaussians preprocessed a draw, with buffers of their own (0: as many as GL_MAX_SHADER_STORAGE_BLOCK_SIZE
                           takes, 524,288 on llvmpipe and zink); tests give a few to cross many batches */
    size_t max_texels;  /* 0: the driver's GL_MAX_TEXTURE_BUFFER_SIZE; smaller: that limit instead (tests of the refusal) */
    int gauss_steps;    /* the Gaussian loops' steps a draw: list entries a pixel (spr_gauss_pixel_run), steps a tile of the
                           backward (spr_gauss_tile_bwd); 0: within llvmpipe's loop budget.  Tests give a few to resume
                           every loop across many draws */
} spr_gl_desc;
void spr_gl_defaults(spr_gl_desc *d);
/* SPR_OK, or SPR_E_ARG with one line: a driver out of the list, or a driver
 * named together with a device (spr_gl_create checks the same). */
spr_result spr_gl_desc_check(const spr_gl_desc *d, spr_error *err);

/* New GL backend, or NULL with a one-line reason in err: SPR_E_NO_DEVICE
 * when no EGL display or GL 4.5 core context can be had at all, or the
 * driver asked for is not the one EGL gave (not installed), another
 * code (SPR_E_BACKEND) when one exists but the backend cannot be built on
 * it, e.g. a shader that does not compile. */
spr_backend *spr_gl_create(const spr_gl_desc *d, spr_error *err);
/* "renderer | version" of a GL backend (for reports; PARITY.md rule 9). */
const char *spr_gl_renderer(const spr_backend *b);
/* The fragment shader text GL compiled for "splat" or "composite", as GL
 * reports it (glGetShaderSource); malloc'd, NULL for another name. */
char *spr_gl_program_source(spr_backend *b, const char *program);

#endif
