/* gl_internal.h — private state of the GL backend, shared by its stages. */
#ifndef GL_INTERNAL_H
#define GL_INTERNAL_H

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include "spr_glbackend.h"

typedef struct gl_target {
    GLuint fbo;
    GLuint color, depth_value, id, count, ztest; /* textures: RGBA32F, R32F, R32UI, R32F, DEPTH32F */
} gl_target;

typedef struct gl_context {
    spr_backend base; /* first: a gl_context is an spr_backend */
    EGLDisplay dpy;
    EGLContext ctx;
    char renderer[512];
    GLuint prog_splat, prog_comp;
    GLuint vao, instances, counters;
    size_t instances_cap;
    GLuint arr_color, arr_depth; /* compositing inputs as array layers */
    int arr_layers, arr_w, arr_h;
    gl_target *targets;
    int cap;
} gl_context;

static inline gl_context *gl_ctx(spr_backend *b) { return (gl_context *)b; }

/* gl_context.c */
spr_result gl__egl_open(gl_context *c, int device, spr_error *err);
void gl__egl_close(gl_context *c);
/* gl_shaders.c */
spr_result gl__build_programs(gl_context *c, spr_error *err);
/* gl_backend.c */
spr_result gl__check(spr_backend *b, const char *what);

#endif
