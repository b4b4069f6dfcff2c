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

typedef struct spr_gl_desc {
    int device;   /* −1: EGL_PLATFORM_SURFACELESS_MESA (default); N ≥ 0: the N-th EGL device */
    int probe;    /* 1: build the debug variant of every program, which can record a pixel's
                     fragments and notes for pixel history (spr_history.h); slower */
} spr_gl_desc;
void spr_gl_defaults(spr_gl_desc *d);

/* New GL backend, or NULL with a one-line reason in err: SPR_E_NO_DEVICE
 * when no EGL display or GL 4.5 core context can be had at all, another
 * code (SPR_E_BACKEND) when one exists but the backend cannot be built on
 * it, e.g. a shader that does not compile. */
spr_backend *spr_gl_create(const spr_gl_desc *d, spr_error *err);
/* "renderer | version" of a GL backend (for reports; PARITY.md rule 9). */
const char *spr_gl_renderer(const spr_backend *b);
/* The fragment shader text GL compiled for "splat" or "composite", as GL
 * reports it (glGetShaderSource); malloc'd, NULL for another name. */
char *spr_gl_program_source(spr_backend *b, const char *program);

#endif
