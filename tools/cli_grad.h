/* cli_grad.h — the gradients' pieces of the command line (cli_grad.c): the
 * upstream gradient's options (grad, check --grads, parity) and the arrays
 * as .npz members. */
#ifndef CLI_GRAD_H
#define CLI_GRAD_H
#include "cli.h"
#include "spr_grad.h"
#include "spr_npy.h"

#define CLI_GRAD_OPTS \
    {"loss", "l1|l2", "the loss whose gradient to take: the mean over pixels and channels of |C - target| or (C - target)^2, as trainers compute it; with --target"}, \
    {"target", "IMG", "--loss: the target image (PNG or PFM, the scene's size)"}, \
    {"dl-dimage", "G.npy|G.pfm", "the upstream gradient dL/dimage instead of a loss: float32 [H, W, 3] .npy with row 0 the top row, as trainers hold images, or a PFM"}, \
    {"dl-dalpha", "A.npy|A.pfm", "also dL/dalpha for the alpha 1 - T (float32 [H, W])"}, \
    {"dl-ddepth", "D.npy|D.pfm", "also dL/d(inverse depth) (float32 [H, W])"}, \
    {"grad-batch", "N", "hold at most N list entries' partial sums at once (default: the backend's own limit; the gradients do not change)"}

typedef struct cli_grad_inputs { float *target, *dl, *da, *dd; } cli_grad_inputs;
/* Mark the upstream gradient's options as read before the scene's setup rejects unread ones (they are read after it,
 * when the image size is known). */
void cli_grad_claim(spr__args *a);
/* The upstream gradient's options for a W×H scene into gd (its arrays held in in); 0, or −1 after one line. */
int cli_grad_upstream(spr__args *a, int W, int H, spr_grad_desc *gd, cli_grad_inputs *in);
void cli_grad_inputs_free(cli_grad_inputs *in);
/* g's arrays as .npz members (up to cap), sh0 [N,1,3] and shN [N,K-1,3] copied into *sh0 and *shN (the caller frees
 * them); the count, or −1 out of memory. */
int cli_grad_npz(const spr_gauss_grads *g, spr_npy *arr, int cap, float **sh0, float **shN);
int cmd_grad(int argc, char **argv);
#endif
