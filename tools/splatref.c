/* splatref.c — entry point of the `splatref` command: subcommand dispatch. */
#include "cli.h"
#include "cli_grad.h"
#include "spr_algo.h"

#include <stdio.h>
#include <string.h>

static const struct { const char *name; int (*fn)(int, char **); const char *help; } commands[] = {
    {"render", cmd_render, NULL}, /* its line is the algorithm registry's (usage) */
    {"group", cmd_group, "group splats (mgc, wgc, hash, extended) and report the statistics of [ZP] Tables 1-3"},
    {"info", cmd_info, "counts, bounds, radius statistics and attribute sources of a model"},
    {"sample", cmd_sample, "resample a mesh to N uniformly distributed points (PLY out)"},
    {"show", cmd_show, "turn a dumped plane (PFM) into a PNG to look at"},
    {"check", cmd_check, "check your image (PNG/PFM) of a scene against the reference under PARITY.md's tiers: verdict, report, heat map"},
    {"explain", cmd_explain, "pixel history: every fragment that reached a pixel, pass by pass, cpu and gl side by side (SPEC 8)"},
    {"step", cmd_step, "a step-by-step walk-through of one frame as a web page: every pass, plane, equation, pixel (no network)"},
    {"compare", cmd_compare, "two images under PARITY.md's tiers, with [ZP]'s eps and covered-pixel means; verdict, report, heat map"},
    {"grad", cmd_grad, "the backward pass of gauss3d (SPEC 10.10): every Gaussian's gradient for a loss or dL/dimage, as one .npz of gsplat's arrays"},
    {"parity", cmd_parity, "compare the CPU reference and the GL backend, every plane of every pass"},
    {"reference", cmd_reference, "check (or --update) the reference images of reference_images/"},
    {"domains", cmd_domains, "multi-scale soft decomposition, domains and support rectangles of a model ([R], SPEC 7)"},
    {"profiles", cmd_profiles, "the Gaussian renderer profiles (SPEC 10.9): each renderer's rules, as a table, Markdown or JSON"},
    {"bench", cmd_bench, "benchmark the CPU reference on fixed scenes, 1 vs 2 threads"},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: splatref COMMAND [options]   (splatref COMMAND --help for its options)\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (commands[i].help) fprintf(f, "  %-10s %s\n", commands[i].name, commands[i].help);
        else fprintf(f, "  %-10s render a model with one of the %d algorithms (%s; cpu or gl backend)\n", commands[i].name, (int)SPR_ALGO__COUNT, spr_algo_names(", "));
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return 0;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (!strcmp(argv[1], commands[i].name)) return commands[i].fn(argc - 2, argv + 2);
    fprintf(stderr, "splatref: unknown command '%s' (see splatref --help)\n", argv[1]);
    return 2;
}
