/* spr_grad.h — the backward pass of gauss3d (SPEC 10.10; docs/gradients.md):
 * a Gaussian frame's gradients, per Gaussian, given the upstream gradient of
 * a loss.  The arrays are gsplat's names and shapes (spr_gauss_grads_arrays
 * lists them for the .npz writer, check --grads and Python).
 */
#ifndef SPR_GRAD_H
#define SPR_GRAD_H

#include <stddef.h>
#include <stdint.h>
#include "spr_algo.h"

typedef enum spr_loss { SPR_LOSS_GIVEN = 0, SPR_LOSS_L1, SPR_LOSS_L2 } spr_loss;

/* The upstream gradient.  loss GIVEN: dl_dimage, W·H·3 floats ∂L/∂C (row 0 the bottom, as images in memory); L1, L2:
 * the mean over pixels and channels of |C − target| or (C − target)², target W·H·3 (row 0 the bottom; NULL: black): ∂L/∂C =
 * sign(C − target)/(3WH) or 2(C − target)/(3WH), in double, rounded once.  dl_dalpha, dl_ddepth: W·H (or NULL):
 * ∂L/∂A for the alpha 1 − T_f and ∂L/∂D for the inverse depth.  batch: list entries a backend holds at once (0: its
 * own). */
typedef struct spr_grad_desc {
    spr_loss loss;
    const float *target;
    const float *dl_dimage;
    const float *dl_dalpha, *dl_ddepth;
    size_t batch;
} spr_grad_desc;

/* Per Gaussian (n, culled ones zero): means 3, quats 4 (the unit quaternion as loaded, the tangent part), scales 3
 * (linear σ), opacities 1 (o in [0, 1]), sh 3 per coefficient (sh_k of them: sh0 then shN), means2d 2 (pixels),
 * conics 3, colors 3 (after SH), absgrad 2, counts 1 (pixels that blended it); the forward's image (W·H·4, row 0 the
 * bottom) and the loss (0 for a given gradient: L = Σ ∂L/∂C·C is not what a trainer computes, so it is not made up). */
typedef struct spr_gauss_grads {
    size_t n;
    int sh_k;
    int width, height;
    float *means, *quats, *scales, *opacities, *sh, *means2d, *conics, *colors, *absgrad;
    int32_t *counts;
    float *image;
    double loss;
    double ms_forward, ms_backward;
} spr_gauss_grads;

/* The gradients of desc's gauss3d frame of cloud through view on backend b: the forward frame (preprocess, sort,
 * raster, as spr_render), then the backward pass (the backend's, SPEC 10.10) and the colour's, on the host. */
spr_result spr_gauss_grad(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc, const spr_grad_desc *gd,
                          spr_gauss_grads *out, spr_error *err);
void spr_gauss_grads_free(spr_gauss_grads *g);

/* The output arrays by gsplat's names, in SPEC 10.10's order: name, values per Gaussian (sh0: 3; shN: 3·(sh_k − 1)),
 * its array in g (NULL for counts, which are int32: g->counts). */
typedef struct spr_grad_array { const char *name; int per; float *data; } spr_grad_array;
int spr_gauss_grads_arrays(const spr_gauss_grads *g, spr_grad_array *a, int cap);

/* explain --gaussian G --grad: every pixel that gave Gaussian G a gradient, in the order the backward sums them
 * (tiles in tile order; in a tile its pixels row-major from the top row), with the chain-rule terms of its step:
 * α, T (the forward's), T_f, the colour and 1/t.z behind (acc, inria's recurrence), ∂L/∂α, ∂L/∂o and ∂L/∂power
 * (gated: the profile's cap gate zeroed both), and the terms the pixel added to G's list entry (SPR_GPART_*). */
typedef struct spr_grad_term {
    int x, y, tile;       /* y from the bottom */
    int rank, blended;    /* G's place among the pixel's blended Gaussians (0: the front), how many it blended */
    float power, alpha, T, Tf, acc[4], dl_dalpha, dl_do, dl_dpower;
    int gated;
    float part[SPR_GPART_FLOATS];
} spr_grad_term;
/* A tile of G's: its list entry, its pixels terms[first … first + count), their partial (summed in that order). */
typedef struct spr_grad_tile {
    int tile;
    uint32_t entry;
    size_t first, count;
    float part[SPR_GPART_FLOATS];
} spr_grad_tile;
typedef struct spr_grad_explain {
    size_t G;
    int width, height;
    spr_grad_term *terms;
    size_t n_terms;
    spr_grad_tile *tiles;
    size_t n_tiles;
    float sum[SPR_GPART_FLOATS]; /* the tiles' partials summed in tile order: G's means2d, conics, colors, opacities, absgrad, counts */
    int consistent;               /* every pixel's recomputed ∂L/∂o equals the term the shared arithmetic added (a self-check) */
} spr_grad_explain;
/* G's terms and sums, from the same frame and arithmetic as spr_gauss_grad (the CPU backend: b must be swrast's,
 * whose backward adds in this order; the float environment is the backend's, flush-to-zero). */
spr_result spr_gauss_grad_explain(spr_backend *b, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *desc,
                                  const spr_grad_desc *gd, size_t G, spr_grad_explain *out, spr_error *err);
void spr_grad_explain_free(spr_grad_explain *x);

/* Two backends' gradients of one frame compared bit for bit, array by array (parity): per array the Gaussians whose
 * values differ in any bit, the first of them and its first values on each side.  Returns the arrays compared. */
typedef struct spr_grad_diff {
    const char *name;
    size_t gaussians, differing;
    long first;
    float va[4], vb[4];
} spr_grad_diff;
int spr_gauss_grad_compare(const spr_gauss_grads *a, const spr_gauss_grads *b, spr_grad_diff *d, int cap);

/* The CPU backend's float environment (swrast's: flush-to-zero, denormals-are-zero) for host code that retraces the
 * backward's arithmetic (explain, step): enter returns what leave restores. */
unsigned spr__grad_fp_enter(void);
void spr__grad_fp_leave(unsigned old);

#endif
