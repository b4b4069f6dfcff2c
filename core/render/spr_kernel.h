/* spr_kernel.h — blending kernels w(ρ) of SPEC §3.1.
 *
 * Every kernel is a fixed sequence of float + − * on ρ or ρ² (no
 * transcendental reaches an output).  `gauss` = exp(−ρ²/(2σ²)), σ = 1/3, is
 * one polynomial in v = 2ρ² − 1 evaluated in Horner form; its coefficients
 * are defined once (kernel.c) and emitted into shader source by the GL
 * backend as exact bit patterns.  Absolute error ≤ 1e-6 on ρ ∈ [0,1] (tests/test_kernel.c).
 */
#ifndef SPR_KERNEL_H
#define SPR_KERNEL_H

typedef enum spr_kernel {
    SPR_KERNEL_GAUSS = 0,     /* default */
    SPR_KERNEL_CONSTANT,
    SPR_KERNEL_LINEAR,
    SPR_KERNEL_EPANECHNIKOV,
    SPR_KERNEL__COUNT
} spr_kernel;

#define SPR_GAUSS_DEGREE 10
/* Coefficients, highest degree first, of the Chebyshev fit of
 * exp(−(9/4)(v + 1)) on v ∈ [−1, 1] (i.e. exp(−4.5ρ²) with v = 2ρ² − 1). */
extern const float spr_gauss_coef[SPR_GAUSS_DEGREE + 1];

/* The shared exponential's constants (SPEC §10.6, arith/gauss.h): log2 e,
 * ln 2 split into a high part of 17 significant bits and the rest, then
 * the Taylor coefficients 1/7! … 1/2!, highest degree first. */
#define SPR_EXP_COEFS 9
extern const float spr_exp_coef[SPR_EXP_COEFS];

/* Name ↔ enum ("gauss", "constant", "linear", "epanechnikov"); −1 if unknown. */
int spr_kernel_from_name(const char *name);
const char *spr_kernel_name(spr_kernel k);

/* w(ρ) itself is spr_kernel_weight() of the shared arithmetic (arith/kernel.h). */

#endif
