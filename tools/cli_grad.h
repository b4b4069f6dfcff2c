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
    {"loss-target", "IMG", "--loss: the target image (PNG or PFM, the scene's size; default black)"}, \
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
/* What grad and check --grads share: the scene's setup (the upstream options claimed first), the upstream gradient,
 * backend bname, and its gradients into g; 0, or −1 after one line (*b and g, when made, for the caller to free). */
int cli_grad_frame(spr__args *a, const char *bname, const spr_gl_desc *gld, spr_scene *s, spr_render_desc *rd, spr_grad_desc *gd,
                   cli_grad_inputs *in, spr_backend **b, spr_gauss_grads *g);
/* g's arrays as .npz members (up to cap), sh0 [N,1,3] and shN [N,K-1,3] copied into *sh0 and *shN (the caller frees
 * them); the count, or −1 out of memory. */
int cli_grad_npz(const spr_gauss_grads *g, spr_npy *arr, int cap, float **sh0, float **shN);
int cmd_grad(int argc, char **argv);
/* check --grads THEIRS.npz (cli_check_grads.c): the reference's gradients of the scene against THEIRS, per array;
 * out: report.json's folder (NULL: none), junit: F.xml (NULL: none).  0 pass, 1 fail, 2 after one line. */
int cli_check_grads(spr__args *a, const char *path, const char *out, const char *junit);
#define CLI_CHECK_GRADS_OPTS \
    {"grads", "THEIRS.npz", "check a training renderer's gradients of this gauss3d scene instead of an image: THEIRS.npz holds gsplat's arrays as splatref grad writes them (means, quats, scales, opacities, sh0, shN, means2d, conics, colors, absgrad, counts), for the upstream gradient given by --loss/--target or --dl-dimage; the reference's are computed on the CPU. One verdict per array"}, \
    {"rtol", "R", "--grads: an entry passes when |theirs - ref| <= R*S_G + atol, S_G the largest |ref| of that Gaussian's row (means2d: and its absgrad row, the exact sum of |terms|). Default 2^-10: a renderer that recovers T by division, uses float32 fast-math exp and sums pixels with atomics in any order errs by ~1e-6 relative per pixel term plus n*2^-24 of the sum of |terms| (not of the value: terms cancel); 2^-10 leaves ~1000x that for cancellation, while a bug (a sign, a missing term, an ungated cap) is O(1). counts: exact"}, \
    {"atol", "A", "--grads: the absolute floor of the tolerance (default 1e-6*max|ref| over each array: the rounding of its largest values, for Gaussians whose whole row is near 0)"}
/* parity: the gradients of scene (view, cloud, rd) under gd on cpu and gl compared array by array, a line each into f
 * (and the first differing Gaussian); 1 when every array is bit-identical, 0 when one differs, −1 after one line in
 * err. */
int cli_grad_parity(FILE *f, spr_backend *cpu, spr_backend *gl, const spr_view *view, const spr_cloud *cloud, const spr_render_desc *rd,
                    const spr_grad_desc *gd, spr_error *err);
#endif
