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
 * terminated when the last backend that initialised it closes.  A display
 * runs one driver from eglInitialize to eglTerminate: the table keeps how
 * its GL_RENDERER begins, so a backend asking for another driver while it
 * is open is refused instead of silently given this one. */
#define GL_MAX_DISPLAYS 8
static struct { EGLDisplay dpy; int refs; char renderer[64]; } displays[GL_MAX_DISPLAYS];

static int display_slot(EGLDisplay d)
{
    for (int i = 0; i < GL_MAX_DISPLAYS; i++)
        if (displays[i].refs && displays[i].dpy == d) return i;
    return -1;
}

static void display_ref(EGLDisplay d)
{
    int i = display_slot(d);
    if (i >= 0) { displays[i].refs++; return; }
    for (i = 0; i < GL_MAX_DISPLAYS; i++)
        if (!displays[i].refs) { displays[i].dpy = d, displays[i].refs = 1, displays[i].renderer[0] = '\0'; return; }
}

/* 1 when this was the last reference (terminate it). */
static int display_unref(EGLDisplay d)
{
    const int i = display_slot(d);
    return i < 0 || --displays[i].refs == 0;
}

static const struct { const char *name, *gallium, *renderer, *package; } drivers[SPR_GL_DRIVER__COUNT] = {
#define GL__DRV(e, name, gallium, renderer, package) {name, gallium, renderer, package},
    SPR_GL_DRIVER_LIST(GL__DRV)
#undef GL__DRV
};

const char *spr_gl_driver_name(spr_gl_driver d) { return (unsigned)d < SPR_GL_DRIVER__COUNT ? drivers[d].name : NULL; }

int spr_gl_driver_parse(const char *name, spr_gl_driver *out)
{
    for (int d = 0; name && d < SPR_GL_DRIVER__COUNT; d++)
        if (!strcmp(name, drivers[d].name)) { *out = (spr_gl_driver)d; return 0; }
    return -1;
}

spr_result spr_gl_desc_check(const spr_gl_desc *d, spr_error *err)
{
    if ((unsigned)d->driver >= SPR_GL_DRIVER__COUNT)
        return spr__fail(err, SPR_E_ARG, "gl: driver %d is not one of %s", (int)d->driver, spr_gl_driver_names());
    if (d->driver != SPR_GL_DRIVER_DEFAULT && d->device >= 0)
        return spr__fail(err, SPR_E_ARG, "gl: --gl-driver %s runs on the surfaceless platform, not on --gl-device %d (an EGL device brings its own driver)",
                         drivers[d->driver].name, d->device);
    return SPR_OK;
}

/* 1 when a GL_RENDERER string is the driver's (NULL: the default, any). */
static int renderer_is(const char *renderer, spr_gl_driver d)
{
    const char *want = drivers[d].renderer;
    return !want || (renderer && !strncmp(renderer, want, strlen(want)));
}

/* "; is Debian's PACKAGE installed?" for a driver that needs one, else "". */
static const char *package_hint(spr_gl_driver d, char *buf, size_t cap)
{
    if (!drivers[d].package) return "";
    snprintf(buf, cap, "; is Debian's %s installed?", drivers[d].package);
    return buf;
}

const char *spr_gl_driver_names(void)
{
#define GL__NAME(e, name, gallium, renderer, package) " | " name
    static const char all[] = SPR_GL_DRIVER_LIST(GL__NAME);
#undef GL__NAME
    return all + 3;
}

/* Mesa's environment for `driver` while the display initialises (the
 * loader reads it then), then the caller's own again, so a later backend
 * asking for the default gets what the user set.  Zink: Mesa's Vulkan
 * device-selection layer is skipped (NODEVICE_SELECT, its manifest's switch)
 * unless the user set it: it only orders GPUs, and looking for a Wayland
 * compositor it prints "XDG_RUNTIME_DIR is invalid" on a machine without one. */
#define GL_ENV_VARS 3
typedef struct gl_env { const char *name[GL_ENV_VARS]; char *saved[GL_ENV_VARS]; int n; } gl_env;

static void env_set(gl_env *e, const char *name, const char *value, int overwrite)
{
    const char *old = getenv(name);
    if (!overwrite && old) return;
    e->name[e->n] = name;
    e->saved[e->n] = old ? strdup(old) : NULL;
    e->n++;
    setenv(name, value, 1);
}

static void env_driver(gl_env *e, spr_gl_driver driver)
{
    memset(e, 0, sizeof *e);
    if (driver != SPR_GL_DRIVER_DEFAULT) {
        env_set(e, "LIBGL_ALWAYS_SOFTWARE", "1", 1);
        env_set(e, "GALLIUM_DRIVER", drivers[driver].gallium, 1);
    }
    const char *g = getenv("GALLIUM_DRIVER");
    if (g && !strcmp(g, "zink")) env_set(e, "NODEVICE_SELECT", "1", 0);
}

static void env_restore(gl_env *e)
{
    for (int i = e->n - 1; i >= 0; i--) {
        if (e->saved[i]) setenv(e->name[i], e->saved[i], 1);
        else unsetenv(e->name[i]);
        free(e->saved[i]);
    }
    e->n = 0;
}

spr_result gl__egl_open(gl_context *c, const spr_gl_desc *d, spr_error *err)
{
    if (spr_gl_desc_check(d, err)) return err->code;
    const int device = d->device;
    const spr_gl_driver driver = d->driver;
    const int named = driver != SPR_GL_DRIVER_DEFAULT; /* a driver asked for by name */
    char hint[96];
    /* Mesa's loader warnings would add lines to our one-line errors. */
    setenv("EGL_LOG_LEVEL", "fatal", 0);
    PFNEGLGETPLATFORMDISPLAYEXTPROC gpd = get_platform_display();
    if (!gpd) return spr__fail(err, SPR_E_NO_DEVICE, "gl: EGL has no eglGetPlatformDisplayEXT (is libegl-mesa0 installed?)");
    const char *platform = getenv("EGL_PLATFORM");
    if (device < 0 && !named && platform && *platform && strcmp(platform, "surfaceless") != 0) {
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
    const int open = display_slot(c->dpy);
    if (named && open >= 0 && !renderer_is(displays[open].renderer, driver)) {
        c->dpy = EGL_NO_DISPLAY;
        return spr__fail(err, SPR_E_ARG, "gl: --gl-driver %s: this process already has a GL backend open on %s; EGL runs one driver a display, so close that one first",
                         drivers[driver].name, displays[open].renderer);
    }
    gl_env env;
    env_driver(&env, open >= 0 ? SPR_GL_DRIVER_DEFAULT : driver);
    EGLint maj, min;
    const EGLBoolean inited = eglInitialize(c->dpy, &maj, &min);
    env_restore(&env);
    if (!inited) {
        c->dpy = EGL_NO_DISPLAY;
        if (named)
            return spr__fail(err, SPR_E_NO_DEVICE, "gl: --gl-driver %s: eglInitialize failed on the surfaceless platform (EGL error 0x%x)%s",
                             drivers[driver].name, (unsigned)eglGetError(), package_hint(driver, hint, sizeof hint));
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
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    snprintf(c->renderer, sizeof c->renderer, "%s | %s", renderer ? renderer : "?", (const char *)glGetString(GL_VERSION));
    const int slot = display_slot(c->dpy);
    if (slot >= 0 && !displays[slot].renderer[0]) snprintf(displays[slot].renderer, sizeof displays[slot].renderer, "%s", renderer ? renderer : "?");
    if (!renderer_is(renderer, driver))
        return spr__fail(err, SPR_E_NO_DEVICE, "gl: --gl-driver %s: EGL gave the driver '%s'%s", drivers[driver].name, renderer ? renderer : "?",
                         package_hint(driver, hint, sizeof hint));
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
