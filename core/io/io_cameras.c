/* io_cameras.c — the training code's cameras.json (SPEC §10.8): one entry
 * per training image, written by graphdeco-inria/gaussian-splatting
 * (utils/camera_utils.py, camera_to_JSON): id, img_name, width, height,
 * position (the camera centre), rotation (camera-to-world, three rows of
 * three), fy, fx.  The principal point is the image centre (the training
 * code's projection matrix is symmetric).  Parsed with cJSON. */
#include "spr_camera.h"
#include "spr_io.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int number_of(const cJSON *e, const char *key, double *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(e, key);
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble)) return 0;
    *out = v->valuedouble;
    return 1;
}

/* Line of byte offset `at`, for a parse error. */
static int line_of(const char *text, size_t at)
{
    int line = 1;
    for (size_t i = 0; i < at; i++) line += text[i] == '\n';
    return line;
}

static spr_result entry_camera(const char *path, const cJSON *e, long id, spr_pinhole *p, int *width, int *height, spr_error *err)
{
    double w, h, fx, fy;
    if (!number_of(e, "width", &w) || !number_of(e, "height", &h) || w != floor(w) || h != floor(h) || w < 1 || h < 1 ||
        w > SPR_MAX_IMAGE_SIDE || h > SPR_MAX_IMAGE_SIDE)
        return spr__fail(err, SPR_E_FORMAT, "%s: camera %ld: width and height must be whole numbers in 1..%d", path, id, SPR_MAX_IMAGE_SIDE);
    if (!number_of(e, "fx", &fx) || !number_of(e, "fy", &fy))
        return spr__fail(err, SPR_E_FORMAT, "%s: camera %ld: no numeric fx and fy", path, id);
    if (!(fx > 0.0) || !(fy > 0.0))
        return spr__fail(err, SPR_E_ARG, "%s: camera %ld: focal lengths fx %g, fy %g must be positive (pixels)", path, id, fx, fy);
    const cJSON *pos = cJSON_GetObjectItemCaseSensitive(e, "position"), *rot = cJSON_GetObjectItemCaseSensitive(e, "rotation");
    double c[3], C2W[9];
    if (cJSON_GetArraySize(pos) != 3) return spr__fail(err, SPR_E_FORMAT, "%s: camera %ld: \"position\" is not three numbers", path, id);
    for (int k = 0; k < 3; k++) {
        const cJSON *v = cJSON_GetArrayItem(pos, k);
        if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
            return spr__fail(err, SPR_E_FORMAT, "%s: camera %ld: \"position\" is not three numbers", path, id);
        c[k] = v->valuedouble;
    }
    if (cJSON_GetArraySize(rot) != 3) return spr__fail(err, SPR_E_FORMAT, "%s: camera %ld: \"rotation\" is not three rows of three numbers", path, id);
    for (int r = 0; r < 3; r++) {
        const cJSON *row = cJSON_GetArrayItem(rot, r);
        if (cJSON_GetArraySize(row) != 3)
            return spr__fail(err, SPR_E_FORMAT, "%s: camera %ld: \"rotation\" is not three rows of three numbers", path, id);
        for (int k = 0; k < 3; k++) {
            const cJSON *v = cJSON_GetArrayItem(row, k);
            if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
                return spr__fail(err, SPR_E_FORMAT, "%s: camera %ld: \"rotation\" is not three rows of three numbers", path, id);
            C2W[3 * r + k] = v->valuedouble;
        }
    }
    /* world-to-camera: R = C2Wᵀ, t = −R·position */
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) p->R[3 * r + k] = C2W[3 * k + r];
    for (int r = 0; r < 3; r++) p->t[r] = -(p->R[3 * r] * c[0] + p->R[3 * r + 1] * c[1] + p->R[3 * r + 2] * c[2]);
    p->fx = fx, p->fy = fy, p->cx = 0.5 * w, p->cy = 0.5 * h;
    *width = (int)w, *height = (int)h;
    char what[1100];
    snprintf(what, sizeof what, "%s: camera %ld", path, id);
    return spr_pinhole_check(p, what, err);
}

spr_result spr_cameras_json(const char *path, long id, spr_pinhole *p, int *width, int *height, spr_error *err)
{
    char *text = NULL;
    size_t len = 0;
    spr_result r = spr__read_file(path, &text, &len, err);
    if (r) return r;
    r = spr__parse_cameras_json(path, text, len, id, p, width, height, err);
    free(text);
    return r;
}

/* The array of entries, or a one-line error naming the file (and the line, for JSON that does not parse). */
static spr_result parse_root(const char *path, const char *text, size_t len, cJSON **root, spr_error *err)
{
    const char *end = NULL;
    *root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    if (!*root) {
        const char *at = cJSON_GetErrorPtr();
        size_t off = at && at >= text && at <= text + len ? (size_t)(at - text) : len;
        return spr__fail(err, SPR_E_FORMAT, "%s:%d: not valid JSON (byte %zu)", path, line_of(text, off), off);
    }
    if (!cJSON_IsArray(*root)) {
        cJSON_Delete(*root);
        *root = NULL;
        return spr__fail(err, SPR_E_FORMAT, "%s: not a cameras.json (an array of camera entries)", path);
    }
    return SPR_OK;
}

/* The whole-number "id" of entry n. */
static spr_result entry_id(const char *path, const cJSON *e, long n, long *id, spr_error *err)
{
    double v;
    if (!cJSON_IsObject(e) || !number_of(e, "id", &v) || v != floor(v) || fabs(v) > 2e9)
        return spr__fail(err, SPR_E_FORMAT, "%s: entry %ld has no whole-number \"id\"", path, n);
    *id = (long)v;
    return SPR_OK;
}

spr_result spr__parse_cameras_json(const char *path, const char *text, size_t len, long id, spr_pinhole *p, int *width, int *height,
                                   spr_error *err)
{
    cJSON *root;
    spr_result r = parse_root(path, text, len, &root, err);
    if (r) return r;
    long lo = 0, hi = -1, n = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, root)
    {
        long eid;
        if ((r = entry_id(path, e, n, &eid, err))) goto done;
        if (n == 0 || eid < lo) lo = eid;
        if (n == 0 || eid > hi) hi = eid;
        n++;
        if (eid == id) {
            r = entry_camera(path, e, id, p, width, height, err);
            goto done;
        }
    }
    r = n ? spr__fail(err, SPR_E_ARG, "%s: no camera with id %ld (%ld entries, ids %ld … %ld)", path, id, n, lo, hi)
          : spr__fail(err, SPR_E_FORMAT, "%s: no camera entries", path);
done:
    cJSON_Delete(root);
    return r;
}

spr_result spr__parse_cameras_json_all(const char *path, const char *text, size_t len, spr_camera_entry **out, size_t *count, spr_error *err)
{
    *out = NULL, *count = 0;
    cJSON *root;
    spr_result r = parse_root(path, text, len, &root, err);
    if (r) return r;
    const size_t n = (size_t)cJSON_GetArraySize(root);
    spr_camera_entry *v = n ? calloc(n, sizeof *v) : NULL;
    if (!n) r = spr__fail(err, SPR_E_FORMAT, "%s: no camera entries", path);
    else if (!v) r = spr__fail(err, SPR_E_NOMEM, "%s: out of memory for %zu camera entries", path, n);
    size_t k = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, root)
    {
        if (r) break;
        spr_camera_entry *c = &v[k];
        if ((r = entry_id(path, e, (long)k, &c->id, err))) break;
        for (size_t j = 0; j < k; j++)
            if (v[j].id == c->id) {
                r = spr__fail(err, SPR_E_FORMAT, "%s: entries %zu and %zu both have id %ld", path, j, k, c->id);
                break;
            }
        if (r || (r = entry_camera(path, e, c->id, &c->pinhole, &c->width, &c->height, err))) break;
        const cJSON *name = cJSON_GetObjectItemCaseSensitive(e, "img_name");
        size_t ctl = 0; /* the first control character of the name (at its end: none) */
        while (cJSON_IsString(name) && name->valuestring[ctl] && (unsigned char)name->valuestring[ctl] >= 0x20 && name->valuestring[ctl] != 0x7f) ctl++;
        if (name && !cJSON_IsString(name))
            r = spr__fail(err, SPR_E_FORMAT, "%s: camera %ld: \"img_name\" is not a string", path, c->id);
        else if (name && strlen(name->valuestring) >= sizeof c->img_name)
            r = spr__fail(err, SPR_E_FORMAT, "%s: camera %ld: \"img_name\" is longer than %zu bytes", path, c->id, sizeof c->img_name - 1);
        else if (name && name->valuestring[ctl]) /* it is shown in check's one line a view, and names a file */
            r = spr__fail(err, SPR_E_FORMAT, "%s: camera %ld: \"img_name\" holds the control character 0x%02x at byte %zu", path, c->id,
                          (unsigned)(unsigned char)name->valuestring[ctl], ctl);
        else if (name)
            memcpy(c->img_name, name->valuestring, strlen(name->valuestring) + 1);
        k++;
    }
    cJSON_Delete(root);
    if (r) { free(v); return r; }
    *out = v, *count = n;
    return SPR_OK;
}

spr_result spr_cameras_json_all(const char *path, spr_camera_entry **out, size_t *count, spr_error *err)
{
    char *text = NULL;
    size_t len = 0;
    *out = NULL, *count = 0;
    spr_result r = spr__read_file(path, &text, &len, err);
    if (r) return r;
    r = spr__parse_cameras_json_all(path, text, len, out, count, err);
    free(text);
    return r;
}
