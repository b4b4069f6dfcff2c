/* algo_gauss_blend.c — the viewers' image (SPEC §10.7): what web and engine
 * viewers draw, and KHR_gaussian_splatting's sorting method cameraDistance.
 *
 *   pass "preprocess": the preprocessing of gauss3d (SPEC 10.3 steps 1–7, 9),
 *                      no tiles: each Gaussian's pixel box m ± r
 *   pass "sort":       every kept Gaussian by |μ − eye| (double, host),
 *                      farthest first, ties in file order
 *   pass "blend":      each Gaussian once, as a screen-space ellipse over
 *                      its box: power < −4.5 (3σ), power > 0 or α < 1/255
 *                      cut, α = min(0.99, o·e^power); (c·α, α) blended
 *                      premultiplied over: dst = src + (1 − α)·dst, onto
 *                      (background, 0); no transmittance stop
 */
#include "spr_algo.h"

spr_result spr__algo_gauss_blend(spr__run *run, int *final_target) { return spr__gauss_run(run, 2, final_target); }
