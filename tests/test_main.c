/* test_main.c — the one Check runner: `splatref_tests [suite]`. */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

Suite *make_kernel_suite(void);
Suite *make_camera_suite(void);
Suite *make_raster_suite(void);
Suite *make_algo_suite(void);
Suite *make_group_suite(void);
Suite *make_io_suite(void);
Suite *make_cli_suite(void);
Suite *make_determinism_suite(void);

static const struct { const char *name; Suite *(*make)(void); } suites[] = {
    {"kernel", make_kernel_suite}, {"camera", make_camera_suite}, {"raster", make_raster_suite},
    {"algo", make_algo_suite},     {"group", make_group_suite},   {"io", make_io_suite},
    {"cli", make_cli_suite},       {"determinism", make_determinism_suite},
};

int main(int argc, char **argv)
{
    SRunner *sr = NULL;
    for (size_t i = 0; i < sizeof suites / sizeof suites[0]; i++) {
        if (argc > 1 && strcmp(argv[1], suites[i].name)) continue;
        if (!sr) sr = srunner_create(suites[i].make());
        else srunner_add_suite(sr, suites[i].make());
    }
    if (!sr) {
        fprintf(stderr, "splatref_tests: no suite named '%s'\n", argv[1]);
        return 2;
    }
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
