/* check_planes.c — the reference planes of a scene file against buffers of
 * your own, with splatref as a library.
 *
 *   check_planes SCENE.json IMAGE.pfm [--lsb N]
 *
 * Loads the scene (spr_scene_load: the model, camera, groups and algorithm
 * exactly as `splatref render --scene` would), renders it on the CPU
 * reference while keeping every plane of every pass (the pass hook), then
 * compares the final image with IMAGE.pfm — the float image your renderer
 * made of the same scene — bit for bit (Tier A), or within N LSB (Tier B).
 * Prints the passes it saw and the verdict; exit 0 pass, 1 fail, 2 error.
 * Your own test suite would compare its intermediate buffers with the
 * planes the hook received in the same way. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <spr_check.h>
#include <spr_image.h>
#include <spr_scene.h>
#include <spr_swrast.h>
#include <spr_version.h>

typedef struct planes_seen {
    int passes;
    size_t values;
} planes_seen;

/* Called after every pass: read each plane of the pass's target. */
static void keep_planes(void *user, spr_backend *b, const spr_pass_info *info)
{
    planes_seen *ps = user;
    const size_t np = (size_t)b->view.width * b->view.height;
    float *buf = malloc(np * 4 * sizeof *buf);
    if (!buf) return;
    printf("  pass %d %s%s", info->index, info->name, info->group >= 0 ? " (group)" : "");
    for (int p = 0; p < SPR_PLANE__COUNT; p++)
        if ((spr_backend_target_planes(b, info->target) & SPR_PLANE_BIT(p)) && !spr_backend_read_plane(b, info->target, (spr_plane)p, buf)) {
            printf(" %s", spr_plane_name((spr_plane)p));
            ps->values += np * (size_t)spr_plane_channels((spr_plane)p);
        }
    printf("\n");
    ps->passes++;
    free(buf);
}

int main(int argc, char **argv)
{
    if (argc != 3 && !(argc == 5 && !strcmp(argv[3], "--lsb"))) {
        fprintf(stderr, "usage: check_planes SCENE.json IMAGE.pfm [--lsb N]\n");
        return 2;
    }
    spr_scene s;
    spr_render_desc rd;
    spr_error err = {0};
    if (spr_scene_load(argv[1], 0, &s, &rd, &err)) { fprintf(stderr, "check_planes: %s\n", err.msg); return 2; }
    printf("check_planes (splatref %s): %s, %zu splats, %s, %dx%d\n", SPR_VERSION_STRING, s.model, s.cloud.n, spr_algo_name(rd.algo),
           s.view.width, s.view.height);
    planes_seen ps = {0, 0};
    rd.hook = keep_planes;
    rd.hook_user = &ps;
    spr_backend *cpu = spr_swrast_create(0, &err);
    spr_render_result res = {0};
    int rc = 2;
    float *mine = NULL, *ref = NULL;
    int w, h, ch;
    if (!cpu || spr_render(cpu, &s.view, &s.cloud, &rd, &res, &err) || spr_read_pfm(argv[2], &mine, &w, &h, &ch, &err)) {
        fprintf(stderr, "check_planes: %s\n", err.msg);
        goto done;
    }
    printf("check_planes: %d passes, %zu plane values from the reference\n", ps.passes, ps.values);
    if (w != res.width || h != res.height || ch != 3) {
        fprintf(stderr, "check_planes: %s is %dx%d with %d channels, the scene renders %dx%d RGB\n", argv[2], w, h, ch, res.width, res.height);
        goto done;
    }
    ref = malloc((size_t)w * h * 3 * sizeof *ref);
    if (!ref) goto done;
    for (size_t i = 0; i < (size_t)w * h; i++)
        for (int c = 0; c < 3; c++) ref[3 * i + c] = res.rgba[4 * i + c];
    spr_check_desc d = {argc == 5 ? SPR_TIER_B : SPR_TIER_A, 32, -1, argc == 5 ? atoi(argv[4]) : -1, 0};
    spr_check_result r;
    spr_check_images(ref, mine, w, h, 3, &d, &r, NULL);
    printf("check_planes: Tier %s: %zu of %zu pixels differ, %zu fail, max %llu ulp, max %d LSB\n", spr_tier_name(d.tier), r.differing, r.pixels,
           r.failing, (unsigned long long)r.max_ulp, r.max_lsb);
    if (r.first_x >= 0) printf("check_planes: first at x %d, y %d: reference %.9g, yours %.9g\n", r.first_x, r.first_y, r.first_ref, r.first_test);
    printf("verdict: %s\n", r.pass ? "PASS" : "FAIL");
    rc = r.pass ? 0 : 1;
done:
    free(mine);
    free(ref);
    spr_render_result_free(&res);
    spr_backend_destroy(cpu);
    spr_scene_free(&s);
    return rc;
}
