/* algo_gauss2d.c — the surfel rasterizer of 2D Gaussian splatting (SPEC
 * §10.5; hbb1's diff-surfel-rasterization, forward pass, restated
 * operation by operation in docs/gaussians.md):
 *
 *   pass "preprocess": per Gaussian, its two largest axes span a disk:
 *                      H = K·[σ_u·u | σ_v·v | t] maps (u, v, 1) to the
 *                      screen; the disk's 3σ box gives centre and radius;
 *                      the normal turned to face the camera
 *   pass "sort":       each tile's Gaussians by t.z, ties in file order
 *   pass "raster":     per pixel (i, j), front to back:
 *                        p = (i·Tw − Tu) × (j·Tw − Tv), s = p.xy / p.z;
 *                        ρ = min(s·s, 2·|m − (i, j)|²), power = −ρ/2;
 *                        skip hits before the near plane; then the
 *                        compositing of gauss3d with w = α·T:
 *                        C += c·w, depth += z·w, normal += n·w
 *                      colour, transmittance, contrib, surfdepth, normal
 */
#include "spr_algo.h"

spr_result spr__algo_gauss2d(spr__run *run, int *final_target) { return spr__gauss_run(run, 1, final_target); }
