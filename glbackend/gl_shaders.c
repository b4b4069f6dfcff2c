/* gl_shaders.c — GLSL sources of the GL backend, built from C at run time.
 *
 * The splat fragment shader is core/spr_fragment.h written again in GLSL,
 * operation for operation: explicit parenthesised sums, `precise` on every
 * arithmetic variable, no dot/length/normalize/mix/fma, no transcendental,
 * per-splat data as flat varyings and the pixel from gl_FragCoord (exactly
 * x + 0.5).  Shared numbers (gauss coefficients, enum values) are emitted
 * from their C definitions as exact bit patterns (uintBitsToFloat), so no
 * decimal round trip is involved.
 */
#include "gl_internal.h"
#include "spr_kernel.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *vs_splat =
    "#version 450 core\n"
    "layout(location = 0) in ivec4 i_rect;   /* x0 y0 x1 y1, inclusive pixels */\n"
    "layout(location = 1) in vec4 i_pr;      /* centre, radius */\n"
    "layout(location = 2) in vec4 i_na;      /* normal, opacity */\n"
    "layout(location = 3) in vec4 i_c;       /* colour */\n"
    "layout(location = 4) in uint i_id;\n"
    "uniform vec2 u_size;\n"
    "flat out vec4 v_pr; flat out vec4 v_na; flat out vec4 v_c; flat out uint v_id;\n"
    "void main() {\n"
    "    /* a quad on pixel boundaries: its edges lie half a pixel from any\n"
    "       sampled centre, so rounding here cannot change coverage */\n"
    "    float x = float((gl_VertexID & 1) != 0 ? i_rect.z + 1 : i_rect.x);\n"
    "    float y = float((gl_VertexID & 2) != 0 ? i_rect.w + 1 : i_rect.y);\n"
    "    gl_Position = vec4(x / u_size.x * 2.0 - 1.0, y / u_size.y * 2.0 - 1.0, 0.0, 1.0);\n"
    "    v_pr = i_pr; v_na = i_na; v_c = i_c; v_id = i_id;\n"
    "}\n";

/* %s: defines; the body mirrors spr_pixel_ray, spr_ray_disk, spr_kernel_weight,
 * spr_test_value of core/spr_fragment.h and core/spr_kernel.h. */
static const char *fs_splat_body =
    "flat in vec4 v_pr; flat in vec4 v_na; flat in vec4 v_c; flat in uint v_id;\n"
    "uniform float u_M[16];\n"
    "uniform float u_sx, u_sy, u_eps, u_dmin, u_dmax, u_n, u_invn;\n"
    "uniform int u_kernel, u_depth, u_output, u_cull;\n"
    "layout(binding = 0, offset = 0) uniform atomic_uint u_generated;\n"
    "layout(location = 0) out vec4 o_color;\n"
    "layout(location = 1) out float o_depth;\n"
    "layout(location = 2) out uint o_id;\n"
    "layout(location = 3) out float o_count;\n"
    "void main() {\n"
    "    precise float nx = gl_FragCoord.x * u_sx - 1.0;\n"
    "    precise float ny = gl_FragCoord.y * u_sy - 1.0;\n"
    "    /* unproject(ndc, -1) and unproject(ndc, +1) */\n"
    "    precise float ax = ((u_M[0] * nx + u_M[1] * ny) + u_M[2] * -1.0) + u_M[3];\n"
    "    precise float ay = ((u_M[4] * nx + u_M[5] * ny) + u_M[6] * -1.0) + u_M[7];\n"
    "    precise float az = ((u_M[8] * nx + u_M[9] * ny) + u_M[10] * -1.0) + u_M[11];\n"
    "    precise float aw = ((u_M[12] * nx + u_M[13] * ny) + u_M[14] * -1.0) + u_M[15];\n"
    "    precise float bx = ((u_M[0] * nx + u_M[1] * ny) + u_M[2] * 1.0) + u_M[3];\n"
    "    precise float by = ((u_M[4] * nx + u_M[5] * ny) + u_M[6] * 1.0) + u_M[7];\n"
    "    precise float bz = ((u_M[8] * nx + u_M[9] * ny) + u_M[10] * 1.0) + u_M[11];\n"
    "    precise float bw = ((u_M[12] * nx + u_M[13] * ny) + u_M[14] * 1.0) + u_M[15];\n"
    "    precise float o0x = ax / aw, o0y = ay / aw, o0z = az / aw;\n"
    "    precise float dx = bx / bw - o0x, dy = by / bw - o0y, dz = bz / bw - o0z;\n"
    "    /* ray-disk intersection */\n"
    "    precise float den = (dx * v_na.x + dy * v_na.y) + dz * v_na.z;\n"
    "    if (den == 0.0) discard;\n"
    "    precise float a0 = v_pr.x - o0x, a1 = v_pr.y - o0y, a2 = v_pr.z - o0z;\n"
    "    precise float num = (a0 * v_na.x + a1 * v_na.y) + a2 * v_na.z;\n"
    "    precise float t = num / den;\n"
    "    if (!(t >= 0.0 && t <= 1.0)) discard;\n"
    "    precise float q0 = (o0x + t * dx) - v_pr.x;\n"
    "    precise float q1 = (o0y + t * dy) - v_pr.y;\n"
    "    precise float q2 = (o0z + t * dz) - v_pr.z;\n"
    "    precise float qq = (q0 * q0 + q1 * q1) + q2 * q2;\n"
    "    precise float rho2 = qq / (v_pr.w * v_pr.w);\n"
    "    if (!(rho2 <= 1.0)) discard;\n"
    "    if (u_cull != 0 && den > 0.0) discard;\n"
    "    atomicCounterIncrement(u_generated);\n"
    "    precise float rho = sqrt(rho2);\n"
    "    /* test value (SPEC 3.3), clamped to the depth range */\n"
    "    precise float z;\n"
    "    if (u_depth == SPR_DEPTH_EPS_OFFSET) {\n"
    "        z = t + u_eps;\n"
    "    } else if (u_depth == SPR_DEPTH_LOWRES || u_depth == SPR_DEPTH_VORONOI) {\n"
    "        precise float zl = floor(((t - u_dmin) / (u_dmax - u_dmin)) * u_n) * u_invn;\n"
    "        z = u_depth == SPR_DEPTH_VORONOI ? zl + rho * u_invn : zl;\n"
    "    } else {\n"
    "        z = t;\n"
    "    }\n"
    "    if (z < 0.0) z = 0.0;\n"
    "    if (z > 1.0) z = 1.0;\n"
    "    gl_FragDepth = z;\n"
    "    if (u_output == SPR_OUT_ALPHA) {\n"
    "        o_color = vec4(v_c.x, v_c.y, v_c.z, v_na.w);\n"
    "    } else {\n"
    "        precise float w;\n"
    "        if (u_kernel == SPR_KERNEL_CONSTANT) {\n"
    "            w = 1.0;\n"
    "        } else if (u_kernel == SPR_KERNEL_LINEAR) {\n"
    "            w = 1.0 - rho;\n"
    "        } else if (u_kernel == SPR_KERNEL_EPANECHNIKOV) {\n"
    "            w = 1.0 - rho2;\n"
    "        } else {\n"
    "            precise float v = rho2 * 2.0 - 1.0;\n"
    "            precise float acc = SPR_GAUSS[0];\n"
    "            for (int i = 1; i <= SPR_GAUSS_DEGREE; i++) acc = acc * v + SPR_GAUSS[i];\n"
    "            w = acc;\n"
    "        }\n"
    "        precise float wr = w * v_c.x, wg = w * v_c.y, wb = w * v_c.z;\n"
    "        o_color = vec4(wr, wg, wb, w);\n"
    "    }\n"
    "    o_depth = t;\n"
    "    o_id = v_id;\n"
    "    o_count = 1.0;\n"
    "}\n";

static const char *vs_full =
    "#version 450 core\n"
    "void main() {\n"
    "    vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID & 2) * 2 - 1));\n"
    "    gl_Position = vec4(p, 0.0, 1.0);\n"
    "}\n";

/* Mirrors swrast/sw_composite.c. */
static const char *fs_comp_body =
    "uniform sampler2DArray u_col;\n"
    "uniform sampler2DArray u_dep;\n"
    "uniform int u_K, u_op;\n"
    "uniform float u_eps;\n"
    "uniform vec3 u_bg;\n"
    "layout(location = 0) out vec4 o_color;\n"
    "layout(location = 1) out float o_depth;\n"
    "void main() {\n"
    "    ivec2 p = ivec2(gl_FragCoord.xy);\n"
    "    precise vec4 acc = vec4(0.0);\n"
    "    precise float d = texelFetch(u_dep, ivec3(p, 0), 0).r;\n"
    "    if (u_op == SPR_COMP_NORMALIZE) {\n"
    "        acc = texelFetch(u_col, ivec3(p, 0), 0);\n"
    "    } else {\n"
    "        for (int k = 1; k < u_K; k++) {\n"
    "            float dk = texelFetch(u_dep, ivec3(p, k), 0).r;\n"
    "            if (dk < d) d = dk;\n"
    "        }\n"
    "        precise float limit = d + u_eps;\n"
    "        for (int k = 0; k < u_K; k++) {\n"
    "            float dk = texelFetch(u_dep, ivec3(p, k), 0).r;\n"
    "            if (!(dk <= limit)) continue;\n"
    "            vec4 c = texelFetch(u_col, ivec3(p, k), 0);\n"
    "            acc.x = acc.x + c.x; acc.y = acc.y + c.y; acc.z = acc.z + c.z; acc.w = acc.w + c.w;\n"
    "        }\n"
    "    }\n"
    "    if (acc.w > 0.0) {\n"
    "        precise float r = acc.x / acc.w, g = acc.y / acc.w, b = acc.z / acc.w;\n"
    "        o_color = vec4(r, g, b, 1.0);\n"
    "    } else {\n"
    "        o_color = vec4(u_bg, 0.0);\n"
    "    }\n"
    "    o_depth = d;\n"
    "    gl_FragDepth = d;\n"
    "}\n";

/* "#version", then every shared constant from its C definition. */
static char *with_prelude(const char *body)
{
    size_t cap = strlen(body) + 4096;
    char *s = malloc(cap);
    if (!s) return NULL;
    int o = snprintf(s, cap,
                     "#version 450 core\n"
                     "#define SPR_KERNEL_GAUSS %d\n#define SPR_KERNEL_CONSTANT %d\n#define SPR_KERNEL_LINEAR %d\n"
                     "#define SPR_KERNEL_EPANECHNIKOV %d\n#define SPR_DEPTH_PLAIN %d\n#define SPR_DEPTH_EPS_OFFSET %d\n"
                     "#define SPR_DEPTH_LOWRES %d\n#define SPR_DEPTH_VORONOI %d\n#define SPR_OUT_WEIGHTED %d\n"
                     "#define SPR_OUT_ALPHA %d\n#define SPR_COMP_NORMALIZE %d\n#define SPR_COMP_DEFERRED %d\n"
                     "#define SPR_GAUSS_DEGREE %d\nconst float SPR_GAUSS[%d] = float[](",
                     SPR_KERNEL_GAUSS, SPR_KERNEL_CONSTANT, SPR_KERNEL_LINEAR, SPR_KERNEL_EPANECHNIKOV, SPR_DEPTH_PLAIN,
                     SPR_DEPTH_EPS_OFFSET, SPR_DEPTH_LOWRES, SPR_DEPTH_VORONOI, SPR_OUT_WEIGHTED, SPR_OUT_ALPHA,
                     SPR_COMP_NORMALIZE, SPR_COMP_DEFERRED, SPR_GAUSS_DEGREE, SPR_GAUSS_DEGREE + 1);
    for (int i = 0; i <= SPR_GAUSS_DEGREE; i++) {
        uint32_t u;
        memcpy(&u, &spr_gauss_coef[i], 4);
        o += snprintf(s + o, cap - (size_t)o, "%suintBitsToFloat(0x%08xu)", i ? ", " : "", u);
    }
    snprintf(s + o, cap - (size_t)o, ");\n%s", body);
    return s;
}

static GLuint compile(GLenum type, const char *src, const char *name, spr_error *err)
{
    GLuint sh = glCreateShader(type);
    glShaderSource(sh, 1, &src, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        for (char *p = log; *p; p++)
            if (*p == '\n') *p = ' ';
        spr__fail(err, SPR_E_BACKEND, "gl: shader %s does not compile: %s", name, log);
        glDeleteShader(sh);
        return 0;
    }
    return sh;
}

static GLuint link(const char *vs, const char *fs, const char *name, spr_error *err)
{
    GLuint v = compile(GL_VERTEX_SHADER, vs, name, err), f = v ? compile(GL_FRAGMENT_SHADER, fs, name, err) : 0;
    if (!v || !f) {
        glDeleteShader(v);
        return 0;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        spr__fail(err, SPR_E_BACKEND, "gl: program %s does not link: %s", name, log);
        glDeleteProgram(p);
        return 0;
    }
    return p;
}

spr_result gl__build_programs(gl_context *c, spr_error *err)
{
    char *fs = with_prelude(fs_splat_body), *fc = with_prelude(fs_comp_body);
    if (!fs || !fc) {
        free(fs);
        free(fc);
        return spr__fail(err, SPR_E_NOMEM, "gl: out of memory");
    }
    c->prog_splat = link(vs_splat, fs, "splat", err);
    c->prog_comp = c->prog_splat ? link(vs_full, fc, "composite", err) : 0;
    free(fs);
    free(fc);
    return c->prog_splat && c->prog_comp ? SPR_OK : err->code;
}
