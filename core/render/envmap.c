/* envmap.c — environment cube maps for SPEC §6.3: built-in procedural
 * ones and six faces from image files.  Texels are computed or read here,
 * once, and given to both backends as the same float bits. */
#include "spr_envmap.h"
#include "spr_image.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Direction through the centre of texel (i, j) of face f: GL's cube map
 * table inverted (s, t in [−1, 1], t growing downwards on every face). */
static void texel_dir(int f, int i, int j, int S, double d[3])
{
    double s = 2.0 * (i + 0.5) / S - 1.0, t = 2.0 * (j + 0.5) / S - 1.0;
    switch (f) {
    case 0: d[0] = 1; d[1] = -t; d[2] = -s; break;
    case 1: d[0] = -1; d[1] = -t; d[2] = s; break;
    case 2: d[0] = s; d[1] = 1; d[2] = t; break;
    case 3: d[0] = s; d[1] = -1; d[2] = -t; break;
    case 4: d[0] = s; d[1] = -t; d[2] = 1; break;
    default: d[0] = -s; d[1] = -t; d[2] = -1; break;
    }
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) d[k] /= l;
}

/* Blue sky brightening to the horizon, a sun, a checkered ground. */
static void sky(const double d[3], double c[3])
{
    if (d[1] >= 0.0) {
        double h = pow(1.0 - d[1], 3.0);
        static const double zen[3] = {0.18, 0.36, 0.78}, hor[3] = {0.86, 0.9, 0.97};
        const double sun[3] = {0.5, 0.6, -0.62};
        double sl = sqrt(sun[0] * sun[0] + sun[1] * sun[1] + sun[2] * sun[2]);
        double cs = (d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2]) / sl;
        double glow = cs > 0.995 ? 1.0 : cs > 0.95 ? 0.35 * (cs - 0.95) / 0.045 : 0.0;
        for (int k = 0; k < 3; k++) c[k] = fmin(1.0, zen[k] + (hor[k] - zen[k]) * h + glow);
    } else {
        double u = d[0] / -d[1], v = d[2] / -d[1];
        int cell = ((int)floor(u * 2.0) + (int)floor(v * 2.0)) & 1;
        double fade = pow(1.0 + d[1], 6.0); /* towards the horizon colour */
        static const double a[3] = {0.42, 0.36, 0.3}, b[3] = {0.82, 0.78, 0.68}, hor[3] = {0.86, 0.9, 0.97};
        for (int k = 0; k < 3; k++) c[k] = (cell ? a[k] : b[k]) * (1.0 - fade) + hor[k] * fade;
    }
}

/* A checkerboard of 8×8 cells on every face, each face its own tint, so a
 * reflected or refracted ray shows which face and texel it reached. */
static void checker(int f, int i, int j, int S, double c[3])
{
    static const double tint[6][3] = {{0.9, 0.3, 0.3}, {0.3, 0.8, 0.8}, {0.35, 0.85, 0.35},
                                      {0.85, 0.35, 0.85}, {0.35, 0.45, 0.95}, {0.95, 0.85, 0.3}};
    int cell = ((i * 8 / S) + (j * 8 / S)) & 1;
    for (int k = 0; k < 3; k++) c[k] = cell ? tint[f][k] : 0.15 + 0.2 * tint[f][k];
}

spr_result spr_envmap_builtin(const char *name, int size, spr_envmap *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    int is_sky = !strcmp(name, "sky"), is_checker = !strcmp(name, "checker");
    if (!is_sky && !is_checker) return spr__fail(err, SPR_E_ARG, "environment '%s' is not sky or checker", name);
    if (size < 1 || size > 4096) return spr__fail(err, SPR_E_ARG, "environment: face size %d outside 1..4096", size);
    const size_t S = (size_t)size;
    if (!(out->texels = malloc(6 * S * S * 4 * sizeof(float)))) return spr__fail(err, SPR_E_NOMEM, "environment: out of memory");
    out->size = size;
    for (int f = 0; f < 6; f++)
        for (int j = 0; j < size; j++)
            for (int i = 0; i < size; i++) {
                double c[3], d[3];
                if (is_sky) {
                    texel_dir(f, i, j, size, d);
                    sky(d, c);
                } else {
                    checker(f, i, j, size, c);
                }
                float *t = out->texels + (((size_t)f * S + (size_t)j) * S + (size_t)i) * 4;
                for (int k = 0; k < 3; k++) t[k] = (float)c[k];
                t[3] = 1.0f;
            }
    return SPR_OK;
}

spr_result spr_envmap_load(const char *dir, spr_envmap *out, spr_error *err)
{
    static const char *const face[6] = {"px", "nx", "py", "ny", "pz", "nz"};
    memset(out, 0, sizeof *out);
    for (int f = 0; f < 6; f++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s.png", dir, face[f]);
        float *im;
        int w, h, ch;
        spr_result r = spr_read_image(path, &im, &w, &h, &ch, err);
        if (r) { spr_envmap_free(out); return r; }
        if (w != h || (f > 0 && w != out->size)) {
            free(im);
            spr__fail(err, SPR_E_FORMAT, "%s: face is %dx%d; the six faces must be square and of one size%s", path, w, h,
                      f > 0 ? " as px.png" : "");
            spr_envmap_free(out);
            return SPR_E_FORMAT;
        }
        if (f == 0) {
            out->size = w;
            if (!(out->texels = malloc(6 * (size_t)w * w * 4 * sizeof(float)))) {
                free(im);
                return spr__fail(err, SPR_E_NOMEM, "environment: out of memory");
            }
        }
        for (int j = 0; j < w; j++) /* face rows from the top: image row h−1−j */
            for (int i = 0; i < w; i++) {
                const float *src = im + ((size_t)(h - 1 - j) * w + i) * ch;
                float *t = out->texels + (((size_t)f * w + (size_t)j) * w + (size_t)i) * 4;
                for (int k = 0; k < 3; k++) t[k] = src[k];
                t[3] = 1.0f;
            }
        free(im);
    }
    return SPR_OK;
}

void spr_envmap_free(spr_envmap *e)
{
    free(e->texels);
    memset(e, 0, sizeof *e);
}
