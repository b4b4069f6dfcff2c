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
 * the mean over pixels and channels of |C − target| or (C − target)², target W·H·3 (row 0 the bottom): ∂L/∂C =
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

#endif
