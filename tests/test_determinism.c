/* test_determinism.c — same input, same bits: every plane of every pass for
 * 1, 2 and 7 threads, both algorithms, on the real bunny. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "spr_domain.h"
#include "spr_bsp.h"
#include <math.h>
#include <omp.h>
#include "test_util.h"

typedef struct hasher {
    uint64_t h;
    int passes;
} hasher;

static void fnv(uint64_t *h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) { *h ^= p[i]; *h *= 0x100000001b3ull; }
}

static void hash_hook(void *user, spr_backend *b, const spr_pass_info *info)
{
    hasher *hs = user;
    size_t np = (size_t)b->view.width * b->view.height;
    float *buf = malloc(np * 4 * sizeof(float));
    for (int p = 0; p < SPR_PLANE__COUNT; p++) {
        if (!(spr_backend_target_planes(b, info->target) & SPR_PLANE_BIT(p))) continue;
        ck_assert_int_eq(spr_backend_read_plane(b, info->target, (spr_plane)p, buf), SPR_OK);
        fnv(&hs->h, buf, np * spr_plane_channels((spr_plane)p) * sizeof(float));
    }
    fnv(&hs->h, &info->stats, sizeof info->stats);
    hs->passes++;
    free(buf);
}

START_TEST(bunny_bits_independent_of_threads)
{
    tu_bunny bn;
    tu_bunny_scene(&bn, 400, 300, 0.4);
    for (int variant = 0; variant < 4; variant++) {
        uint64_t first = 0;
        static const int thread_counts[3] = {1, 2, 7};
        for (int ti = 0; ti < 3; ti++) {
            int threads = thread_counts[ti];
            omp_set_num_threads(threads); /* the library's own parallel loops (the BSP traversal of transparent1) too */
            hasher hs = {0xcbf29ce484222325ull, 0};
            spr_render_desc d = {.algo = variant == 0 ? SPR_ALGO_PBR2P1 : variant == 3 ? SPR_ALGO_TRANSPARENT1 : SPR_ALGO_DEFERRED,
                                 .voronoi = variant == 2, .groups = &bn.groups, .hook = hash_hook, .hook_user = &hs, .alpha = variant == 3 ? 0.5f : 0.0f};
            spr_render_result r;
            tu_render(&bn.view, &bn.cloud, &d, threads, &r);
            fnv(&hs.h, r.rgba, (size_t)r.width * r.height * 4 * sizeof(float));
            printf("determinism: %s%s threads %d: %d passes, hash %016llx\n", spr_algo_name(d.algo), d.voronoi ? "+voronoi" : "",
                   threads, hs.passes, (unsigned long long)hs.h);
            if (ti == 0) first = hs.h;
            else ck_assert_msg(hs.h == first, "%d threads differ from 1 thread", threads);
            spr_render_result_free(&r);
        }
    }
    omp_set_num_threads(omp_get_num_procs());
    tu_bunny_free(&bn);
}
END_TEST

START_TEST(mgc_labels_independent_of_threads)
{
    spr_cloud c;
    tu_load("meshes/bunny00.off", &c);
    int32_t *a = malloc(c.n * sizeof *a), *b = malloc(c.n * sizeof *b);
    spr_mgc_desc md;
    spr_mgc_defaults(&md);
    spr_group_stats s1, s2;
    spr_error err;
    md.threads = 1;
    ck_assert_int_eq(spr_group_mgc(&c, &md, a, &s1, &err), SPR_OK);
    md.threads = 2;
    ck_assert_int_eq(spr_group_mgc(&c, &md, b, &s2, &err), SPR_OK);
    ck_assert_mem_eq(a, b, c.n * sizeof *a);
    free(a);
    free(b);
    spr_cloud_free(&c);
}
END_TEST

/* SPEC 5.6 by the book: split at the median of the longest extent (a full
 * sort by (coordinate, index)), ≤ 64 per leaf, nodes numbered depth first. */
static const spr_cloud *ref_cloud;
static int ref_axis;
static int ref_cmp(const void *a, const void *b)
{
    uint32_t i = *(const uint32_t *)a, j = *(const uint32_t *)b;
    float x = ref_cloud->pos[3 * (size_t)i + ref_axis], y = ref_cloud->pos[3 * (size_t)j + ref_axis];
    if (x != y) return x < y ? -1 : 1;
    return (i > j) - (i < j);
}
static int32_t ref_build(spr_bsp *t, uint32_t first, uint32_t count)
{
    int32_t id = (int32_t)t->n_nodes++;
    spr_bsp_node *nd = &t->nodes[id];
    memset(nd, 0, sizeof *nd);
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t k = first; k < first + count; k++)
        for (int a = 0; a < 3; a++) {
            float v = ref_cloud->pos[3 * (size_t)t->order[k] + a];
            lo[a] = v < lo[a] ? v : lo[a];
            hi[a] = v > hi[a] ? v : hi[a];
        }
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    if (count <= SPR_BSP_LEAF || !(hi[axis] > lo[axis])) {
        nd->axis = -1, nd->first = first, nd->count = count;
        double s[3] = {0, 0, 0};
        for (uint32_t k = first; k < first + count; k++) {
            for (int a = 0; a < 3; a++) s[a] += ref_cloud->nrm[3 * (size_t)t->order[k] + a];
            t->leaf_of[t->order[k]] = (uint32_t)id;
        }
        double l = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
        for (int a = 0; a < 3; a++) nd->normal[a] = l > 0.0 ? (float)(s[a] / l) : (a == 2 ? 1.0f : 0.0f);
        return id;
    }
    ref_axis = axis;
    qsort(t->order + first, count, sizeof(uint32_t), ref_cmp);
    float split = ref_cloud->pos[3 * (size_t)t->order[first + count / 2] + axis];
    int32_t l = ref_build(t, first, count / 2), r = ref_build(t, first + count / 2, count - count / 2);
    nd = &t->nodes[id];
    nd->axis = axis, nd->split = split, nd->left = l, nd->right = r;
    return id;
}

/* The parallel BSP build (selection, spliced subtrees) is the tree above,
 * byte for byte, for 1, 2 and 7 threads. */
static size_t bsp_matches_the_sorting_build(spr_cloud *c)
{
    spr_bsp ref = {0};
    ref.n = c->n;
    ref.nodes = malloc(c->n * sizeof *ref.nodes); /* ≥ 2n/64 nodes */
    ref.order = malloc(c->n * sizeof *ref.order);
    ref.leaf_of = malloc(c->n * sizeof *ref.leaf_of);
    for (size_t i = 0; i < c->n; i++) ref.order[i] = (uint32_t)i;
    ref_cloud = c;
    ref_build(&ref, 0, (uint32_t)c->n);
    static const int threads[] = {1, 2, 7};
    for (int k = 0; k < 3; k++) {
        omp_set_num_threads(threads[k]);
        spr_bsp t;
        spr_error err;
        ck_assert_int_eq(spr_bsp_build(c, &t, &err), SPR_OK);
        ck_assert_uint_eq(t.n_nodes, ref.n_nodes);
        ck_assert_mem_eq(t.nodes, ref.nodes, t.n_nodes * sizeof *t.nodes);
        ck_assert_mem_eq(t.order, ref.order, c->n * sizeof *t.order);
        ck_assert_mem_eq(t.leaf_of, ref.leaf_of, c->n * sizeof *t.leaf_of);
        spr_bsp_free(&t);
    }
    omp_set_num_threads(omp_get_num_procs());
    const size_t nodes = ref.n_nodes;
    spr_bsp_free(&ref);
    return nodes;
}

START_TEST(bsp_equals_the_sorting_build_on_any_threads)
{
    spr_cloud c = tu_builtin("builtin:sphere", tu_small() ? 60000 : 250000);
    size_t nodes = bsp_matches_the_sorting_build(&c);
    printf("bsp: %zu splats, %zu nodes: the parallel build equals the sorting build on 1, 2 and 7 threads\n", c.n, nodes);
    /* the same centres on a grid of 1/8 (ties everywhere: the ids decide),
     * zeros signed both ways (−0 and +0 compare equal) */
    size_t zeros = 0;
    for (size_t i = 0; i < c.n; i++)
        for (int a = 0; a < 3; a++) {
            float *v = &c.pos[3 * i + a];
            *v = roundf(*v * 8.0f) / 8.0f;
            if (*v == 0.0f) *v = (i & 1) ? -0.0f : 0.0f, zeros++;
        }
    nodes = bsp_matches_the_sorting_build(&c);
    printf("bsp: the same on a 1/8 grid with %zu signed zeros, %zu nodes\n", zeros, nodes);
    spr_cloud_free(&c);
}
END_TEST

/* SPEC 7: the bunny's level-6 primitives built with 1, 2 and 7 threads are
 * the same bytes, and every domain method renders the same bits on 1, 2
 * and 7 CPU threads (the fragment lists of prefix included). */
START_TEST(domain_bits_independent_of_threads)
{
    tu_bunny bn;
    tu_bunny_scene(&bn, 200, 160, 0.4);
    spr_decomp_desc dd;
    spr_decomp_defaults(&dd);
    spr_decomp dc = {0};
    spr_error err = {0};
    ck_assert_msg(spr_decompose(&bn.cloud, &dd, &dc, &err) == SPR_OK, "%s", err.msg);
    ck_assert_int_gt(dc.levels, 6);
    spr_rects r[3];
    static const int thread_counts[3] = {1, 2, 7};
    for (int ti = 0; ti < 3; ti++) {
        spr_prims_desc pd;
        spr_prims_defaults(&pd);
        pd.threads = thread_counts[ti];
        spr_prims_stats st;
        ck_assert_msg(spr_domain_prims(&bn.cloud, &dc.basis[6], &pd, &r[ti], &st, &err) == SPR_OK, "%s", err.msg);
        if (ti == 0) continue;
        ck_assert(r[ti].n == r[0].n && r[ti].n_texels == r[0].n_texels);
        ck_assert(!memcmp(r[ti].f, r[0].f, r[0].n * SPR_RECT_FLOATS * sizeof(float)));
        ck_assert(!memcmp(r[ti].i, r[0].i, r[0].n * SPR_RECTI_COUNT * sizeof(uint32_t)));
        ck_assert(!memcmp(r[ti].texels, r[0].texels, r[0].n_texels * 4 * sizeof(float)));
        ck_assert(!memcmp(r[ti].nbr, r[0].nbr, r[0].n * spr_rects_words(r[0].n) * sizeof(uint32_t)));
    }
    for (int al = SPR_ALGO_DOMAIN_BLENDALL; al <= SPR_ALGO_DOMAIN_PREFIX; al++) {
        uint64_t first = 0;
        for (int ti = 0; ti < 3; ti++) {
            hasher hs = {0xcbf29ce484222325ull, 0};
            spr_render_desc d = {.algo = (spr_algo)al, .rects = &r[0], .sampling = SPR_SAMPLE_LINEAR, .hook = hash_hook, .hook_user = &hs};
            spr_render_result res;
            tu_render(&bn.view, &bn.cloud, &d, thread_counts[ti], &res);
            fnv(&hs.h, res.rgba, (size_t)res.width * res.height * 4 * sizeof(float));
            if (ti == 0) first = hs.h;
            else ck_assert_msg(hs.h == first, "%s: %d threads differ from 1 thread", spr_algo_name(d.algo), thread_counts[ti]);
            spr_render_result_free(&res);
        }
        printf("determinism: %s, %zu rectangles, 1/2/7 threads: hash %016llx\n", spr_algo_name((spr_algo)al), r[0].n, (unsigned long long)first);
    }
    for (int ti = 0; ti < 3; ti++) spr_rects_free(&r[ti]);
    spr_decomp_free(&dc);
    tu_bunny_free(&bn);
}
END_TEST

Suite *make_determinism_suite(void)
{
    Suite *s = suite_create("determinism");
    TCase *tc = tcase_create("determinism");
    tcase_set_timeout(tc, 600);
    tcase_add_test(tc, bunny_bits_independent_of_threads);
    tcase_add_test(tc, mgc_labels_independent_of_threads);
    tcase_add_test(tc, bsp_equals_the_sorting_build_on_any_threads);
    tcase_add_test(tc, domain_bits_independent_of_threads);
    suite_add_tcase(s, tc);
    return s;
}
