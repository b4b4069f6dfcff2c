/* algo_gauss3d.c — the training rasterizer of 3D Gaussian splatting
 * (SPEC §10.3, §10.4; graphdeco-inria's diff-gaussian-rasterization,
 * forward pass, restated in docs/gaussians.md):
 *
 *   pass "preprocess": per Gaussian, t = R·μ + t (culled at t.z ≤ 0.2);
 *                      Σ' = (J·W)·Rq·S²·Rqᵀ·(J·W)ᵀ with clamped tangents,
 *                      dilated by 0.3; conic, radius ceil(3·sqrt(λ_max)),
 *                      centre, 16×16 tile rectangle (empty: culled)
 *   pass "sort":       each tile's Gaussians by t.z, ties in file order
 *   pass "raster":     per pixel, front to back over its tile's list:
 *                        power > 0: next;  α = min(0.99, o·e^power);
 *                        α < 1/255: next;  T' = T(1 − α); T' < 1e-4: stop;
 *                        C += c·α·T;  D += (1/t.z)·α·T;  T = T'
 *                      colour C + T·bg, transmittance, contrib, invdepth
 */
#include "spr_algo.h"

spr_result spr__algo_gauss3d(spr__run *run, int *final_target) { return spr__gauss_run(run, 0, final_target); }
