/* zink-counter-repro.c — the smallest GL program that shows the Mesa 22.3.6
 * zink bug behind splatref's lost fragment counts and parity --random's
 * crash on zink (docs/parity-gpu.md; the workaround: glbackend/gl_buffers.c).
 *
 * A fragment shader counts its fragments into a one-word buffer; before each
 * draw the word is set to 0, after it the word is read (with the barrier GL
 * asks for: glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT)).  Every draw
 * covers the W×H framebuffer, so every read must give W·H.  Each round
 * zeroes and draws twice, the second time while the first draw may still be
 * queued, which is when a driver may give the buffer new storage.
 *
 * Variants (argument 1):
 *   atomic        an atomic counter (atomic_uint), the shader also reads one
 *                 shader storage block, zeroed by glBufferSubData
 *   atomic-alone  the same without the storage block
 *   storage       the counter is a storage-block word (atomicAdd), zeroed
 *                 by glBufferSubData
 *   clear         the atomic counter with the storage block, zeroed by
 *                 glClearBufferSubData
 * Argument 2: rounds (default 40).  Exit status 1 when a read is wrong.
 *
 * Measured on Debian 12 (Mesa 22.3.6), LIBGL_ALWAYS_SOFTWARE=1
 * GALLIUM_DRIVER=zink: "atomic" reads 0 in every round, the three others
 * W·H every time; on llvmpipe all four do.  Under valgrind, "atomic" also
 * shows lavapipe reading a freed block (the old storage's VkBuffer).
 * Cause: zink_set_shader_buffers records a buffer's slot at the call's loop
 * index, not start_slot + index, and Mesa binds a lowered atomic counter at
 * slot (the program's storage blocks + its binding); invalidating the busy
 * buffer then rebinds through the wrong slot.  Fixed upstream in Mesa 23.1
 * (commit 5149b2a93865, "zink: unbind the ssbo slot being iterated, not the
 * index of the buffer").
 *
 * Build: cmake --build build --target zink_counter_repro, or
 *   cc -o zink-counter-repro tools/zink-counter-repro.c -lEGL -lOpenGL
 */
#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *vs = "#version 450 core\n"
                        "void main() { gl_Position = vec4((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0, 0.0, 1.0); }\n";
static const char *fs_atomic = "#version 450 core\n"
                               "layout(std430, binding = 0) readonly buffer B { float b[]; };\n"
                               "layout(binding = 0, offset = 0) uniform atomic_uint n;\n"
                               "out vec4 o;\n"
                               "void main() { atomicCounterIncrement(n); o = vec4(b[0]); }\n";
static const char *fs_alone = "#version 450 core\n"
                              "layout(binding = 0, offset = 0) uniform atomic_uint n;\n"
                              "out vec4 o;\n"
                              "void main() { atomicCounterIncrement(n); o = vec4(1.0); }\n";
static const char *fs_storage = "#version 450 core\n"
                                "layout(std430, binding = 0) readonly buffer B { float b[]; };\n"
                                "layout(std430, binding = 1) buffer N { uint n; };\n"
                                "out vec4 o;\n"
                                "void main() { atomicAdd(n, 1u); o = vec4(b[0]); }\n";

static GLuint shader(GLenum type, const char *src)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "zink-counter-repro: shader: %s\n", log);
        exit(2);
    }
    return s;
}

int main(int argc, char **argv)
{
    const char *variant = argc > 1 ? argv[1] : "atomic";
    const int rounds = argc > 2 ? atoi(argv[2]) : 40;
    const int storage = !strcmp(variant, "storage"), alone = !strcmp(variant, "atomic-alone"), clear = !strcmp(variant, "clear");
    if (!storage && !alone && !clear && strcmp(variant, "atomic")) {
        fprintf(stderr, "zink-counter-repro: variant '%s' is not atomic, atomic-alone, storage or clear\n", variant);
        return 2;
    }
    PFNEGLGETPLATFORMDISPLAYEXTPROC gpd = (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    EGLDisplay dpy = gpd ? gpd(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL) : EGL_NO_DISPLAY;
    const EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext ctx = EGL_NO_CONTEXT;
    if (dpy != EGL_NO_DISPLAY && eglInitialize(dpy, NULL, NULL) && eglBindAPI(EGL_OPENGL_API))
        ctx = eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attrs);
    if (ctx == EGL_NO_CONTEXT || !eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        fprintf(stderr, "zink-counter-repro: no GL 4.5 core context on the surfaceless platform\n");
        return 77;
    }
    printf("%s | %s: variant %s\n", (const char *)glGetString(GL_RENDERER), (const char *)glGetString(GL_VERSION), variant);

    enum { W = 64, H = 64 };
    GLuint color, fbo, vao, counter, block;
    glCreateTextures(GL_TEXTURE_2D, 1, &color);
    glTextureStorage2D(color, 1, GL_RGBA32F, W, H);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, color, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, W, H);
    glCreateVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const float one = 1.0f;
    glCreateBuffers(1, &block);
    glNamedBufferData(block, sizeof one, &one, GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, block);
    glCreateBuffers(1, &counter);
    glNamedBufferData(counter, sizeof(GLuint), NULL, GL_DYNAMIC_DRAW);
    if (storage) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, counter);
    else glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, counter);
    GLuint prog = glCreateProgram();
    glAttachShader(prog, shader(GL_VERTEX_SHADER, vs));
    glAttachShader(prog, shader(GL_FRAGMENT_SHADER, storage ? fs_storage : alone ? fs_alone : fs_atomic));
    glLinkProgram(prog);
    glUseProgram(prog);

    int wrong = 0, first_wrong = -1;
    for (int r = 0; r < rounds; r++)
        for (int twice = 0; twice < 2; twice++) {
            const GLuint zero = 0;
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT); /* the last draw's writes before this write */
            if (clear) glClearNamedBufferSubData(counter, GL_R32UI, 0, sizeof zero, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
            else glNamedBufferSubData(counter, 0, sizeof zero, &zero);
            glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
            if (!twice) continue; /* the second zero lands while this draw may be queued */
            GLuint n = 0;
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
            glGetNamedBufferSubData(counter, 0, sizeof n, &n);
            if (n != W * H) {
                if (first_wrong < 0) first_wrong = r, printf("round %d: counter %u, expected %d\n", r + 1, n, W * H);
                wrong++;
            }
        }
    if (wrong) printf("%s: %d of %d rounds read a wrong count, the first round %d\n", variant, wrong, rounds, first_wrong + 1);
    else printf("%s: all %d rounds read %d\n", variant, rounds, W * H);
    glDeleteProgram(prog);
    GLuint bufs[2] = {counter, block};
    glDeleteBuffers(2, bufs);
    glDeleteVertexArrays(1, &vao);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &color);
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy, ctx);
    eglTerminate(dpy);
    return wrong != 0;
}
