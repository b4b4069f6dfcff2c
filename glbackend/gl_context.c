/* gl_context.c — EGL display and a GL 4.5 core context with no surface.
 *
 * Default: EGL_PLATFORM_SURFACELESS_MESA (Mesa's llvmpipe on a machine with
 * no GPU).  With a device index: EGL_EXT_platform_device on the N-th device
 * of EGL_EXT_device_enumeration, which is how a GPU driver (NVIDIA, Mesa
 * radeonsi/iris) is reached without a window system.
 */
#if defined(SPR_PIN_DRIVERS)
#define _GNU_SOURCE 1 /* dl_iterate_phdr, RTLD_NODELETE */
#endif
#include "gl_internal.h"

#if defined(SPR_PIN_DRIVERS)
#include <dlfcn.h>
#include <link.h>
/* Sanitizer builds: keep every library EGL loaded resident (RTLD_NODELETE),
 * so that what the driver still holds at exit is reported against its own
 * module and tools/lsan.supp can name it; after eglTerminate unloads it, the
 * frames would read "<unknown module>". */
static int pin(struct dl_phdr_info *info, size_t size, void *user)
{
    (void)size;
    (void)user;
    if (info->dlpi_name && info->dlpi_name[0]) dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
    return 0;
}
#endif

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display(void)
{
    return (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
}

/* EGL displays are per process: eglGetPlatformDisplay returns the same
 * handle to every backend on one platform/device, and eglTerminate on it
 * would end the contexts of every other backend too.  Each display is
 * terminated when the last backend that initialised it closes. */
#define GL_MAX_DISPLAYS 8
static struct { EGLDisplay dpy; int refs; } displays[GL_MAX_DISPLAYS];

static void display_ref(EGLDisplay d)
{
    int free_slot = -1;
    for (int i = 0; i < GL_MAX_DISPLAYS; i++) {
        if (displays[i].refs && displays[i].dpy == d) { displays[i].refs++; return; }
        if (!displays[i].refs && free_slot < 0) free_slot = i;
    }
    if (free_slot >= 0) { displays[free_slot].dpy = d; displays[free_slot].refs = 1; }
}

/* 1 when this was the last reference (terminate it). */
static int display_unref(EGLDisplay d)
{
    for (int i = 0; i < GL_MAX_DISPLAYS; i++)
        if (displays[i].refs && displays[i].dpy == d) return --displays[i].refs == 0;
    return 1;
}

spr_result gl__egl_open(gl_context *c, int device, spr_error *err)
{
    /* Mesa's loader warnings would add lines to our one-line errors. */
    setenv("EGL_LOG_LEVEL", "fatal", 0);
    PFNEGLGETPLATFORMDISPLAYEXTPROC gpd = get_platform_display();
    if (!gpd) return spr__fail(err, SPR_E_NO_DEVICE, "gl: EGL has no eglGetPlatformDisplayEXT (is libegl-mesa0 installed?)");
    const char *platform = getenv("EGL_PLATFORM");
    if (device < 0 && platform && *platform && strcmp(platform, "surfaceless") != 0) {
        /* The user named another platform: let EGL's default display resolve it. */
        c->dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    } else if (device < 0) {
        c->dpy = gpd(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    } else {
        PFNEGLQUERYDEVICESEXTPROC query = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
        EGLDeviceEXT devs[32];
        EGLint n = 0;
        if (!query || !query(32, devs, &n))
            return spr__fail(err, SPR_E_BACKEND, "gl: --gl-device %d: EGL_EXT_device_enumeration is not available", device);
        if (device >= n) return spr__fail(err, SPR_E_BACKEND, "gl: --gl-device %d: EGL reports %d device(s)", device, n);
        c->dpy = gpd(EGL_PLATFORM_DEVICE_EXT, devs[device], NULL);
    }
    if (c->dpy == EGL_NO_DISPLAY)
        return spr__fail(err, SPR_E_NO_DEVICE, "gl: no EGL display for the %s platform (EGL error 0x%x; is libegl-mesa0 installed?)",
                         device >= 0 ? "device" : platform && *platform ? platform : "surfaceless", (unsigned)eglGetError());
    EGLint maj, min;
    if (!eglInitialize(c->dpy, &maj, &min)) {
        c->dpy = EGL_NO_DISPLAY;
        return spr__fail(err, SPR_E_NO_DEVICE, "gl: eglInitialize failed on the %s platform (EGL error 0x%x): no usable GL driver there",
                         device >= 0 ? "device" : platform && *platform ? platform : "surfaceless", (unsigned)eglGetError());
    }
    display_ref(c->dpy);
    if (!eglBindAPI(EGL_OPENGL_API)) return spr__fail(err, SPR_E_NO_DEVICE, "gl: EGL cannot bind the OpenGL API");
    const EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLConfig cfg = EGL_NO_CONFIG_KHR;
    const char *exts = eglQueryString(c->dpy, EGL_EXTENSIONS);
    if (!exts || !strstr(exts, "EGL_KHR_no_config_context")) {
        const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLint got = 0;
        if (!eglChooseConfig(c->dpy, want, &cfg, 1, &got) || got < 1)
            return spr__fail(err, SPR_E_NO_DEVICE, "gl: no EGL config renders OpenGL");
    }
    c->ctx = eglCreateContext(c->dpy, cfg, EGL_NO_CONTEXT, attrs);
    if (c->ctx == EGL_NO_CONTEXT)
        return spr__fail(err, SPR_E_NO_DEVICE, "gl: no OpenGL 4.5 core context (EGL error 0x%x)", (unsigned)eglGetError());
    if (!eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->ctx))
        return spr__fail(err, SPR_E_NO_DEVICE, "gl: cannot make the context current without a surface (EGL error 0x%x)",
                         (unsigned)eglGetError());
#if defined(SPR_PIN_DRIVERS)
    dl_iterate_phdr(pin, NULL);
#endif
    snprintf(c->renderer, sizeof c->renderer, "%s | %s", (const char *)glGetString(GL_RENDERER),
             (const char *)glGetString(GL_VERSION));
    return SPR_OK;
}

void gl__make_current(gl_context *c)
{
    if (c->ctx != EGL_NO_CONTEXT && eglGetCurrentContext() != c->ctx) eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->ctx);
}

void gl__egl_close(gl_context *c)
{
    if (c->dpy != EGL_NO_DISPLAY) {
        if (c->ctx != EGL_NO_CONTEXT && eglGetCurrentContext() == c->ctx)
            eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (c->ctx != EGL_NO_CONTEXT) eglDestroyContext(c->dpy, c->ctx);
        if (display_unref(c->dpy)) eglTerminate(c->dpy); /* the last backend on this display */
    }
    c->dpy = EGL_NO_DISPLAY;
    c->ctx = EGL_NO_CONTEXT;
}
