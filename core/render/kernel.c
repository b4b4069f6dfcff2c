/* kernel.c — the single definition of the kernel constants (SPEC §3.1).
 *
 * The gauss coefficients were obtained once with mpmath.chebyfit (degree 10,
 * 40 digits, fit error 2.6e-8) and rounded to float; they are the source of
 * truth, not a cache of a computation.
 */
#include "spr_kernel.h"

#include <string.h>

const float spr_gauss_coef[SPR_GAUSS_DEGREE + 1] = {
    0x1.c1f76p-14f,  -0x1.fe6ca2p-12f, 0x1.bf42ap-10f,  -0x1.8c421p-8f,
    0x1.3743aep-6f,  -0x1.9f205p-5f,   0x1.cd034p-4f,   -0x1.99c85ep-3f,
    0x1.1131ep-2f,   -0x1.e5ae1cp-3f,  0x1.afb718p-4f,
};

/* log2 e and ln 2 = hi + lo rounded from the exact values; the Taylor
 * coefficients 1/k! rounded to float (checked in tests/test_gauss.c). */
const float spr_exp_coef[SPR_EXP_COEFS] = {
    0x1.715476p+0f, 0x1.62e4p-1f, 0x1.7f7d1cp-20f,
    0x1.a01a02p-13f, 0x1.6c16c2p-10f, 0x1.111112p-7f, 0x1.555556p-5f, 0x1.555556p-3f, 0x1p-1f,
};

static const char *const kernel_names[SPR_KERNEL__COUNT] = {
    [SPR_KERNEL_GAUSS] = "gauss",
    [SPR_KERNEL_CONSTANT] = "constant",
    [SPR_KERNEL_LINEAR] = "linear",
    [SPR_KERNEL_EPANECHNIKOV] = "epanechnikov",
};

int spr_kernel_from_name(const char *name)
{
    for (int k = 0; k < SPR_KERNEL__COUNT; k++)
        if (strcmp(name, kernel_names[k]) == 0) return k;
    return -1;
}

const char *spr_kernel_name(spr_kernel k)
{
    return (unsigned)k < SPR_KERNEL__COUNT ? kernel_names[k] : "?";
}
