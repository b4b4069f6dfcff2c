/* scenefile.c — scene files (docs/scene-format.md): `--save-scene F`
 * writes everything that determines the image as JSON, `--scene F` reads it
 * back as option values the command line did not give.
 *
 * A scene file is the command line in sections: each key of "model",
 * "camera", "render", "domain" and "grouping" is the option of that name
 * (model.path is --model), so every option an algorithm reads is stored
 * without a second table to keep in step.  The camera is written resolved
 * (after framing), as eye/target/up/fov or as the raw matrices. */
#include "spr__options.h"
#include "spr__scene_opts.h"
#include "spr_image.h"
#include "spr_version.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SCENE_VERSION 1

static const spr__opt model_rows[] = {SPR__MODEL_OPTS, {NULL, NULL, NULL}};
static const spr__opt camera_rows[] = {SPR__CAMERA_OPTS, {NULL, NULL, NULL}};
static const spr__opt algo_rows[] = {SPR__ALGO_OPTS, {NULL, NULL, NULL}};
static const spr__opt domain_rows[] = {SPR__DOMAIN_OPTS, {NULL, NULL, NULL}};
static const spr__opt group_rows[] = {{"groups", "", ""}, SPR__GROUP_OPTS, {NULL, NULL, NULL}};
static const spr__opt backend_rows[] = {SPR__BACKEND_OPTS, {NULL, NULL, NULL}};

static int in_rows(const spr__opt *rows, const char *name)
{
    for (; rows->name; rows++)
        if (!strcmp(rows->name, name)) return 1;
    return 0;
}

/* The section an option is stored in; NULL for options that do not change
 * the image (threads, quiet) or are not scene options. */
static const char *section_of(const char *name)
{
    if (!strcmp(name, "threads") || !strcmp(name, "quiet")) return NULL;
    if (!strcmp(name, "background")) return "render";
    if (in_rows(model_rows, name)) return "model";
    if (in_rows(camera_rows, name)) return "camera";
    if (in_rows(algo_rows, name)) return "render";
    if (in_rows(domain_rows, name)) return "domain";
    if (in_rows(group_rows, name)) return "grouping";
    if (in_rows(backend_rows, name)) return "backend";
    return NULL;
}

int spr__is_scene_option(const char *name) { return !strcmp(name, "scene") || section_of(name) != NULL; }

static int opt_index(const spr__args *a, const char *name)
{
    for (int k = 0; a->opts[k].name; k++)
        if (!strcmp(a->opts[k].name, name)) return k;
    return -1;
}

/* Scene values given by the command line replace these too: options that
 * choose the same thing another way.  A moved camera is framed again. */
static const char *const camera_place[] = {"eye", "target", "up", "fov", "ortho", "view-matrix", "projection-matrix", "intrinsics",
                                           "world-to-camera", "cameras", "camera", NULL};
static const struct { const char *key; const char *const by[9]; } displaced[] = {
    {"eye", {"view-matrix", "projection-matrix", "intrinsics", "world-to-camera", "cameras", "camera"}},
    {"target", {"view-matrix", "projection-matrix", "intrinsics", "world-to-camera", "cameras", "camera"}},
    {"up", {"view-matrix", "projection-matrix", "intrinsics", "world-to-camera", "cameras", "camera"}},
    {"fov", {"ortho", "view-matrix", "projection-matrix", "intrinsics", "world-to-camera", "cameras", "camera"}},
    {"ortho", {"fov", "view-matrix", "projection-matrix", "intrinsics", "world-to-camera", "cameras", "camera"}},
    {"view-matrix", {"eye", "target", "up", "fov", "ortho", "intrinsics", "world-to-camera", "cameras"}},
    {"projection-matrix", {"eye", "target", "up", "fov", "ortho", "intrinsics", "world-to-camera", "cameras"}},
    {"intrinsics", {"eye", "target", "up", "fov", "ortho", "view-matrix", "projection-matrix", "cameras"}},
    {"world-to-camera", {"eye", "target", "up", "fov", "ortho", "view-matrix", "projection-matrix", "cameras"}},
    {"cameras", {"eye", "target", "up", "fov", "ortho", "view-matrix", "projection-matrix", "intrinsics"}},
    {"camera", {"eye", "target", "up", "fov", "ortho", "view-matrix", "projection-matrix", "intrinsics"}},
    {"groups", {"groups-file"}},
    {"groups-file", {"groups"}},
};

static int given_on_command_line(const spr__args *a, const char *name)
{
    int k = opt_index(a, name);
    return k >= 0 && a->value[k] && !a->from_scene[k];
}

static int displaced_by_command_line(const spr__args *a, const char *key)
{
    if (!strcmp(key, "near") || !strcmp(key, "far"))
        for (int i = 0; camera_place[i]; i++)
            if (given_on_command_line(a, camera_place[i])) return 1;
    for (size_t i = 0; i < sizeof displaced / sizeof displaced[0]; i++)
        if (!strcmp(displaced[i].key, key))
            for (int j = 0; displaced[i].by[j]; j++)
                if (given_on_command_line(a, displaced[i].by[j])) return 1;
    return 0;
}

/* The option values a scene file gave are malloc'd strings that a->value
 * points to, owned by a->scene_text: spr__parse hands a command's to the
 * process (options.c), a library caller frees its own with spr__scene_forget(). */
void spr__scene_forget(spr__args *a)
{
    for (int k = 0; k < SPR__MAX_OPTS; k++)
        if (a->scene_text[k]) {
            if (a->value[k] == a->scene_text[k]) a->value[k] = NULL, a->from_scene[k] = 0;
            free(a->scene_text[k]);
            a->scene_text[k] = NULL;
        }
}

static char *fmt_number(double v)
{
    char *s = malloc(32);
    if (s) snprintf(s, 32, "%.17g", v);
    return s;
}

static int is_path_option(const char *name, const char *v)
{
    if (!strcmp(name, "model")) return strncmp(v, "builtin:", 8) != 0;
    if (!strcmp(name, "groups-file") || !strcmp(name, "cameras")) return 1;
    if (!strcmp(name, "env")) return strcmp(v, "sky") && strcmp(v, "checker") && strcmp(v, "none");
    return 0;
}

/* A JSON value as the option's command-line text (malloc'd), or NULL
 * after an error naming the key. */
static char *value_text(spr__args *a, const char *file, const char *sec, const char *key, const spr__opt *o, const cJSON *v)
{
    if (!o->arg) { /* a flag */
        if (cJSON_IsBool(v)) return cJSON_IsTrue(v) ? strdup("1") : NULL;
        spr__error(a, "%s: %s.%s: expected true or false", file, sec, key);
        return NULL;
    }
    if (cJSON_IsString(v)) return strdup(v->valuestring);
    if (cJSON_IsNumber(v)) return fmt_number(v->valuedouble);
    if (cJSON_IsArray(v)) {
        const int rows = !strcmp(key, "view-matrix") || !strcmp(key, "projection-matrix") ? 4 : !strcmp(key, "world-to-camera") ? 3 : 0;
        const int matrix = rows > 0;
        const int size = !strcmp(key, "size");
        double x[16];
        int n = 0, ok = 1;
        const cJSON *e;
        cJSON_ArrayForEach(e, v)
        {
            if (matrix && cJSON_IsArray(e)) {
                const cJSON *f;
                int row = 0;
                cJSON_ArrayForEach(f, e)
                {
                    if (!cJSON_IsNumber(f) || n >= 16) { ok = 0; break; }
                    x[n++] = f->valuedouble;
                    row++;
                }
                ok &= row == 4;
            } else if (cJSON_IsNumber(e) && n < 16) {
                x[n++] = e->valuedouble;
            } else {
                ok = 0;
            }
            if (!ok) break;
        }
        if (ok && size && n == 2 && x[0] == floor(x[0]) && x[1] == floor(x[1]) && fabs(x[0]) < 1e9 && fabs(x[1]) < 1e9) {
            char *s = malloc(48);
            if (s) snprintf(s, 48, "%.0fx%.0f", x[0], x[1]);
            return s;
        }
        if (ok && (matrix ? n == 4 * rows : !size && n >= 1 && n <= 4)) { /* the numbers, comma-separated, exact */
            char *s = malloc(16 * 26);
            size_t at = 0;
            for (int i = 0; s && i < n; i++) at += (size_t)snprintf(s + at, 16 * 26 - at, "%s%.17g", i ? "," : "", x[i]);
            return s;
        }
        spr__error(a, "%s: %s.%s: expected %s", file, sec, key,
                  matrix ? (rows == 4 ? "4 rows of 4 numbers" : "3 rows of 4 numbers") : size ? "[width, height]" : "a number, a string or up to 4 numbers");
        return NULL;
    }
    spr__error(a, "%s: %s.%s: expected %s", file, sec, key, "a number, a string or an array of numbers");
    return NULL;
}

/* Line and column of byte offset `at` of text. */
static void line_col(const char *text, size_t at, int *line, int *col)
{
    *line = 1, *col = 1;
    for (size_t i = 0; i < at && text[i]; i++) {
        if (text[i] == '\n') (*line)++, *col = 1;
        else (*col)++;
    }
}

int spr__scene_read(spr__args *a, const char *file)
{
    char *text = NULL;
    size_t len = 0;
    spr_error err = {0};
    snprintf(a->scene_file, sizeof a->scene_file, "%s", file);
    if (spr__read_file(file, &text, &len, &err)) { spr__error(a, "--scene: %s", err.msg); return -1; }
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    int rc = -1;
    if (!root) {
        int line, col;
        const char *at = cJSON_GetErrorPtr();
        line_col(text, at && at >= text && at <= text + len ? (size_t)(at - text) : len, &line, &col);
        spr__error(a, "%s:%d:%d: not valid JSON", file, line, col);
        goto done;
    }
    const cJSON *ver = cJSON_GetObjectItemCaseSensitive(root, "splatref_scene");
    if (!cJSON_IsObject(root) || !cJSON_IsNumber(ver)) { spr__error(a, "%s: not a splatref scene (no \"splatref_scene\": version)", file); goto done; }
    if (ver->valuedouble != SCENE_VERSION) {
        spr__error(a, "%s: scene format version %g, this splatref reads version %d", file, ver->valuedouble, SCENE_VERSION);
        goto done;
    }
    /* the scene's own folder, for relative paths */
    char dir[PATH_MAX];
    snprintf(dir, sizeof dir, "%s", file);
    char *slash = strrchr(dir, '/');
    if (slash) slash[1] = '\0';
    else dir[0] = '\0';
    static const char *const sections[] = {"model", "camera", "render", "domain", "grouping", "backend", NULL};
    const cJSON *sec;
    cJSON_ArrayForEach(sec, root)
    {
        if (!strcmp(sec->string, "splatref_scene") || !strcmp(sec->string, "generator")) continue;
        int si = 0;
        while (sections[si] && strcmp(sections[si], sec->string)) si++;
        if (!sections[si]) { spr__error(a, "%s: unknown key '%s' (sections: model, camera, render, domain, grouping, backend)", file, sec->string); goto done; }
        if (!cJSON_IsObject(sec)) { spr__error(a, "%s: '%s' must be an object", file, sec->string); goto done; }
        const cJSON *it;
        cJSON_ArrayForEach(it, sec)
        {
            const char *key = it->string;
            if (si == 0 && !strcmp(key, "fnv1a64")) {
                if (!cJSON_IsString(it) || strlen(it->valuestring) != 16) { spr__error(a, "%s: model.fnv1a64: expected 16 hex digits", file); goto done; }
                snprintf(a->scene_hash, sizeof a->scene_hash, "%s", it->valuestring);
                continue;
            }
            const char *name = si == 0 && !strcmp(key, "path") ? "model" : key;
            const char *s_of = si == 0 && !strcmp(key, "model") ? NULL : section_of(name);
            int k = opt_index(a, name);
            if (!s_of || strcmp(s_of, sections[si]) || k < 0) {
                spr__error(a, "%s: unknown key '%s.%s' (see docs/scene-format.md)", file, sections[si], key);
                goto done;
            }
            char *v = value_text(a, file, sections[si], key, &a->opts[k], it);
            if (!v) {
                if (!a->opts[k].arg && cJSON_IsFalse(it)) continue; /* a flag set false */
                goto done;
            }
            if (a->value[k] || displaced_by_command_line(a, name)) { free(v); continue; } /* the command line wins */
            if (is_path_option(name, v) && v[0] != '/' && dir[0]) {
                size_t L = strlen(dir) + strlen(v) + 1;
                char *p = malloc(L);
                if (!p) { free(v); goto done; }
                snprintf(p, L, "%s%s", dir, v);
                free(v);
                v = p;
            }
            a->value[k] = a->scene_text[k] = v;
            a->from_scene[k] = 1;
        }
    }
    /* the hash belongs to the scene's model: another --model drops it */
    int km = opt_index(a, "model");
    if (km < 0 || !a->from_scene[km]) a->scene_hash[0] = '\0';
    rc = 0;
done:
    cJSON_Delete(root);
    free(text);
    return rc;
}

int spr__scene_check_model(spr__args *a, const char *model)
{
    if (!a->scene_hash[0] || !strncmp(model, "builtin:", 8)) return 0;
    uint64_t h;
    spr_error err = {0};
    if (spr_hash_file(model, &h, &err)) { spr__error(a, "%s", err.msg); return -1; }
    char now[17];
    snprintf(now, sizeof now, "%016llx", (unsigned long long)h);
    if (strcmp(now, a->scene_hash)) {
        spr__error(a, "%s: model %s changed since the scene was saved (FNV-1a 64 %s, the file now %s); give --model to use it anyway",
                  a->scene_file, model, a->scene_hash, now);
        return -1;
    }
    return 0;
}

/* An option's text as JSON: true for flags, numbers and lists of numbers
 * as numbers, anything else a string; paths made absolute. */
static cJSON *json_of(const spr__opt *o, const char *v)
{
    if (!o->arg) return cJSON_CreateTrue();
    if (is_path_option(o->name, v)) {
        char real[PATH_MAX];
        if (realpath(v, real)) return cJSON_CreateString(real);
        return cJSON_CreateString(v);
    }
    double x[4];
    int n = 0;
    const char *p = v;
    while (n < 4 && *p) {
        char *e;
        errno = 0;
        x[n] = strtod(p, &e);
        if (e == p || errno || !isfinite(x[n])) break;
        n++;
        p = e;
        if (*p == ',') p++;
        else break;
    }
    if (*p || n == 0 || v[strlen(v) - 1] == ',') return cJSON_CreateString(v);
    if (n == 1) return cJSON_CreateNumber(x[0]);
    return cJSON_CreateDoubleArray(x, n);
}

static cJSON *add_section(cJSON *root, const char *name)
{
    cJSON *s = cJSON_GetObjectItemCaseSensitive(root, name);
    return s ? s : cJSON_AddObjectToObject(root, name);
}

static cJSON *matrix_json(const double *m, int n_rows)
{
    cJSON *rows = cJSON_CreateArray();
    for (int r = 0; rows && r < n_rows; r++) cJSON_AddItemToArray(rows, cJSON_CreateDoubleArray(m + 4 * r, 4));
    return rows;
}

int spr__scene_save(spr__args *a, const spr_scene *s, const spr_render_desc *rd, const char *path, int matrices)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "splatref_scene", SCENE_VERSION);
    cJSON_AddStringToObject(root, "generator", "splatref " SPR_VERSION_STRING);
    cJSON *model = add_section(root, "model");
    cJSON_AddItemToObject(model, "path", json_of(&(spr__opt){"model", "PATH", ""}, s->model));
    if (strncmp(s->model, "builtin:", 8)) {
        uint64_t h;
        spr_error err = {0};
        if (spr_hash_file(s->model, &h, &err)) { spr__error(a, "--save-scene: %s", err.msg); cJSON_Delete(root); return -1; }
        char hex[17];
        snprintf(hex, sizeof hex, "%016llx", (unsigned long long)h);
        cJSON_AddStringToObject(model, "fnv1a64", hex);
    }
    /* the camera as resolved by framing */
    cJSON *cam = add_section(root, "camera");
    if (matrices) {
        cJSON_AddItemToObject(cam, "view-matrix", matrix_json(s->view.V, 4));
        cJSON_AddItemToObject(cam, "projection-matrix", matrix_json(s->view.P, 4));
    } else if (s->cam.have_pinhole) { /* the pinhole as given or as read from cameras.json, resolved */
        const spr_pinhole *p = &s->cam.pinhole;
        const double k[4] = {p->fx, p->fy, p->cx, p->cy};
        double m[12];
        for (int r = 0; r < 3; r++) {
            for (int j = 0; j < 3; j++) m[4 * r + j] = p->R[3 * r + j];
            m[4 * r + 3] = p->t[r];
        }
        cJSON_AddItemToObject(cam, "intrinsics", cJSON_CreateDoubleArray(k, 4));
        cJSON_AddItemToObject(cam, "world-to-camera", matrix_json(m, 3));
    } else {
        cJSON_AddItemToObject(cam, "eye", cJSON_CreateDoubleArray(s->cam.eye, 3));
        cJSON_AddItemToObject(cam, "target", cJSON_CreateDoubleArray(s->cam.target, 3));
        cJSON_AddItemToObject(cam, "up", cJSON_CreateDoubleArray(s->cam.up, 3));
        if (s->cam.ortho_height > 0.0) cJSON_AddNumberToObject(cam, "ortho", s->cam.ortho_height);
        else cJSON_AddNumberToObject(cam, "fov", s->cam.fov_deg);
    }
    cJSON_AddNumberToObject(cam, "near", s->view.near_plane);
    cJSON_AddNumberToObject(cam, "far", s->view.far_plane);
    const double size[2] = {s->view.width, s->view.height};
    cJSON_AddItemToObject(cam, "size", cJSON_CreateDoubleArray(size, 2));
    cJSON *render = add_section(root, "render");
    if (!s->all_algos) cJSON_AddStringToObject(render, "algo", spr_algo_name(rd->algo));
    /* every other scene option the command has a value for */
    for (int k = 0; a->opts[k].name; k++) {
        const char *name = a->opts[k].name, *sec = section_of(name);
        if (!a->value[k] || !sec || !strcmp(sec, "camera") || !strcmp(name, "model") || !strcmp(name, "algo")) continue;
        /* the old name of an option is saved under its name of now */
        cJSON_AddItemToObject(add_section(root, sec), strcmp(name, "gauss-flavor") ? name : "gauss-profile", json_of(&a->opts[k], a->value[k]));
    }
    return spr__write_json(a, path, root);
}
