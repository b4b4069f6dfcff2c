/* test_kernel.c — SPEC §3.1: kernel values and the gauss polynomial's error. */
#include <math.h>
#include "spr_fragment.h"
#include "test_util.h"

START_TEST(gauss_polynomial_error_below_1e6)
{
    double worst = 0.0;
    for (int i = 0; i <= 100000; i++) {
        float rho = (float)i / 100000.0f, rho2 = rho * rho;
        double exact = exp(-(double)rho2 / (2.0 * (1.0 / 3.0) * (1.0 / 3.0)));
        double err = fabs((double)spr_kernel_weight(SPR_KERNEL_GAUSS, rho2, rho) - exact);
        if (err > worst) worst = err;
    }
    printf("kernel: gauss polynomial max abs error %.3g on [0,1]\n", worst);
    ck_assert_double_le(worst, 1e-6);
}
END_TEST

START_TEST(gauss_rim_weight_is_about_0_011)
{
    /* [R] §3.3.2: σ = 1/3 gives ≈ 0.011 at the rim */
    ck_assert_double_eq_tol(spr_kernel_weight(SPR_KERNEL_GAUSS, 1.0f, 1.0f), exp(-4.5), 1e-6);
    ck_assert_double_eq_tol(spr_kernel_weight(SPR_KERNEL_GAUSS, 0.0f, 0.0f), 1.0, 1e-6);
}
END_TEST

START_TEST(simple_kernels_exact)
{
    ck_assert_float_eq(spr_kernel_weight(SPR_KERNEL_CONSTANT, 0.25f, 0.5f), 1.0f);
    ck_assert_float_eq(spr_kernel_weight(SPR_KERNEL_LINEAR, 0.25f, 0.5f), 0.5f);
    ck_assert_float_eq(spr_kernel_weight(SPR_KERNEL_EPANECHNIKOV, 0.25f, 0.5f), 0.75f);
    ck_assert_float_eq(spr_kernel_weight(SPR_KERNEL_LINEAR, 1.0f, 1.0f), 0.0f);
    ck_assert_int_eq(spr_kernel_from_name("epanechnikov"), SPR_KERNEL_EPANECHNIKOV);
    ck_assert_int_eq(spr_kernel_from_name("gaussian"), -1);
}
END_TEST

Suite *make_kernel_suite(void)
{
    Suite *s = suite_create("kernel");
    TCase *tc = tcase_create("kernel");
    tcase_add_test(tc, gauss_polynomial_error_below_1e6);
    tcase_add_test(tc, gauss_rim_weight_is_about_0_011);
    tcase_add_test(tc, simple_kernels_exact);
    suite_add_tcase(s, tc);
    return s;
}
