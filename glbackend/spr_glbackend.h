/* spr_glbackend.h — the OpenGL 4.5 core backend (EGL, any driver).
 *
 * Implements spr_backend with the real GL pipeline: one instanced screen
 * quad per splat bounding its projected disk, a fragment shader doing the
 * SPEC §2 ray–disk test with the operations of core/spr_fragment.h in the
 * same order (`precise` everywhere, PARITY.md rules 1–5), fixed-function
 * depth test (gl_FragDepth into DEPTH_COMPONENT32F) and blending on RGBA32F.
 * Compositing is a full-screen pass reading the group targets with
 * texelFetch in the fixed k order.
 */
#ifndef SPR_GLBACKEND_H
#define SPR_GLBACKEND_H

#include "spr_backend.h"

typedef struct spr_gl_desc {
    int device;   /* −1: EGL_PLATFORM_SURFACELESS_MESA (default); N ≥ 0: the N-th EGL device */
} spr_gl_desc;
void spr_gl_defaults(spr_gl_desc *d);

/* New GL backend, or NULL with a one-line reason in err (no EGL display,
 * no GL 4.5 core context, shader compile failure). */
spr_backend *spr_gl_create(const spr_gl_desc *d, spr_error *err);
/* "renderer | version" of a GL backend (for reports; PARITY.md rule 9). */
const char *spr_gl_renderer(const spr_backend *b);
/* Number of EGL devices (EGL_EXT_device_enumeration), 0 when unsupported. */
int spr_gl_device_count(void);

#endif
