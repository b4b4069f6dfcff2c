/* spr_io.h — reading and writing splat clouds (SPEC §1).
 *
 * spr_load() accepts PLY (ascii, binary little/big endian), OFF meshes,
 * XYZ/PWN point files and the built-in models "builtin:NAME".  Missing
 * normals come from mesh faces (area-weighted) or from PCA of the k nearest
 * neighbours oriented away from the bounding-box centre; missing radii are
 * ρ·d_k (distance to the k-th neighbour); missing colours are 0.5·n + 0.5.
 * Every failure is one line naming the file and the line or byte offset;
 * nothing is partially returned.
 */
#ifndef SPR_IO_H
#define SPR_IO_H

#include <math.h>
#include <stdio.h>
#include "spr_camera.h"
#include "spr_cloud.h"
#include "spr_knn.h"
#include "spr_result.h"
#include "spr_util.h"

typedef struct spr_load_desc {
    size_t points;       /* size of built-in models (0 = 20000) */
    int radius_k;        /* k of the radius rule (0 = 8) */
    double radius_rho;   /* ρ of the radius rule (0 = 1.0) */
    int normal_k;        /* k of PCA normals (0 = 10) */
    int threads;         /* for neighbour searches (0 = all cores) */
    double opacity;      /* > 0: every loaded splat's α (before balls are added) */
    int balls;           /* > 0: add this many small opaque balls inside the model (SPEC 6) */
    spr_progress progress;
    spr_warn warn;       /* deviations accepted (a header line outside the grammar, all-zero normals) */
    double gauss_cut;    /* Gaussian-splat files: the surfel's edge in standard deviations, in (0, 3] (0 = 3) */
    int sh_degree;       /* Gaussian-splat files: spherical-harmonics degree kept for view-dependent colour, 0..3 */
    const char *columns; /* text point files without a header: column names "x,y,z,…" (NULL: 3 or 6 columns) */
    int spz_raw;         /* .spz: 1 takes the data in the frame it is stored in (--spz-frame raw: splat-transform 3.x
                          * writes the PLY frame unconverted); 0 turns the format's RUB frame into the training frame */
} spr_load_desc;
void spr_load_defaults(spr_load_desc *d);

/* Load `path` into c (allocated here; free with spr_cloud_free). */
spr_result spr_load(const char *path, const spr_load_desc *d, spr_cloud *c, spr_error *err);

/* Write a binary little-endian PLY (x y z nx ny nz float, red green blue
 * alpha uchar, radius float) through a temporary file renamed into place. */
spr_result spr_write_ply(const char *path, const spr_cloud *c, spr_error *err);

/* A Gaussian capture as the training code's PLY stores it (3DGS layout): per
 * Gaussian the centre (3), SH coefficients sh_k × rgb, coefficient-major (DC
 * first), the logit of the opacity, log σ (3) and the rotation w x y z (4,
 * any length).  spr_write_gauss_ply writes it through a temporary file; a
 * load gives back σ = exp(log σ), α = sigmoid(logit) and the normalised
 * rotation, the same bits each time. */
typedef struct spr_gauss_file {
    size_t n;
    const float *pos, *sh, *opacity_logit, *log_scale, *rot;
    int sh_k;        /* 1 (DC) … 16 (degree 3) */
} spr_gauss_file;
spr_result spr_write_gauss_ply(const char *path, const spr_gauss_file *g, spr_error *err);
/* Cloud c as a capture in that layout, SH degree 3: each splat a flat Gaussian, σ = r/3 along its axes and
 * r/300 across, opacity its α (at most 0.999), DC its colour; the higher coefficients 0, or (seed ≠ 0) drawn
 * in ±0.2 from that seed, so that view-dependent colour has work to do. */
spr_result spr_write_gauss_ply_of_cloud(const char *path, const spr_cloud *c, uint64_t seed, spr_error *err);

/* A binary PLY opened for reading in chunks of `chunk` splats (0: 2^20)
 * instead of whole (`render --stream`, clouds larger than memory): only the
 * header is read here.  The file must be binary, with fixed-size records up
 * to its vertex element, and carry normals and radii (computing them needs
 * every point's neighbours); each chunk reads as spr_load reads it (same
 * decoding, colours by normal when absent, d->opacity).  Close with
 * spr_ply_source_close; src->bounds are set by spr_cloud_source_scan. */
spr_result spr_ply_source_open(const char *path, const spr_load_desc *d, size_t chunk, spr_cloud_source *src, spr_error *err);
void spr_ply_source_close(spr_cloud_source *src);

/* Resample a mesh (OFF or PLY with faces) to n points: triangles chosen by
 * area, uniform barycentrics, face normals, colours by normal, radii by the
 * radius rule; fixed seed, so the same call gives the same cloud. */
spr_result spr_sample_mesh(const char *path, size_t n, uint64_t seed, const spr_load_desc *d, spr_cloud *c,
                           spr_error *err);

/* Names of the built-in models, NULL-terminated. */
extern const char *const spr_builtin_names[];

/* ---- internal, shared by the loaders ---- */
typedef struct spr__mesh {
    size_t nv, nt;
    uint32_t *tri;  /* 3·nt vertex indices (polygons fanned) */
    size_t cap;     /* triangles tri has room for */
} spr__mesh;
void spr__mesh_free(spr__mesh *m);
/* Append the polygon idx[0 … k) (k ≥ 3) as the fan idx[0], idx[j+1], idx[j+2];
 * tri grows geometrically (a realloc per face copies the whole list each time
 * under an allocator that cannot grow in place).  -1: out of memory. */
int spr__mesh_fan(spr__mesh *m, const uint32_t *idx, int k);
spr_result spr__read_file(const char *path, char **buf, size_t *len, spr_error *err);
/* The same for the readers of spr_load, without the copy: a regular file of
 * SPR__MAP_MIN bytes or more is mapped read-only (the readers never read
 * past len; a file truncated while it is read is the caller's error), a
 * smaller one read.  Release with spr__unmap_file(buf, len, mapped). */
#define SPR__MAP_MIN ((size_t)16 << 20)
spr_result spr__map_file(const char *path, char **buf, size_t *len, int *mapped, spr_error *err);
void spr__unmap_file(char *buf, size_t len, int mapped);
/* Text files hold no NUL byte: SPR_E_FORMAT naming the first one in buf[from, len). */
spr_result spr__check_text(const char *path, const char *buf, size_t from, size_t len, spr_error *err);
/* 1 when v is finite as a float too (1e300 is a finite double but not a float). */
static inline int spr__finite_float(double v) { return isfinite(v) && isfinite((float)v); }
/* The readers, over the file's bytes in memory (`path` only names it in
 * messages): spr_load and spr_sample_mesh read the file once and call them,
 * the fuzz harnesses of tests/fuzz/ drive them directly. */
/* (prog: NULL, or progress every 2^20 vertices; warn: NULL, or the
 * deviations accepted: header lines outside the grammar skipped, normals
 * that are all zero read as none) */

/* Gaussian splats (io_gauss.c): one Gaussian as the readers decode it, and
 * the one mapping to an elliptical surfel (docs/formats.md). */
typedef struct spr__gauss_opts {
    double cut;      /* radii = cut × σ */
    int sh_degree;   /* SH coefficients kept: (degree + 1)², capped by the file's */
    int spz_raw;     /* .spz data taken as stored, not turned from the format's RUB frame (--spz-frame raw) */
} spr__gauss_opts;
void spr__gauss_defaults(spr__gauss_opts *o);
typedef struct spr__gauss {
    double pos[3];
    double sigma[3]; /* σ along the local axes, linear (after exp); sigma[2] < 0: a 2D Gaussian */
    double q[4];     /* rotation w x y z, any non-zero length (normalised here) */
    double rgb[3];   /* colour, clamped to [0,1] here */
    double alpha;    /* opacity in [0,1] (after the sigmoid) */
} spr__gauss;
/* c with ellipses (and sh when o asks for more than degree 0 and the file
 * has file_k > 1 coefficients per channel) for n Gaussians. */
spr_result spr__gauss_alloc(spr_cloud *c, size_t n, int file_k, const spr__gauss_opts *o, const char *path, spr_error *err);
/* Splat s of c from g: the surfel spans the two largest axes (largest = u),
 * n = u × v along the smallest, r_u = cut·σ_u, r_v = cut·σ_v. */
spr_result spr__gauss_put(const spr__gauss *g, const spr__gauss_opts *o, spr_cloud *c, size_t s, const char *path, size_t index,
                          spr_error *err);
/* Splats 0 … c->n − 1 of c (from spr__gauss_alloc) from a reader's decoder,
 * in parallel: decode(user, i, g, sh) gives Gaussian i and, when sh is not
 * NULL, its c->sh_k × 3 coefficients; each is mapped by spr__gauss_put.  On
 * a bad splat: the lowest one's message (any thread count), c freed. */
typedef void (*spr__gauss_decode)(const void *user, size_t i, spr__gauss *g, float *sh);
spr_result spr__gauss_fill(spr_cloud *c, const spr__gauss_opts *o, spr__gauss_decode decode, const void *user, const char *path,
                           spr_error *err);
double spr__sigmoid(double x);
/* The SH degree-0 constant: colour = 0.5 + C0·f_dc (every capture format). */
#define SPR__SH_C0 0.28209479177387814
spr_result spr__parse_ply(const char *path, const char *buf, size_t len, spr_cloud *c, spr__mesh *mesh, const spr_progress *prog,
                          const spr_warn *warn, const spr__gauss_opts *go, spr_error *err);
/* The same with binary fixed-size vertex records decoded `block` at a time (0: SPR__PLY_BLOCK), each
 * block into its view of the cloud (spr_cloud_view): a test crosses many block boundaries with a small file. */
#define SPR__PLY_BLOCK ((size_t)1 << 20)
spr_result spr__parse_ply_blocks(const char *path, const char *buf, size_t len, spr_cloud *c, spr__mesh *mesh, const spr_progress *prog,
                                 const spr_warn *warn, const spr__gauss_opts *go, size_t block, spr_error *err);
/* cameras.json over its bytes (spr_cameras_json reads the file and calls it; the fuzz harness drives it). */
spr_result spr__parse_cameras_json(const char *path, const char *text, size_t len, long id, spr_pinhole *p, int *width, int *height,
                                   spr_error *err);
spr_result spr__parse_cameras_json_all(const char *path, const char *text, size_t len, spr_camera_entry **out, size_t *count, spr_error *err);
spr_result spr__parse_splat(const char *path, const char *buf, size_t len, const spr__gauss_opts *o, spr_cloud *c, spr_error *err);
spr_result spr__parse_spz(const char *path, const char *buf, size_t len, const spr__gauss_opts *o, spr_cloud *c, spr_error *err);
spr_result spr__parse_glb(const char *path, const char *buf, size_t len, const spr__gauss_opts *o, spr_cloud *c, spr_error *err);
/* PlayCanvas SOG version 2 (io_sog.c): a .sog zip over its bytes, or the folder form from its meta.json's bytes
 * (the images read beside path). */
spr_result spr__parse_sog(const char *path, const char *buf, size_t len, const spr__gauss_opts *o, spr_cloud *c, spr_error *err);
spr_result spr__parse_sog_folder(const char *path, const char *buf, size_t len, const spr__gauss_opts *o, spr_cloud *c, spr_error *err);
/* The same over files in memory (the fuzz harness: a SOG's own files, mutated, without its zip). */
typedef struct spr__sog_file { const char *name; const unsigned char *data; size_t len; } spr__sog_file;
spr_result spr__parse_sog_files(const char *path, const spr__sog_file *files, size_t n, const spr__gauss_opts *o, spr_cloud *c, spr_error *err);
spr_result spr__parse_off(const char *path, const char *buf, size_t len, spr_cloud *c, spr__mesh *mesh, spr_error *err);
/* Point files by column name (docs/formats.md): a header line (`//X Y Z
 * R G B … Nx Ny Nz`, `# x y z nx ny nz`, CSV `x,y,z,…`) names the columns,
 * case-insensitive, unknown ones skipped; separators space, tab, comma,
 * semicolon; columns (--columns, NULL: none) names them for a file without
 * a header; otherwise 3 (x y z) or 6 (x y z nx ny nz) columns. */
spr_result spr__parse_xyz(const char *path, const char *buf, size_t len, const char *columns, spr_cloud *c, spr_error *err);
spr_result spr__builtin(const char *name, size_t n, spr_cloud *c, spr_error *err);
/* Append n small opaque balls inside the closed model c (builtin.c). */
spr_result spr__add_balls(spr_cloud *c, int n, spr_error *err);
/* Area-weighted face normals; returns the count of vertices left without one. */
size_t spr__mesh_normals(const spr__mesh *m, spr_cloud *c);
/* PCA normals (k neighbours) for splats whose normal is zero (all when `all`). */
spr_result spr__pca_normals(spr_cloud *c, int k, int all, int threads, const spr_progress *prog, spr_error *err);
/* r_i = ρ·d_k(i). */
spr_result spr__knn_radii(spr_cloud *c, int k, double rho, int threads, const spr_progress *prog, spr_error *err);

#endif
