/* fuzz_readers.c — libFuzzer harnesses for the file readers (issue 9).
 *
 * One source, one harness per reader, chosen at compile time with
 * -DSPR_FUZZ_PLY / _OFF / _XYZ / _GROUPS / _SPLAT / _SPZ / _GLB / _CAMERAS (issue 15:
 * the Gaussian-splat readers) / _SOG (issue 36: PlayCanvas SOG, zipped or its files) / _IMAGE (issue 25: the PNG and PFM readers of check;
 * the Gaussian-splat readers; their first input byte picks the options) / _SCENE (issue 25:
 * scene files, read and checked) / _NPY (issue 43: NumPy .npy and .npz).  The readers run over the input
 * as it is, in memory (spr__parse_*; the groups reader through a memfd):
 * any crash, leak, hang or out-of-memory libFuzzer or the sanitizers find
 * is a bug, and every such input goes into corpus/<reader>/ as a
 * regression file.  A failure must come back as one line naming the file.
 */
#define _GNU_SOURCE
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#include "spr_group.h"
#include "spr_image.h"
#include "spr_io.h"
#include "spr_npy.h"
#ifdef SPR_FUZZ_SCENE
#include <errno.h>
#include <sys/stat.h>
#include "spr__options.h"
#include "spr__scene_opts.h"
#endif

static void check_message(spr_result r, const spr_error *err, const char *name)
{
    if (!r) return;
    /* one line, naming the input */
    if (!strstr(err->msg, name) || strchr(err->msg, '\n')) {
        fprintf(stderr, "bad error message for %s: [%s]\n", name, err->msg);
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    spr_error err = {0};
    spr_cloud c;
#if defined(SPR_FUZZ_PLY) || defined(SPR_FUZZ_OFF)
    spr__mesh mesh;
#if defined(SPR_FUZZ_PLY)
    const spr__gauss_opts go = {3.0, (int)(size % 4)}; /* Gaussian PLYs: every SH degree, chosen by the length */
    spr_result r = spr__parse_ply("fuzz.ply", (const char *)data, size, &c, &mesh, NULL, NULL, &go, &err);
    check_message(r, &err, "fuzz.ply");
#else
    spr_result r = spr__parse_off("fuzz.off", (const char *)data, size, &c, &mesh, &err);
    check_message(r, &err, "fuzz.off");
#endif
    if (!r) {
        spr__mesh_free(&mesh);
        spr_cloud_free(&c);
    }
#elif defined(SPR_FUZZ_SPLAT) || defined(SPR_FUZZ_SPZ) || defined(SPR_FUZZ_GLB)
    /* Gaussian-splat captures; the first byte chooses the options (SH degree 0..3, cut 1 or 3) */
    if (size < 1) return 0;
    spr__gauss_opts go = {(data[0] & 4) ? 1.0 : 3.0, data[0] & 3};
#if defined(SPR_FUZZ_SPLAT)
    const char *name = "fuzz.splat";
    spr_result r = spr__parse_splat(name, (const char *)data + 1, size - 1, &go, &c, &err);
#elif defined(SPR_FUZZ_SPZ)
    const char *name = "fuzz.spz";
    spr_result r = spr__parse_spz(name, (const char *)data + 1, size - 1, &go, &c, &err);
#else
    const char *name = "fuzz.glb";
    spr_result r = spr__parse_glb(name, (const char *)data + 1, size - 1, &go, &c, &err);
#endif
    check_message(r, &err, name);
    if (!r) {
        if (spr_cloud_validate(&c, name, &err)) { /* what a reader accepts holds every invariant */
            fprintf(stderr, "accepted an invalid cloud: %s\n", err.msg);
            abort();
        }
        spr_cloud_free(&c);
    }
#elif defined(SPR_FUZZ_CAMERAS)
    /* the training code's cameras.json; the first byte: the id asked for (0..255) */
    if (size < 1) return 0;
    spr_pinhole p;
    int w, h;
    spr_result r = spr__parse_cameras_json("fuzz.json", (const char *)data + 1, size - 1, data[0], &p, &w, &h, &err);
    check_message(r, &err, "fuzz.json");
    if (!r && (w < 1 || h < 1 || spr_pinhole_check(&p, "fuzz.json", &err))) abort(); /* an accepted camera is a camera */
    /* every entry (check --camera all): all of them cameras, ids distinct, names terminated */
    spr_camera_entry *v = NULL;
    size_t n = 0;
    memset(&err, 0, sizeof err);
    r = spr__parse_cameras_json_all("fuzz.json", (const char *)data + 1, size - 1, &v, &n, &err);
    check_message(r, &err, "fuzz.json");
    if (!r && (!v || !n)) abort();
    for (size_t k = 0; !r && k < n; k++) {
        if (v[k].width < 1 || v[k].height < 1 || spr_pinhole_check(&v[k].pinhole, "fuzz.json", &err) ||
            !memchr(v[k].img_name, 0, sizeof v[k].img_name))
            abort();
        for (size_t j = 0; j < k; j++)
            if (v[j].id == v[k].id) abort();
    }
    free(v);
    (void)c;
#elif defined(SPR_FUZZ_SOG)
    /* PlayCanvas SOG: the first byte picks the form and the SH degree kept (bits 1–2).  Even: the rest is a .sog
     * (a zip); odd: the rest holds the SOG's files themselves, each as a name length (1 byte), the name, a data
     * length (4 bytes, little endian) and the data, so that mutations reach meta.json and the WebP images (inside
     * the zip, their CRCs would refuse almost every one first) */
    if (size < 1) return 0;
    const spr__gauss_opts go = {3.0, (data[0] >> 1) & 3, 0};
    spr_result r;
    if (!(data[0] & 1)) {
        r = spr__parse_sog("fuzz.sog", (const char *)data + 1, size - 1, &go, &c, &err);
    } else {
        spr__sog_file f[16];
        char names[16][256];
        size_t n = 0, at = 1;
        while (n < 16 && at < size) {
            const size_t nl = data[at++];
            if (at + nl + 4 > size) break;
            memcpy(names[n], data + at, nl);
            names[n][nl] = '\0';
            at += nl;
            size_t dl = (size_t)data[at] | (size_t)data[at + 1] << 8 | (size_t)data[at + 2] << 16 | (size_t)data[at + 3] << 24;
            at += 4;
            if (dl > size - at) dl = size - at;
            f[n] = (spr__sog_file){names[n], data + at, dl};
            at += dl, n++;
        }
        r = spr__parse_sog_files("fuzz.sog", f, n, &go, &c, &err);
    }
    check_message(r, &err, "fuzz.sog");
    if (!r) {
        if (!c.n || !c.gauss || !c.sh) abort();
        for (size_t i = 0; i < c.n; i++)
            if (!(c.alpha[i] >= 0.0f && c.alpha[i] <= 1.0f) || !(c.radius[i] > 0.0f)) abort(); /* an accepted Gaussian is a Gaussian */
        spr_cloud_free(&c);
    }
#elif defined(SPR_FUZZ_NPY)
    /* NumPy arrays: the first byte's bit 0 picks a lone .npy (0) or an .npz (1), the rest is the file.  An accepted
     * array holds spr_npy.h's invariants and every value is read (ASan sees the whole allocation). */
    if (size < 1) return 0;
    spr_npy one, *v = &one;
    int n = 1;
    const char *name = data[0] & 1 ? "fuzz.npz" : "fuzz.npy";
    spr_result r = data[0] & 1 ? spr__parse_npz(name, data + 1, size - 1, &v, &n, &err) : spr__parse_npy(name, data + 1, size - 1, NULL, &one, &err);
    check_message(r, &err, name);
    if (r && (data[0] & 1) && (v || n)) abort(); /* nothing handed out on failure */
    if (r && !(data[0] & 1) && one.data) abort();
    for (int k = 0; !r && k < n; k++) {
        const spr_npy *a = &v[k];
        if (a->ndim < 0 || a->ndim > SPR_NPY_MAX_DIMS || (a->type != SPR_NPY_F4 && a->type != SPR_NPY_I4) || !a->data ||
            spr_npy_count(a) > SPR_NPY_MAX_ELEMS || !memchr(a->name, 0, sizeof a->name) || ((data[0] & 1) ? !a->name[0] : a->name[0] != 0))
            abort();
        for (int j = 0; j < k; j++)
            if (!strcmp(v[j].name, a->name)) abort(); /* npz members are distinct */
        volatile uint32_t sum = 0;
        for (size_t i = 0; i < spr_npy_count(a); i++) sum += ((const uint32_t *)a->data)[i];
    }
    if (!r) {
        if (data[0] & 1) spr_npz_free(v, n);
        else spr_npy_free(&one);
    }
    (void)c;
#elif defined(SPR_FUZZ_XYZ)
    spr_result r = spr__parse_xyz("fuzz.xyz", (const char *)data, size, NULL, &c, &err);
    check_message(r, &err, "fuzz.xyz");
    if (!r) spr_cloud_free(&c);
#elif defined(SPR_FUZZ_GROUPS)
    /* first byte: how many splats the groups are for (1..64); the rest is the file */
    if (size < 1) return 0;
    size_t n = 1 + data[0] % 64;
    int fd = memfd_create("groups", 0);
    if (fd < 0) return 0;
    if (write(fd, data + 1, size - 1) != (ssize_t)(size - 1)) { close(fd); return 0; }
    char path[64];
    snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    spr_groups g;
    int32_t label[64];
    spr_result r = spr_groups_read_any(path, n, &g, label, &err);
    check_message(r, &err, path);
    if (!r) {
        for (size_t i = 0; i < n; i++)
            if (label[i] < 0 || label[i] >= g.K) abort(); /* every splat in a group of range */
        spr_groups_free(&g);
    }
    close(fd);
#elif defined(SPR_FUZZ_IMAGE)
    /* what users hand to `check` (issue 25): the first byte picks PNG (even) or PFM (odd), the rest is the file,
     * written to tmpfs under a name with that extension (the reader goes by it) */
    if (size < 1) return 0;
    static char path[96];
    if (!path[0]) snprintf(path, sizeof path, "/dev/shm/splatref-fuzz-%ld", (long)getpid());
    char file[128];
    snprintf(file, sizeof file, "%s.%s", path, data[0] & 1 ? "pfm" : "png");
    FILE *f = fopen(file, "wb");
    if (!f) return 0;
    const int ok = fwrite(data + 1, 1, size - 1, f) == size - 1;
    fclose(f);
    if (!ok) { remove(file); return 0; }
    float *img = NULL;
    int w, h, ch, bits;
    spr_result r = spr_read_image_bits(file, &img, &w, &h, &ch, &bits, &err);
    check_message(r, &err, file);
    if (!r) {
        /* an accepted image is one: a size, 1..4 channels, 8, 16 or 32 bits, every value readable */
        if (w < 1 || h < 1 || ch < 1 || ch > 4 || (bits != 8 && bits != 16 && bits != 32)) abort();
        volatile float sum = 0.0f;
        for (size_t i = 0; i < (size_t)w * h * ch; i++) sum += img[i];
        free(img);
    }
    remove(file);
    (void)c;
#elif defined(SPR_FUZZ_SCENE)
    /* scene files (issue 25): the input is the file, read and every option in it checked as spr_scene_load does
     * before any work (spr__scene_read, spr__scene_opts; nothing is loaded).  It lies in a folder of its own on
     * tmpfs, beside a cameras.json (tests/fuzz/scene-cameras.json), so relative paths resolve there; an accepted camera is then
     * framed on a unit box and made into a view (or refused in one line). */
    static char dir[96], file[128];
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "/dev/shm/splatref-fuzz-scene-%ld", (long)getpid());
        snprintf(file, sizeof file, "%s/scene.json", dir);
        char cams[160], *text = NULL;
        size_t len = 0;
        snprintf(cams, sizeof cams, "%s/cameras.json", dir);
        if ((mkdir(dir, 0700) && errno != EEXIST) || spr__read_file(SPR_FUZZ_CAMERAS_JSON, &text, &len, &err)) abort();
        FILE *f = fopen(cams, "wb");
        if (!f || fwrite(text, 1, len, f) != len || fclose(f)) abort();
        free(text);
    }
    FILE *f = fopen(file, "wb");
    if (!f) return 0;
    const int ok = fwrite(data, 1, size, f) == size;
    if (fclose(f) || !ok) return 0;
    static const spr__opt opts[] = {SPR__SCENE_OPTS, {NULL, NULL, NULL}};
    spr__args a;
    memset(&a, 0, sizeof a);
    a.cmd = "scene";
    a.opts = opts;
    a.sink = &err;
    for (int k = 0; opts[k].name; k++) {
        if (!strcmp(opts[k].name, "quiet")) a.value[k] = "1";
        if (!strcmp(opts[k].name, "threads")) a.value[k] = "1";
    }
    spr_scene s;
    spr_render_desc rd;
    spr__scene_plan plan;
    memset(&s, 0, sizeof s);
    spr_result r = spr__scene_read(&a, file) || spr__scene_opts(&a, &s, &rd, &plan, (int)(size & 1)) ? SPR_E_ARG : SPR_OK;
    check_message(r, &err, file); /* every option came from the file: the error names it */
    if (!r) {
        const spr_bounds unit = {{-1, -1, -1}, {1, 1, 1}, 0.1, 0.05, 0.01};
        spr_view v;
        spr_camera_frame(&s.cam, &unit);
        memset(&err, 0, sizeof err);
        if (spr_view_make(&s.cam, &v, &err) && (!err.msg[0] || strchr(err.msg, '\n'))) abort();
    }
    spr__scene_forget(&a); /* the option phase holds nothing else */
    (void)c;
#else
#error "define one of SPR_FUZZ_PLY, SPR_FUZZ_OFF, SPR_FUZZ_XYZ, SPR_FUZZ_GROUPS, SPR_FUZZ_SPLAT, SPR_FUZZ_SPZ, SPR_FUZZ_GLB, SPR_FUZZ_SOG, SPR_FUZZ_CAMERAS, SPR_FUZZ_IMAGE, SPR_FUZZ_SCENE, SPR_FUZZ_NPY"
#endif
    return 0;
}
