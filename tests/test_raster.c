/* test_raster.c — the CPU backend on tiny scenes (SPEC §2, §3.2–§3.4). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "spr_fragment.h"
#include "test_util.h"

typedef struct fixture {
    spr_backend *b;
    int t;
    float color[4 * 64];
    float depth[64], test[64];
    uint32_t id[64], count[64];
} fixture;

static void setup(fixture *f, int threads)
{
    spr_error err;
    spr_view v;
    tu_hand_view(4, 4, &v);
    f->b = spr_swrast_create(threads, &err);
    ck_assert_ptr_nonnull(f->b);
    ck_assert_int_eq(spr_backend_set_view(f->b, &v), SPR_OK);
    ck_assert_int_eq(spr_backend_target_create(f->b, SPR_PLANES_ALL, &f->t), SPR_OK);
}

static void draw(fixture *f, const spr_cloud *c, const spr_pass_state *s, spr_draw_stats *st)
{
    spr_draw_desc d = {.cloud = c, .state = *s};
    ck_assert_int_eq(spr_backend_draw(f->b, f->t, &d, st), SPR_OK);
    spr_backend_read_plane(f->b, f->t, SPR_PLANE_COLOR, f->color);
    spr_backend_read_plane(f->b, f->t, SPR_PLANE_DEPTH, f->depth);
    spr_backend_read_plane(f->b, f->t, SPR_PLANE_TEST, f->test);
    spr_backend_read_plane(f->b, f->t, SPR_PLANE_ID, f->id);
    spr_backend_read_plane(f->b, f->t, SPR_PLANE_COUNT, f->count);
}

static void state(spr_pass_state *s)
{
    spr_pass_state_defaults(s);
    s->depth_write = 1;
}

START_TEST(one_splat_covers_four_pixels)
{
    fixture f;
    setup(&f, 1);
    spr_cloud c;
    tu_cloud(&c, 1, (double[]){0, 0, 0}, 0.5f);
    tu_set_color(&c, 0, 1.0f, 0.5f, 0.25f);
    spr_pass_state s;
    state(&s);
    spr_draw_stats st;
    draw(&f, &c, &s, &st);
    ck_assert_uint_eq(st.generated, 4);
    ck_assert_uint_eq(st.passed, 4);
    float w = spr_kernel_weight(SPR_KERNEL_GAUSS, 0.5f, sqrtf(0.5f));
    ck_assert_double_eq_tol(w, exp(-4.5 * 0.5), 1e-6); /* ρ² = 0.5 at (±0.25, ±0.25) */
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) {
            int p = 4 * y + x, in = (x == 1 || x == 2) && (y == 1 || y == 2);
            ck_assert_float_eq(f.depth[p], in ? 0.5f : 1.0f);
            ck_assert_float_eq(f.test[p], in ? 0.5f : 1.0f);
            ck_assert_uint_eq(f.id[p], in ? 0u : UINT32_MAX);
            ck_assert_uint_eq(f.count[p], in ? 1u : 0u);
            ck_assert_float_eq(f.color[4 * p + 0], in ? w * 1.0f : 0.0f);
            ck_assert_float_eq(f.color[4 * p + 1], in ? w * 0.5f : 0.0f);
            ck_assert_float_eq(f.color[4 * p + 2], in ? w * 0.25f : 0.0f);
            ck_assert_float_eq(f.color[4 * p + 3], in ? w : 0.0f);
        }
    spr_cloud_free(&c);
    spr_backend_destroy(f.b);
}
END_TEST

START_TEST(closed_disk_rim_pixels)
{
    fixture f;
    setup(&f, 1);
    spr_cloud c; /* centred on pixel (2,2): the 4 neighbours lie exactly on the rim */
    tu_cloud(&c, 1, (double[]){0.25, 0.25, 0}, 0.5f);
    spr_pass_state s;
    state(&s);
    s.kernel = SPR_KERNEL_LINEAR;
    spr_draw_stats st;
    draw(&f, &c, &s, &st);
    ck_assert_uint_eq(st.generated, 5);
    ck_assert_float_eq(f.color[4 * (4 * 2 + 2) + 3], 1.0f); /* ρ = 0 */
    ck_assert_float_eq(f.color[4 * (4 * 2 + 1) + 3], 0.0f); /* ρ = 1: linear weight 0, still a fragment */
    ck_assert_uint_eq(f.count[4 * 2 + 1], 1);
    ck_assert_uint_eq(f.count[4 * 1 + 1], 0);               /* diagonal: ρ² = 2 */
    spr_cloud_free(&c);
    spr_backend_destroy(f.b);
}
END_TEST

START_TEST(edge_on_and_behind_camera_draw_nothing)
{
    fixture f;
    setup(&f, 2);
    spr_cloud c;
    tu_cloud(&c, 3, (double[]){0, 0, 0, 0, 0, 3, 0, 0, -1.5}, 0.9f);
    c.nrm[0] = 1.0f; c.nrm[2] = 0.0f; /* splat 0 exactly edge-on */
    spr_pass_state s;
    state(&s);
    spr_draw_stats st;
    draw(&f, &c, &s, &st);
    ck_assert_uint_eq(st.splats, 3);
    ck_assert_uint_eq(st.generated, 0); /* behind the eye (t < 0) and beyond far (t > 1) */
    spr_cloud_free(&c);
    spr_backend_destroy(f.b);
}
END_TEST

START_TEST(depth_test_nearer_wins_ties_keep_first)
{
    fixture f;
    setup(&f, 2);
    spr_cloud c; /* 0: far (t = 0.5), 1: near (t = 0.25), 2: same depth as 1 */
    tu_cloud(&c, 3, (double[]){0, 0, 0, 0, 0, 0.5, 0, 0, 0.5}, 0.5f);
    spr_pass_state s;
    state(&s);
    spr_draw_stats st;
    draw(&f, &c, &s, &st);
    ck_assert_uint_eq(st.generated, 12);
    ck_assert_uint_eq(st.passed, 8); /* far, then near replaces it; the tie fails LESS */
    ck_assert_uint_eq(f.id[4 * 1 + 1], 1);
    ck_assert_float_eq(f.depth[4 * 1 + 1], 0.25f);
    ck_assert_uint_eq(f.count[4 * 1 + 1], 2);
    spr_cloud_free(&c);
    spr_backend_destroy(f.b);
}
END_TEST

START_TEST(lequal_and_add_blend)
{
    fixture f;
    setup(&f, 2);
    spr_cloud c;
    tu_cloud(&c, 2, (double[]){0, 0, 0, 0, 0, 0}, 0.5f);
    tu_set_color(&c, 1, 0.5f, 0.5f, 0.5f);
    spr_pass_state s;
    state(&s);
    s.depth_func = SPR_FUNC_LEQUAL;
    spr_pass_state_blend(&s, SPR_BLEND_ADD);
    s.kernel = SPR_KERNEL_CONSTANT;
    spr_draw_stats st;
    draw(&f, &c, &s, &st);
    ck_assert_uint_eq(st.passed, 8);
    ck_assert_float_eq(f.color[4 * 5 + 0], 1.5f);
    ck_assert_float_eq(f.color[4 * 5 + 3], 2.0f);
    ck_assert_uint_eq(f.id[5], 1);
    spr_cloud_free(&c);
    spr_backend_destroy(f.b);
}
END_TEST

START_TEST(backface_culling)
{
    fixture f;
    setup(&f, 1);
    spr_cloud c;
    tu_cloud(&c, 1, (double[]){0, 0, 0}, 0.5f);
    c.nrm[2] = -1.0f;
    spr_pass_state s;
    state(&s);
    s.cull_backfaces = 1;
    spr_draw_stats st;
    draw(&f, &c, &s, &st);
    ck_assert_uint_eq(st.generated, 0);
    spr_cloud_free(&c);
    spr_backend_destroy(f.b);
}
END_TEST

START_TEST(thousands_of_fragments_in_submission_order)
{
    /* 3000 splats on the same pixels, additive: the float sum must be the
     * sequential sum in submission order whatever the thread count. */
    const int n = 3000;
    double *xyz = calloc(3 * (size_t)n, sizeof(double));
    for (int i = 0; i < n; i++) xyz[3 * i + 2] = -0.001 * (i % 7);
    spr_cloud c;
    tu_cloud(&c, (size_t)n, xyz, 0.4f);
    for (int i = 0; i < n; i++) tu_set_color(&c, (size_t)i, (float)((i * 37) % 101) / 100.0f, 0.1f, 0.7f);
    spr_pass_state s;
    spr_pass_state_defaults(&s);
    s.depth_func = SPR_FUNC_ALWAYS;
    spr_pass_state_blend(&s, SPR_BLEND_ADD);
    for (int threads = 1; threads <= 7; threads += 3) {
        fixture f;
        setup(&f, threads);
        spr_draw_stats st;
        draw(&f, &c, &s, &st);
        float o0[3], d[3], t, rho2, den;
        spr_pixel_ray(&f.b->view, 1, 1, o0, d);
        float acc = 0.0f;
        for (int i = 0; i < n; i++) {
            if (!spr_ray_disk(o0, d, c.pos + 3 * i, c.nrm + 3 * i, c.radius[i], &t, &rho2, &den)) ck_abort_msg("splat %d misses", i);
            float w = spr_kernel_weight(SPR_KERNEL_GAUSS, rho2, sqrtf(rho2));
            acc = w * c.color[3 * i] + acc;
        }
        ck_assert_float_eq(f.color[4 * 5], acc);
        ck_assert_uint_eq(f.count[5], (uint32_t)n);
        spr_backend_destroy(f.b);
    }
    spr_cloud_free(&c);
    free(xyz);
}
END_TEST

/* SPEC §6.1's average, I = (1/K) Σ I_k, on values exact in float: inputs
 * (0.25, 0.5, 0.75, 1) and (0.5, 0, 0.25, 0.5) give (0.375, 0.25, 0.5, 0.75);
 * a splat drawn into the second input at t = 0.5 makes the output depth 0.5
 * there (the nearest), 1 elsewhere. */
/* A draw of the same splats as the last one in the same view takes its
 * bins (swrast keeps them); a draw of other splats through the same index
 * buffer, or after a set_view with the cloud moved, must not.  Hand view
 * 4×4: a splat of radius 0.2 at a pixel centre covers that pixel alone. */
START_TEST(kept_bins_only_for_the_same_draw)
{
    fixture f;
    setup(&f, 2);
    spr_cloud c;
    const double xyz[6] = {-0.75, -0.75, 0.0, 0.75, 0.75, 0.0}; /* pixel (0, 0) and pixel (3, 3) */
    tu_cloud(&c, 2, xyz, 0.2f);
    uint32_t idx[1] = {0};
    spr_draw_desc d = {.cloud = &c, .indices = idx, .count = 1};
    state(&d.state);
    const float zero[4] = {0, 0, 0, 0};
    int t[4];
    for (int k = 0; k < 4; k++) {
        ck_assert_int_eq(spr_backend_target_create(f.b, SPR_PLANES_ALL, &t[k]), SPR_OK);
        ck_assert_int_eq(spr_backend_clear(f.b, t[k], zero), SPR_OK);
    }
    ck_assert_int_eq(spr_backend_draw(f.b, t[0], &d, NULL), SPR_OK); /* splat 0 */
    ck_assert_int_eq(spr_backend_draw(f.b, t[1], &d, NULL), SPR_OK); /* the same draw: kept bins */
    idx[0] = 1;
    ck_assert_int_eq(spr_backend_draw(f.b, t[2], &d, NULL), SPR_OK); /* splat 1, through the same buffer */
    const int covered[4] = {0, 0, 15, 12}; /* the pixel each draw covers (x + 4y) */
    for (int k = 0; k < 3; k++) {
        ck_assert_int_eq(spr_backend_read_plane(f.b, t[k], SPR_PLANE_COUNT, f.count), SPR_OK);
        for (int i = 0; i < 16; i++) ck_assert_uint_eq(f.count[i], i == covered[k] ? 1u : 0u);
    }
    /* the next frame, the same draw as the last, but splat 1 moved to pixel
     * (0, 3) and the view set again (no target may outlive a view) */
    c.pos[3] = -0.75f;
    for (int k = 0; k < 4; k++) spr_backend_target_destroy(f.b, t[k]);
    spr_backend_target_destroy(f.b, f.t);
    spr_view v;
    tu_hand_view(4, 4, &v);
    ck_assert_int_eq(spr_backend_set_view(f.b, &v), SPR_OK);
    ck_assert_int_eq(spr_backend_target_create(f.b, SPR_PLANES_ALL, &t[3]), SPR_OK);
    ck_assert_int_eq(spr_backend_clear(f.b, t[3], zero), SPR_OK);
    ck_assert_int_eq(spr_backend_draw(f.b, t[3], &d, NULL), SPR_OK);
    ck_assert_int_eq(spr_backend_read_plane(f.b, t[3], SPR_PLANE_COUNT, f.count), SPR_OK);
    for (int i = 0; i < 16; i++) ck_assert_uint_eq(f.count[i], i == covered[3] ? 1u : 0u);
    spr_cloud_free(&c);
    spr_backend_destroy(f.b);
}
END_TEST

/* A composite reads a tile no draw touched as cleared: the CPU backend
 * clears tile by tile where a draw or a composite gets there, and reads an
 * input's tile still pending the zero clear from a band of that clear.
 * 100x70 pixels (4 x 3 tiles, the last ones partial): target A drawn near
 * the centre, B never drawn, C cleared to a colour and drawn elsewhere; the
 * deferred composite of (A, B, C) and of (A, B) equals the one over inputs
 * read (so filled) first, bit for bit, and by hand where nothing was drawn:
 * C's colour over its weight 1, or the background; A still reads as
 * cleared after the composite. */
START_TEST(pending_tiles_composite_as_cleared)
{
    const int threads = _i + 1, W = 100, H = 70, np = W * H;
    spr_error err;
    spr_view v;
    tu_hand_view(W, H, &v);
    spr_cloud a, cc;
    tu_cloud(&a, 1, (double[]){0, 0, 0}, 0.08f);
    tu_cloud(&cc, 1, (double[]){0.9, 0.6, 0}, 0.08f);
    tu_set_color(&cc, 0, 0.0f, 1.0f, 0.0f);
    const float c_color[4] = {0.25f, 0.5f, 0.75f, 1.0f}, bg[3] = {0.1f, 0.2f, 0.3f};
    float *out[2][2], *depth[2][2];
    for (int side = 0; side < 2; side++) { /* side 1: every input read (its tiles filled) before the composites */
        spr_backend *b = spr_swrast_create(threads, &err);
        ck_assert_ptr_nonnull(b);
        ck_assert_int_eq(spr_backend_set_view(b, &v), SPR_OK);
        int t[4];
        for (int k = 0; k < 3; k++) ck_assert_int_eq(spr_backend_target_create(b, SPR_PLANES_OPAQUE, &t[k]), SPR_OK);
        ck_assert_int_eq(spr_backend_target_create(b, SPR_PLANES_IMAGE, &t[3]), SPR_OK);
        ck_assert_int_eq(spr_backend_clear(b, t[2], c_color), SPR_OK);
        spr_draw_desc d = {.cloud = &a};
        state(&d.state);
        spr_draw_stats st;
        ck_assert_int_eq(spr_backend_draw(b, t[0], &d, &st), SPR_OK);
        ck_assert_uint_gt(st.passed, 0);
        d.cloud = &cc;
        ck_assert_int_eq(spr_backend_draw(b, t[2], &d, &st), SPR_OK);
        ck_assert_uint_gt(st.passed, 0);
        float *buf = malloc((size_t)np * 4 * sizeof *buf);
        if (side)
            for (int k = 0; k < 3; k++) ck_assert_int_eq(spr_backend_read_plane(b, t[k], SPR_PLANE_COLOR, buf), SPR_OK);
        for (int pass = 0; pass < 2; pass++) {
            spr_composite_desc cd = {.op = SPR_COMP_DEFERRED, .inputs = t, .n_inputs = pass ? 2 : 3, .output = t[3], .eps_t = 0.1f,
                                     .background = {bg[0], bg[1], bg[2]}};
            ck_assert_int_eq(spr_backend_composite(b, &cd), SPR_OK);
            out[side][pass] = malloc((size_t)np * 4 * sizeof(float));
            depth[side][pass] = malloc((size_t)np * sizeof(float));
            ck_assert_int_eq(spr_backend_read_plane(b, t[3], SPR_PLANE_COLOR, out[side][pass]), SPR_OK);
            ck_assert_int_eq(spr_backend_read_plane(b, t[3], SPR_PLANE_DEPTH, depth[side][pass]), SPR_OK);
        }
        /* A after the composites: cleared where its splat is not */
        ck_assert_int_eq(spr_backend_read_plane(b, t[0], SPR_PLANE_DEPTH, buf), SPR_OK);
        ck_assert_float_eq(buf[0], 1.0f);
        ck_assert_float_eq(buf[np - 1], 1.0f);
        ck_assert_float_lt(buf[35 * W + 50], 1.0f);
        ck_assert_int_eq(spr_backend_read_plane(b, t[0], SPR_PLANE_ID, buf), SPR_OK);
        ck_assert_uint_eq(((uint32_t *)buf)[np - 1], 0xffffffffu);
        free(buf);
        spr_backend_destroy(b);
    }
    for (int pass = 0; pass < 2; pass++) {
        ck_assert(memcmp(out[0][pass], out[1][pass], (size_t)np * 4 * sizeof(float)) == 0);
        ck_assert(memcmp(depth[0][pass], depth[1][pass], (size_t)np * sizeof(float)) == 0);
        /* pixel (2, 68), a corner no splat reaches: every input at its clear depth 1 */
        const int i = 68 * W + 2;
        for (int ch = 0; ch < 3; ch++) ck_assert_float_eq(out[0][pass][4 * i + ch], pass ? bg[ch] : c_color[ch]);
        ck_assert_float_eq(depth[0][pass][i], 1.0f);
        for (int side = 0; side < 2; side++) free(out[side][pass]), free(depth[side][pass]);
    }
    spr_cloud_free(&a);
    spr_cloud_free(&cc);
}
END_TEST

/* A target reads as cleared when created (colour 0, the other planes their
 * SPEC values: depth and test +1, id ~0, count 0, the rest 0, transmittance
 * 1), even on memory kept from a drawn target and never cleared explicitly;
 * an explicit clear alone gives its colour. The CPU backend clears a new
 * target at its first use, so a clear that follows the creation writes the
 * planes once; 37x5 pixels (odd: the fill's heads and tails) on 1 and 2
 * threads. */
START_TEST(created_targets_read_as_cleared)
{
    const int threads = _i + 1, W = 37, H = 5, np = W * H;
    spr_error err;
    spr_view v;
    tu_hand_view(W, H, &v);
    spr_backend *b = spr_swrast_create(threads, &err);
    ck_assert_ptr_nonnull(b);
    ck_assert_int_eq(spr_backend_set_view(b, &v), SPR_OK);
    spr_cloud c;
    tu_cloud(&c, 1, (double[]){0, 0, 0}, 0.9f);
    int t;
    ck_assert_int_eq(spr_backend_target_create(b, SPR_PLANES_ALL, &t), SPR_OK);
    spr_draw_desc d = {.cloud = &c};
    state(&d.state);
    spr_draw_stats st;
    ck_assert_int_eq(spr_backend_draw(b, t, &d, &st), SPR_OK);
    ck_assert_uint_gt(st.passed, 0);
    spr_backend_target_destroy(b, t);
    float *buf = malloc((size_t)np * 4 * sizeof *buf);
    uint32_t *u = (uint32_t *)buf;
    /* plane, channels, expected value as float (uint planes: as uint) */
    static const struct { spr_plane p; int ch; int is_uint; double want; } planes[] = {
        {SPR_PLANE_COLOR, 4, 0, 0.0}, {SPR_PLANE_DEPTH, 1, 0, 1.0}, {SPR_PLANE_TEST, 1, 0, 1.0}, {SPR_PLANE_ID, 1, 1, 4294967295.0},
        {SPR_PLANE_COUNT, 1, 1, 0.0}, {SPR_PLANE_OPACITY, 1, 0, 0.0}, {SPR_PLANE_NORMAL, 4, 0, 0.0}, {SPR_PLANE_TRANS, 1, 0, 1.0},
        {SPR_PLANE_CONTRIB, 1, 1, 0.0}, {SPR_PLANE_INVDEPTH, 1, 0, 0.0}, {SPR_PLANE_SURFDEPTH, 1, 0, 0.0}};
    for (int round = 0; round < 2; round++) {
        /* round 0: created only; round 1: created, then cleared to a colour */
        const float color[4] = {0.25f, 0.5f, 0.75f, 1.0f};
        ck_assert_int_eq(spr_backend_target_create(b, SPR_PLANES_ALL, &t), SPR_OK); /* the drawn target's memory */
        if (round) ck_assert_int_eq(spr_backend_clear(b, t, color), SPR_OK);
        for (size_t q = 0; q < sizeof planes / sizeof *planes; q++) {
            ck_assert_int_eq(spr_backend_read_plane(b, t, planes[q].p, buf), SPR_OK);
            for (int i = 0; i < np * planes[q].ch; i++) {
                if (planes[q].is_uint) ck_assert_msg(u[i] == (uint32_t)planes[q].want, "round %d plane %d word %d: %u", round, (int)planes[q].p, i, u[i]);
                else {
                    const float want = round && planes[q].p == SPR_PLANE_COLOR ? color[i % 4] : (float)planes[q].want;
                    ck_assert_msg(buf[i] == want, "round %d plane %d word %d: %g, not %g", round, (int)planes[q].p, i, buf[i], want);
                }
            }
        }
        /* drawn after the lazy clear: the fragment sees the cleared depth */
        ck_assert_int_eq(spr_backend_draw(b, t, &d, &st), SPR_OK);
        ck_assert_uint_gt(st.passed, 0);
        spr_backend_target_destroy(b, t);
    }
    free(buf);
    spr_cloud_free(&c);
    spr_backend_destroy(b);
}
END_TEST

/* Disks are drawn eight pixels of a row at once (sw_raster.c's disk_lanes,
 * a lane-by-lane copy of spr_ray_disk); drawn pixel by pixel through
 * spr_ray_disk itself (spr_swrast_scalar) every plane must be the same
 * bits.  4000 random splats (radii over 150x: under a pixel to 20 pixels
 * wide, normals any way, so culling drops some), a perspective 61x47 view
 * (odd: blocks past the row's end), three draws: a plain depth-tested one,
 * an additive eps-offset one with culling, and one masked by the first's
 * depth (SPEC 6.2 step 2). */
START_TEST(disk_lanes_are_the_scalar_test)
{
    spr_view v;
    spr_error err;
    tu_view(3.0, 40.0, 0.0, 1.0, 5.0, 61, 47, &v);
    const size_t n = 4000;
    spr_cloud c;
    ck_assert_int_eq(spr_cloud_alloc(&c, n), SPR_OK);
    uint64_t st = 20261202u;
    for (size_t i = 0; i < n; i++) {
        double nn[3], l = 0.0;
        for (int k = 0; k < 3; k++) c.pos[3 * i + k] = (float)(2.0 * tu_uniform(&st) - 1.0);
        do {
            l = 0.0;
            for (int k = 0; k < 3; k++) nn[k] = 2.0 * tu_uniform(&st) - 1.0, l += nn[k] * nn[k];
        } while (l < 1e-4 || l > 1.0);
        for (int k = 0; k < 3; k++) c.nrm[3 * i + k] = (float)(nn[k] / sqrt(l));
        c.radius[i] = (float)(0.002 * pow(150.0, tu_uniform(&st)));
        for (int k = 0; k < 3; k++) c.color[3 * i + k] = (float)tu_uniform(&st);
        c.alpha[i] = (float)(0.05 + 0.95 * tu_uniform(&st));
    }
    uint32_t half[2000];
    for (uint32_t i = 0; i < 2000; i++) half[i] = 2 * i + 1;
    float *plane[2][2][SPR_PLANE__COUNT];
    uint64_t generated[2] = {0, 0};
    const size_t np = (size_t)v.width * v.height;
    for (int scalar = 0; scalar < 2; scalar++) {
        spr_backend *b = spr_swrast_create(2, &err);
        ck_assert_ptr_nonnull(b);
        spr_swrast_scalar(b, scalar);
        ck_assert_int_eq(spr_backend_set_view(b, &v), SPR_OK);
        int t[2];
        for (int k = 0; k < 2; k++) ck_assert_int_eq(spr_backend_target_create(b, SPR_PLANES_OPAQUE | SPR_PLANE_BIT(SPR_PLANE_OPACITY), &t[k]), SPR_OK);
        spr_draw_stats ds;
        spr_draw_desc d = {.cloud = &c, .indices = half, .count = 2000};
        state(&d.state);
        ck_assert_int_eq(spr_backend_draw(b, t[0], &d, &ds), SPR_OK);
        generated[scalar] += ds.generated;
        d.indices = NULL;
        d.count = 0;
        d.state.depth_value = SPR_DEPTH_EPS_OFFSET;
        d.state.eps_t = 0.01f;
        d.state.cull_backfaces = 1;
        spr_pass_state_blend(&d.state, SPR_BLEND_ADD);
        ck_assert_int_eq(spr_backend_draw(b, t[1], &d, &ds), SPR_OK);
        generated[scalar] += ds.generated;
        d.depth_mask = 1;
        d.mask_target = t[0];
        d.state.cull_backfaces = 0;
        d.state.output = SPR_OUT_ALPHA;
        ck_assert_int_eq(spr_backend_draw(b, t[1], &d, &ds), SPR_OK);
        generated[scalar] += ds.generated;
        for (int k = 0; k < 2; k++)
            for (int p = 0; p < SPR_PLANE__COUNT; p++) {
                plane[scalar][k][p] = NULL;
                if (!((SPR_PLANES_OPAQUE | SPR_PLANE_BIT(SPR_PLANE_OPACITY)) & SPR_PLANE_BIT(p))) continue;
                plane[scalar][k][p] = malloc(np * 4 * sizeof(float));
                ck_assert_int_eq(spr_backend_read_plane(b, t[k], (spr_plane)p, plane[scalar][k][p]), SPR_OK);
            }
        spr_backend_destroy(b);
    }
    ck_assert_uint_eq(generated[0], generated[1]);
    ck_assert_uint_gt(generated[0], 20000);
    for (int k = 0; k < 2; k++)
        for (int p = 0; p < SPR_PLANE__COUNT; p++) {
            if (!plane[0][k][p]) continue;
            const size_t words = np * (size_t)spr_plane_channels((spr_plane)p);
            for (size_t i = 0; i < words; i++)
                ck_assert_msg(!memcmp(&plane[0][k][p][i], &plane[1][k][p][i], 4), "target %d plane %d word %zu: %a (8 at once) vs %a (one by one)", k, p, i,
                              plane[0][k][p][i], plane[1][k][p][i]);
            free(plane[0][k][p]);
            free(plane[1][k][p]);
        }
    spr_cloud_free(&c);
}
END_TEST

/* The CPU backend keeps its pixel rays while the view is set again with the
 * same matrices; another view of the same size must get its own: 4x1
 * pixels, orthographic, view height 0.5 (4 x 0.5 = 2 wide: pixel centres at
 * x = -0.75, -0.25, 0.25, 0.75) or 1 (centres -1.5, -0.5, 0.5, 1.5); a disk
 * at x = 0.6, y = 0 of radius 0.2 covers pixel 3 in the first, 2 in the
 * second. */
START_TEST(rays_follow_the_view)
{
    spr_error err;
    spr_backend *b = spr_swrast_create(1, &err);
    ck_assert_ptr_nonnull(b);
    spr_cloud c;
    tu_cloud(&c, 1, (double[]){0.6, 0.0, 0.0}, 0.2f);
    spr_draw_desc d = {.cloud = &c};
    state(&d.state);
    uint32_t count[16];
    for (int round = 0; round < 3; round++) {
        spr_view v;
        tu_view(2.0, 0.0, round == 1 ? 1.0 : 0.5, 1.0, 3.0, 4, 1, &v); /* view heights 0.5, 1, then 0.5 again */
        ck_assert_int_eq(spr_backend_set_view(b, &v), SPR_OK);
        int t;
        ck_assert_int_eq(spr_backend_target_create(b, SPR_PLANES_ALL, &t), SPR_OK);
        ck_assert_int_eq(spr_backend_draw(b, t, &d, NULL), SPR_OK);
        ck_assert_int_eq(spr_backend_read_plane(b, t, SPR_PLANE_COUNT, count), SPR_OK);
        const int want = round == 1 ? 2 : 3;
        for (int x = 0; x < 4; x++) ck_assert_msg(count[x] == (x == want ? 1u : 0u), "round %d pixel %d: %u", round, x, count[x]);
        spr_backend_target_destroy(b, t);
    }
    spr_cloud_free(&c);
    spr_backend_destroy(b);
}
END_TEST

START_TEST(average_composite)
{
    fixture f;
    setup(&f, 2);
    int t1, out;
    ck_assert_int_eq(spr_backend_target_create(f.b, SPR_PLANES_ALL, &t1), SPR_OK);
    ck_assert_int_eq(spr_backend_target_create(f.b, SPR_PLANE_BIT(SPR_PLANE_COLOR) | SPR_PLANE_BIT(SPR_PLANE_DEPTH), &out), SPR_OK);
    static const float c0[4] = {0.25f, 0.5f, 0.75f, 1.0f}, c1[4] = {0.5f, 0.0f, 0.25f, 0.5f};
    ck_assert_int_eq(spr_backend_clear(f.b, f.t, c0), SPR_OK);
    ck_assert_int_eq(spr_backend_clear(f.b, t1, c1), SPR_OK);
    spr_cloud c;
    const double xyz[3] = {0.0, 0.0, 0.0}; /* world z 0: t = 0.5; covers the 4 centre pixels (tu_hand_view) */
    tu_cloud(&c, 1, xyz, 0.75f);
    spr_draw_desc d = {.cloud = &c};
    spr_pass_state_defaults(&d.state);
    d.state.write_mask = SPR_WRITE_DEPTH; /* colour stays as cleared */
    ck_assert_int_eq(spr_backend_draw(f.b, t1, &d, NULL), SPR_OK);
    int in[2] = {f.t, t1};
    spr_composite_desc cd = {SPR_COMP_AVERAGE, in, 2, out, 0.0f, {0, 0, 0}, NULL, NULL, NULL};
    ck_assert_int_eq(spr_backend_composite(f.b, &cd), SPR_OK);
    ck_assert_int_eq(spr_backend_read_plane(f.b, out, SPR_PLANE_COLOR, f.color), SPR_OK);
    ck_assert_int_eq(spr_backend_read_plane(f.b, out, SPR_PLANE_DEPTH, f.depth), SPR_OK);
    static const float want[4] = {0.375f, 0.25f, 0.5f, 0.75f};
    for (int i = 0; i < 16; i++) {
        for (int ch = 0; ch < 4; ch++) ck_assert_float_eq(f.color[4 * i + ch], want[ch]);
        int x = i % 4, y = i / 4, centre = x >= 1 && x <= 2 && y >= 1 && y <= 2;
        ck_assert_float_eq(f.depth[i], centre ? 0.5f : 1.0f);
    }
    /* a target without a test plane takes no test-plane read */
    ck_assert_int_ne(spr_backend_read_plane(f.b, out, SPR_PLANE_TEST, f.test), SPR_OK);
    spr_cloud_free(&c);
    spr_backend_destroy(f.b);
}
END_TEST

/* The opacity plane (SPEC §6.2): w·α per fragment; with the constant
 * kernel (w = 1) and α = 0.5 a covered pixel holds 0.5 after one draw and
 * 1.0 after a second with `add`; `over` on it is refused. */
START_TEST(opacity_plane)
{
    fixture f;
    setup(&f, 2);
    spr_cloud c;
    const double xyz[3] = {0.0, 0.0, 0.0};
    tu_cloud(&c, 1, xyz, 0.75f);
    c.alpha[0] = 0.5f;
    spr_draw_desc d = {.cloud = &c};
    spr_pass_state_defaults(&d.state);
    d.state.kernel = SPR_KERNEL_CONSTANT;
    d.state.depth_func = SPR_FUNC_ALWAYS;
    d.state.write_mask = SPR_WRITE_OPACITY;
    spr_pass_state_blend(&d.state, SPR_BLEND_ADD);
    float op[16];
    for (int rep = 1; rep <= 2; rep++) {
        ck_assert_int_eq(spr_backend_draw(f.b, f.t, &d, NULL), SPR_OK);
        ck_assert_int_eq(spr_backend_read_plane(f.b, f.t, SPR_PLANE_OPACITY, op), SPR_OK);
        for (int i = 0; i < 16; i++) {
            int x = i % 4, y = i / 4, centre = x >= 1 && x <= 2 && y >= 1 && y <= 2;
            ck_assert_float_eq(op[i], centre ? 0.5f * (float)rep : 0.0f);
        }
    }
    d.state.blend_alpha = SPR_BLEND_OVER;
    ck_assert_int_eq(spr_backend_draw(f.b, f.t, &d, NULL), SPR_E_ARG);
    spr_cloud_free(&c);
    spr_backend_destroy(f.b);
}
END_TEST

/* Splats straddling the 32×32 tile boundaries of an 80×70 view (3×3 tiles,
 * the last ones partial): the count, id and test planes equal a per-pixel
 * brute force over every splat in submission order — binning and clipping
 * to tiles must not lose, duplicate or reorder a fragment.  Depth LESS on
 * d_f: the test plane holds the smallest t, the id plane the first splat
 * reaching it (ties keep the earlier). */
START_TEST(splats_across_tile_boundaries)
{
    const int W = 80, H = 70;
    spr_view v;
    tu_hand_view(W, H, &v);
    spr_error err;
    spr_backend *b = spr_swrast_create(3, &err);
    ck_assert_ptr_nonnull(b);
    ck_assert_int_eq(spr_backend_set_view(b, &v), SPR_OK);
    int t;
    ck_assert_int_eq(spr_backend_target_create(b, SPR_PLANES_OPAQUE, &t), SPR_OK);
    /* world x of pixel column 32 and 64: −1 + 32·2/80 = −0.2, 0.6; rows 32, 64: −1 + 64/70, −1 + 128/70 */
    const double bx[3] = {-0.2, 0.6, 0.95}, by[3] = {-1.0 + 64.0 / 70.0, -1.0 + 128.0 / 70.0, -0.97};
    double xyz[3 * 27];
    size_t n = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++, n++) {
                xyz[3 * n] = bx[i] + 0.011 * (k - 1);
                xyz[3 * n + 1] = by[j] - 0.013 * (k - 1);
                xyz[3 * n + 2] = 0.1 * (k - 1) + 0.01 * i;
            }
    spr_cloud c;
    tu_cloud(&c, n, xyz, 0.09f);
    for (size_t i = 0; i < n; i += 4) { /* some tilted: elliptical footprints across the boundary */
        float *nr = c.nrm + 3 * i;
        nr[0] = 0.6f; nr[1] = 0.0f; nr[2] = 0.8f;
    }
    spr_draw_desc d = {.cloud = &c};
    spr_pass_state_defaults(&d.state);
    d.state.depth_write = 1;
    spr_draw_stats st;
    ck_assert_int_eq(spr_backend_draw(b, t, &d, &st), SPR_OK);
    size_t np = (size_t)W * H;
    uint32_t *id = malloc(np * 4), *count = malloc(np * 4);
    float *test = malloc(np * 4);
    ck_assert_int_eq(spr_backend_read_plane(b, t, SPR_PLANE_ID, id), SPR_OK);
    ck_assert_int_eq(spr_backend_read_plane(b, t, SPR_PLANE_COUNT, count), SPR_OK);
    ck_assert_int_eq(spr_backend_read_plane(b, t, SPR_PLANE_TEST, test), SPR_OK);
    uint64_t gen = 0;
    int crossing = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float o0[3], dd[3], zmin = 1.0f;
            uint32_t want_id = UINT32_MAX, want_count = 0;
            spr_pixel_ray(&v, x, y, o0, dd);
            for (size_t i = 0; i < n; i++) {
                float tt, rho2, den;
                if (!spr_ray_disk(o0, dd, c.pos + 3 * i, c.nrm + 3 * i, c.radius[i], &tt, &rho2, &den)) continue;
                gen++;
                if (tt < zmin) { zmin = tt; want_id = (uint32_t)i; want_count++; }
            }
            size_t p = (size_t)y * W + x;
            if (want_count && (x % 32 == 0 || x % 32 == 31 || y % 32 == 0 || y % 32 == 31)) crossing++;
            if (id[p] != want_id || count[p] != want_count || test[p] != zmin)
                ck_abort_msg("pixel (%d,%d): id %u count %u test %g, brute force %u %u %g", x, y, id[p], count[p], test[p], want_id,
                             want_count, zmin);
        }
    ck_assert_uint_eq(st.generated, gen);
    ck_assert_int_gt(crossing, 50); /* the scene really sits on the boundaries */
    free(id);
    free(count);
    free(test);
    spr_cloud_free(&c);
    spr_backend_destroy(b);
}
END_TEST

START_TEST(backend_rejects_bad_calls)
{
    fixture f;
    setup(&f, 1);
    spr_cloud c;
    tu_cloud(&c, 1, (double[]){0, 0, 0}, 0.5f);
    spr_draw_desc d = {.cloud = &c};
    spr_pass_state_defaults(&d.state);
    ck_assert_int_eq(spr_backend_draw(f.b, 99, &d, NULL), SPR_E_ARG);
    uint32_t bad = 5;
    d.indices = &bad;
    d.count = 1;
    ck_assert_int_eq(spr_backend_draw(f.b, f.t, &d, NULL), SPR_E_ARG);
    d.indices = NULL;
    d.state.depth_value = SPR_DEPTH_VORONOI;
    d.state.lowres.d_max = d.state.lowres.d_min;
    ck_assert_int_eq(spr_backend_draw(f.b, f.t, &d, NULL), SPR_E_ARG);
    spr_composite_desc cd = {SPR_COMP_NORMALIZE, &f.t, 1, f.t, 0.0f, {0, 0, 0}, NULL, NULL, NULL};
    ck_assert_int_eq(spr_backend_composite(f.b, &cd), SPR_E_ARG);
    spr_cloud_free(&c);
    spr_backend_destroy(f.b);
}
END_TEST

Suite *make_raster_suite(void)
{
    Suite *s = suite_create("raster");
    TCase *tc = tcase_create("raster");
    tcase_add_test(tc, one_splat_covers_four_pixels);
    tcase_add_test(tc, closed_disk_rim_pixels);
    tcase_add_test(tc, edge_on_and_behind_camera_draw_nothing);
    tcase_add_test(tc, depth_test_nearer_wins_ties_keep_first);
    tcase_add_test(tc, lequal_and_add_blend);
    tcase_add_test(tc, backface_culling);
    tcase_add_test(tc, thousands_of_fragments_in_submission_order);
    tcase_add_test(tc, backend_rejects_bad_calls);
    tcase_add_test(tc, average_composite);
    tcase_add_test(tc, kept_bins_only_for_the_same_draw);
    tcase_add_loop_test(tc, created_targets_read_as_cleared, 0, 2);
    tcase_add_loop_test(tc, pending_tiles_composite_as_cleared, 0, 2);
    tcase_add_test(tc, disk_lanes_are_the_scalar_test);
    tcase_add_test(tc, rays_follow_the_view);
    tcase_add_test(tc, opacity_plane);
    tcase_add_test(tc, splats_across_tile_boundaries);
    suite_add_tcase(s, tc);
    return s;
}
