/* test_group.c — SPEC §5.1 MGC (checked by brute force) and §5.3 hash groups. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "spr_overlap.h"
#include "spr__group.h"
#include "spr__spatial.h"
#include "test_util.h"

/* SPEC §5.1's relaxation 1 as written, from splat i's side:
 * n_i·n_j ≥ cos 5° and |(p_j − p_i)·n_i| ≤ 0.05·r_i. */
static int coplanar_from(const spr_cloud *c, size_t i, size_t j)
{
    const float *pi = c->pos + 3 * i, *pj = c->pos + 3 * j, *ni = c->nrm + 3 * i, *nj = c->nrm + 3 * j;
    double nn = 0.0, h = 0.0;
    for (int k = 0; k < 3; k++) {
        nn += (double)ni[k] * nj[k];
        h += ((double)pj[k] - pi[k]) * ni[k];
    }
    return nn >= cos(5.0 * M_PI / 180.0) && fabs(h) <= 0.05 * c->radius[i];
}

/* Eq. 5 with the relaxations of SPEC §5.1: an edge when |p_i − p_j| <
 * c·(r_i + r_j) (3), unless the normals are opposite (2) or the pair is
 * coplanar (1) — from both sides, the symmetric reading docs/grouping.md
 * records, since a conflict cannot depend on which splat is called i. */
static int conflict_by_spec(const spr_cloud *c, size_t i, size_t j, double cf, int cop, int opp)
{
    double dist2 = 0.0, nn = 0.0;
    for (int k = 0; k < 3; k++) {
        double q = (double)c->pos[3 * j + k] - c->pos[3 * i + k];
        dist2 += q * q;
        nn += (double)c->nrm[3 * i + k] * c->nrm[3 * j + k];
    }
    if (!(sqrt(dist2) < cf * ((double)c->radius[i] + c->radius[j]))) return 0;
    if (opp && nn < 0.0) return 0;
    if (cop && coplanar_from(c, i, j) && coplanar_from(c, j, i)) return 0;
    return 1;
}

typedef struct vdeg_t { size_t deg, idx; } vdeg_t;
static int by_deg_desc(const void *a, const void *b)
{
    const vdeg_t *x = a, *y = b;
    if (x->deg != y->deg) return x->deg < y->deg ? 1 : -1;
    return (x->idx > y->idx) - (x->idx < y->idx);
}

/* The whole of SPEC §5.1 replayed by brute force: every pair's edge from the
 * rule above, vertices by non-increasing degree (ties by index), each the
 * smallest colour unused by its already coloured neighbours — the labels
 * must be exactly these. */
static void check_mgc_cloud(const char *model, spr_cloud c, double cf, int cop, int opp)
{
    spr_mgc_desc d;
    spr_mgc_defaults(&d);
    d.c = cf;
    d.relax_coplanar = cop;
    d.relax_opposite = opp;
    int32_t *lab = malloc(c.n * sizeof *lab);
    spr_group_stats st;
    spr_error err;
    ck_assert_int_eq(spr_group_mgc(&c, &d, lab, &st, &err), SPR_OK);
    size_t n = c.n, edges = 0, cap = 1024;
    uint32_t *ei = malloc(cap * 2 * sizeof *ei);
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 1; j < n; j++) { /* plain ifs in the hot loops: every ck_assert records a mark point */
            if (!conflict_by_spec(&c, i, j, cf, cop, opp)) continue;
            if (edges == cap) ei = realloc(ei, (cap *= 2) * 2 * sizeof *ei);
            ei[2 * edges] = (uint32_t)i;
            ei[2 * edges + 1] = (uint32_t)j;
            edges++;
        }
    ck_assert_uint_eq(edges, st.edges); /* the FLANN graph found every edge */
    size_t *start = calloc(n + 1, sizeof *start), *fill = calloc(n, sizeof *fill);
    uint32_t *adj = malloc((2 * edges + 1) * sizeof *adj);
    for (size_t e = 0; e < edges; e++) { start[ei[2 * e] + 1]++; start[ei[2 * e + 1] + 1]++; }
    for (size_t i = 0; i < n; i++) start[i + 1] += start[i];
    for (size_t e = 0; e < edges; e++) {
        adj[start[ei[2 * e]] + fill[ei[2 * e]]++] = ei[2 * e + 1];
        adj[start[ei[2 * e + 1]] + fill[ei[2 * e + 1]]++] = ei[2 * e];
    }
    vdeg_t *order = malloc(n * sizeof *order);
    size_t maxdeg = 0;
    for (size_t i = 0; i < n; i++) {
        order[i] = (vdeg_t){start[i + 1] - start[i], i};
        if (order[i].deg > maxdeg) maxdeg = order[i].deg;
    }
    qsort(order, n, sizeof *order, by_deg_desc);
    int32_t *want = malloc(n * sizeof *want);
    for (size_t i = 0; i < n; i++) want[i] = -1;
    unsigned char *used = malloc(maxdeg + 2);
    int K = 0;
    for (size_t o = 0; o < n; o++) {
        size_t v = order[o].idx;
        memset(used, 0, maxdeg + 2);
        for (size_t k = start[v]; k < start[v + 1]; k++)
            if (want[adj[k]] >= 0 && (size_t)want[adj[k]] <= maxdeg) used[want[adj[k]]] = 1;
        int col = 0;
        while (used[col]) col++;
        want[v] = col;
        if (col + 1 > K) K = col + 1;
    }
    for (size_t i = 0; i < n; i++)
        if (lab[i] != want[i]) ck_abort_msg("%s: splat %zu has group %d, SPEC 5.1's largest-first colouring gives %d", model, i, lab[i], want[i]);
    ck_assert_int_eq(st.K, K);
    ck_assert_int_eq(st.max_degree, (int)maxdeg);
    printf("group: MGC %s n=%zu c=%.1f relax=%d%d: K=%d max degree %d avg %.2f, %zu edges and every label checked by brute force\n",
           model, n, cf, cop, opp, st.K, st.max_degree, st.avg_degree, edges);
    free(ei);
    free(start);
    free(fill);
    free(adj);
    free(order);
    free(want);
    free(used);
    free(lab);
    spr_cloud_free(&c);
}

static void check_mgc(const char *model, size_t n, double cf, int cop, int opp)
{
    check_mgc_cloud(model, tu_builtin(model, n), cf, cop, opp);
}

START_TEST(mgc_bunny_has_no_conflicts)
{
    spr_cloud c;
    tu_load("meshes/bunny00.off", &c);
    check_mgc_cloud("bunny00.off", c, 0.4, 1, 1);
}
END_TEST

START_TEST(mgc_groups_have_no_conflicts)
{
    check_mgc("builtin:sphere", 3000, 1.0, 1, 1);
    check_mgc("builtin:sphere", 3000, 1.0, 0, 0);
    check_mgc("builtin:torus", 3000, 0.6, 1, 1);
    check_mgc("builtin:cube", 2400, 1.0, 1, 1);  /* coplanar faces: relaxation 1 at work */
    check_mgc("builtin:cube", 2400, 0.4, 0, 1);
    check_mgc("builtin:planes", 2000, 1.0, 0, 0);
}
END_TEST

START_TEST(mgc_k_falls_with_c)
{
    spr_cloud c = tu_builtin("builtin:sphere", 20000);
    int32_t *lab = malloc(c.n * sizeof *lab);
    int prev = 1 << 30;
    for (double cf = 1.0; cf > 0.3; cf -= 0.2) {
        spr_mgc_desc d;
        spr_mgc_defaults(&d);
        d.c = cf;
        spr_group_stats st;
        spr_error err;
        ck_assert_int_eq(spr_group_mgc(&c, &d, lab, &st, &err), SPR_OK);
        ck_assert_int_le(st.K, prev);
        prev = st.K;
    }
    free(lab);
    spr_cloud_free(&c);
}
END_TEST

START_TEST(hash_step_and_table)
{
    ck_assert_int_eq(spr_hash_step(8), 3);
    spr_cloud c = tu_builtin("builtin:torus", 5000);
    for (size_t i = 0; i < c.n; i++) c.pos[3 * i] -= 3.0f; /* negative coordinates too */
    int32_t *lab = malloc(c.n * sizeof *lab);
    spr_group_stats st;
    spr_error err;
    spr_hash_desc hd;
    spr_hash_defaults(&hd);
    hd.axis = SPR_HASH_AXIS_NORMAL; /* Eq. 9 with the splat's own normal */
    ck_assert_int_eq(spr_group_hash(&c, &hd, lab, &st, &err), SPR_OK);
    for (size_t i = 0; i < c.n; i++) {
        const float *n = c.nrm + 3 * i, *p = c.pos + 3 * i;
        int d = fabsf(n[0]) >= fabsf(n[1]) && fabsf(n[0]) >= fabsf(n[2]) ? 0 : (fabsf(n[1]) >= fabsf(n[2]) ? 1 : 2);
        double x = floorf(p[(d + 1) % 3] / c.radius[i]), y = floorf(p[(d + 2) % 3] / c.radius[i]); /* Eq. 9 in float */
        double m = fmod(x + 3.0 * y, 8.0);
        if (m < 0) m += 8.0;
        if (lab[i] != (int)m) ck_abort_msg("splat %zu: group %d, Eq. 9 gives %d", i, lab[i], (int)m); /* Fig. 9's table */
    }
    free(lab);
    spr_cloud_free(&c);
}
END_TEST

START_TEST(groups_file_round_trip_and_errors)
{
    char path[] = "/tmp/spr_groups_XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    close(fd);
    int32_t lab[5] = {0, 2, 1, 2, 0}, back[5];
    spr_error err;
    ck_assert_int_eq(spr_groups_write(path, lab, 5, &err), SPR_OK);
    ck_assert_int_eq(spr_groups_read(path, 5, back, &err), SPR_OK);
    for (int i = 0; i < 5; i++) ck_assert_int_eq(back[i], lab[i]);
    ck_assert_int_eq(spr_groups_read(path, 6, back, &err), SPR_E_TRUNCATED);
    ck_assert_ptr_nonnull(strstr(err.msg, path));
    spr_groups g;
    ck_assert_int_eq(spr_groups_from_labels(lab, 5, 0, &g, &err), SPR_OK);
    ck_assert_int_eq(g.K, 3);
    ck_assert_uint_eq(g.start[1], 2); /* group 0: splats 0 and 4, in submission order */
    ck_assert_uint_eq(g.members[0], 0);
    ck_assert_uint_eq(g.members[1], 4);
    spr_groups_free(&g);
    FILE *f = fopen(path, "w");
    fputs("0\n1\nx\n", f);
    fclose(f);
    ck_assert_int_eq(spr_groups_read(path, 3, back, &err), SPR_E_FORMAT);
    ck_assert_ptr_nonnull(strstr(err.msg, ":3:"));
    /* memberships: splat 1 in two groups; splat 2 in none is an error */
    f = fopen(path, "w");
    fputs("0 1\n1 0\n1 1\n2 0\n", f);
    fclose(f);
    int32_t lab3[3];
    ck_assert_int_eq(spr_groups_read_any(path, 3, &g, lab3, &err), SPR_OK);
    ck_assert_int_eq(g.K, 2);
    ck_assert_uint_eq(g.start[1], 2);         /* group 0: splats 1, 2 */
    ck_assert_uint_eq(g.start[2] - g.start[1], 2); /* group 1: splats 0, 1 */
    ck_assert_uint_eq(g.members[2], 0);
    ck_assert_int_eq(lab3[1], 0);
    spr_groups_free(&g);
    f = fopen(path, "w");
    fputs("0 1\n1 0\n", f);
    fclose(f);
    ck_assert_int_eq(spr_groups_read_any(path, 3, &g, lab3, &err), SPR_E_VALUE);
    ck_assert_ptr_nonnull(strstr(err.msg, "splat 2 is in no group"));
    remove(path);
}
END_TEST

/* A_ij of SPEC 5.2 (Eq. 8) on hand-made pairs: disk i (index 0) against
 * disk j (index 1).  Where every sample must count the area is the whole
 * disk, π r_i², exactly; where none can, 0; partial cases against their
 * closed forms within the sampling error of 256 samples. */
static float area_of(const double pi[3], const double ni[3], double ri, const double pj[3], const double nj[3], double rj, double eps)
{
    double xyz[6] = {pi[0], pi[1], pi[2], pj[0], pj[1], pj[2]};
    spr_cloud c;
    tu_cloud(&c, 2, xyz, 1.0f);
    for (int k = 0; k < 3; k++) {
        c.nrm[k] = (float)ni[k];
        c.nrm[3 + k] = (float)nj[k];
    }
    c.radius[0] = (float)ri;
    c.radius[1] = (float)rj;
    uint32_t j = 1;
    float a;
    spr_overlap_areas(&c, 0, &j, 1, eps, &a);
    spr_cloud_free(&c);
    return a;
}

START_TEST(overlap_area_hand_cases)
{
    const double z[3] = {0, 0, 1}, x[3] = {1, 0, 0}, o[3] = {0, 0, 0};
    const float full = (float)(M_PI * 0.25);
    /* coplanar, i inside j: far from the edge, and within 1e-9 of it (no shortcut there) */
    ck_assert_float_eq(area_of((double[3]){0.3, 0, 0}, z, 0.5, o, z, 1.0, 0.1), full);
    ck_assert_float_eq(area_of((double[3]){0.5 - 1e-9, 0, 0}, z, 0.5, o, z, 1.0, 0.1), full);
    /* parallel, half ε above: inside; 2ε above: nothing */
    ck_assert_float_eq(area_of((double[3]){0.2, 0, 0.05}, z, 0.5, o, z, 1.0, 0.1), full);
    ck_assert_float_eq(area_of((double[3]){0.2, 0, 0.2}, z, 0.5, o, z, 1.0, 0.1), 0.0f);
    /* coplanar and apart: 0, also just beyond touching */
    ck_assert_float_eq(area_of((double[3]){2.0, 0, 0}, z, 0.5, o, z, 1.0, 0.1), 0.0f);
    ck_assert_float_eq(area_of((double[3]){1.5 + 1e-9, 0, 0}, z, 0.5, o, z, 1.0, 0.1), 0.0f);
    /* coplanar unit disks at distance 1: the lens 2 acos(1/2) − (1/2)√3 = 1.2284 */
    const double lens = 2.0 * acos(0.5) - 0.5 * sqrt(3.0);
    float a = area_of((double[3]){1.0, 0, 0}, z, 1.0, o, z, 1.0, 0.1);
    printf("overlap area: lens of two unit disks at distance 1: %.4f sampled, %.4f exact\n", a, lens);
    ck_assert_double_lt(fabs(a - lens) / lens, 0.03);
    /* disk i on edge (normal along x) through j's centre, j much larger: the
     * part of a unit disk within a slab |h| ≤ 0.25, 2(t√(1−t²) + asin t) for t = 0.25 */
    const double slab = 2.0 * (0.25 * sqrt(1.0 - 0.0625) + asin(0.25));
    a = area_of(o, x, 1.0, o, z, 10.0, 0.25);
    printf("overlap area: unit disk edge-on within eps 0.25: %.4f sampled, %.4f exact\n", a, slab);
    ck_assert_double_lt(fabs(a - slab) / slab, 0.03);
}
END_TEST

/* The 256-sample count of SPEC §5.2 as it was written before rings were
 * decided whole (commit cde1253): every sample of the pattern tested, in
 * the same arithmetic on the same frame, so its areas are the bits
 * spr_overlap_areas must give. */
static int sample_loop_count(const spr_cloud *c, size_t i, size_t j, double eps, const double pu[256], const double pv[256])
{
    double e1[3], e2[3], ri = c->radius[i], rj = c->radius[j];
    spr__disk_frame(c->nrm + 3 * i, e1, e2);
    const float *pi = c->pos + 3 * i, *pj = c->pos + 3 * j, *nj = c->nrm + 3 * j;
    double D[3];
    for (int k = 0; k < 3; k++) D[k] = (double)pi[k] - pj[k];
    double h0 = D[0] * nj[0] + D[1] * nj[1] + D[2] * nj[2];
    double a = ri * (e1[0] * nj[0] + e1[1] * nj[1] + e1[2] * nj[2]), b = ri * (e2[0] * nj[0] + e2[1] * nj[1] + e2[2] * nj[2]);
    double D2 = D[0] * D[0] + D[1] * D[1] + D[2] * D[2];
    double c1 = 2.0 * ri * (D[0] * e1[0] + D[1] * e1[1] + D[2] * e1[2]), c2 = 2.0 * ri * (D[0] * e2[0] + D[1] * e2[1] + D[2] * e2[2]);
    double ri2 = ri * ri, rj2 = rj * rj;
    int hit = 0;
    for (int s = 0; s < 256; s++) {
        double h = h0 + pu[s] * a + pv[s] * b;
        double q2 = D2 + pu[s] * c1 + pv[s] * c2 + ri2 * (pu[s] * pu[s] + pv[s] * pv[s]);
        hit += (fabs(h) <= eps) & (q2 - h * h <= rj2);
    }
    return hit;
}

/* Every ordered pair of a random set (radii over a 50× range, random,
 * near-parallel and axis normals so that coplanar pairs and exact ties
 * occur, some centres shared) at five ε: spr_overlap_areas gives the bits
 * of the plain sample loop. */
START_TEST(overlap_areas_are_the_sample_loop)
{
    double pu[256], pv[256];
    for (int a = 0; a < 16; a++)
        for (int b = 0; b < 16; b++) {
            double rho = sqrt((a + 0.5) / 16.0), th = 2.0 * M_PI * (b + 0.5 * (a & 1) + 0.5) / 16.0;
            pu[16 * a + b] = rho * cos(th);
            pv[16 * a + b] = rho * sin(th);
        }
    const size_t n = tu_small() ? 300 : 1000;
    spr_cloud c;
    double *zero = calloc(3 * n, sizeof *zero);
    ck_assert(zero);
    tu_cloud(&c, n, zero, 1.0f);
    free(zero);
    uint64_t st = 0x9E3779B97F4A7C15ull;
#define RND() ((st = st * 6364136223846793005ull + 1442695040888963407ull), (double)(st >> 11) / 9007199254740992.0)
    for (size_t i = 0; i < n; i++) {
        if (i % 7 == 6) { /* a shared centre */
            memcpy(c.pos + 3 * i, c.pos + 3 * (i - 1), 3 * sizeof(float));
        } else {
            for (int k = 0; k < 3; k++) c.pos[3 * i + k] = (float)RND();
            if (i % 5 == 0) c.pos[3 * i + 2] = 0.5f; /* on one plane */
        }
        float *nv = c.nrm + 3 * i;
        const int kind = (int)(i % 3);
        if (kind == 0) { /* random direction */
            double z = 2.0 * RND() - 1.0, ph = 2.0 * M_PI * RND(), s = sqrt(1.0 - z * z);
            nv[0] = (float)(s * cos(ph)), nv[1] = (float)(s * sin(ph)), nv[2] = (float)z;
        } else if (kind == 1) { /* within about 3° of +z */
            double x = 0.1 * (RND() - 0.5), y = 0.1 * (RND() - 0.5), l = sqrt(x * x + y * y + 1.0);
            nv[0] = (float)(x / l), nv[1] = (float)(y / l), nv[2] = (float)(1.0 / l);
        } else { /* an axis, either sign */
            const int ax = RND() < 0.6 ? 2 : (int)(2.0 * RND());
            nv[0] = nv[1] = nv[2] = 0.0f;
            nv[ax] = RND() < 0.5 ? -1.0f : 1.0f;
        }
        c.radius[i] = (float)(0.02 * exp(log(50.0) * RND()));
    }
#undef RND
    const double epss[5] = {1e-4, 0.01, 0.05, 0.3, 2.0};
    uint32_t *js = malloc(n * sizeof *js);
    float *got = malloc(n * sizeof *got);
    ck_assert(js && got);
    size_t pairs = 0, partial = 0, full = 0, differ = 0;
    for (int e = 0; e < 5; e++)
        for (size_t i = 0; i < n; i++) {
            size_t m = 0;
            for (size_t j = 0; j < n; j++)
                if (j != i) js[m++] = (uint32_t)j;
            spr_overlap_areas(&c, i, js, m, epss[e], got);
            spr_overlap_row row;
            spr_overlap_row_init(&row, &c, i, epss[e]);
            const double ri = c.radius[i];
            for (size_t k = 0; k < m; k++) {
                const int hit = sample_loop_count(&c, i, js[k], epss[e], pu, pv);
                const float want = (float)(M_PI * (ri * ri) * hit / 256);
                if (memcmp(&want, &got[k], sizeof want)) {
                    if (differ < 5) printf("overlap: pair (%zu, %u) eps %g: %.9g, the sample loop %.9g (%d samples)\n", i, js[k], epss[e], got[k], want, hit);
                    differ++;
                }
                if (spr_overlap_row_positive(&row, js[k]) != (want > 0.0f)) { /* the early-exit test: A > 0 exactly */
                    if (differ < 5) printf("overlap: pair (%zu, %u) eps %g: positive %d, the sample loop %.9g\n", i, js[k], epss[e], !(want > 0.0f), want);
                    differ++;
                }
                pairs++;
                partial += hit > 0 && hit < 256;
                full += hit == 256;
            }
        }
    /* disks so small that one sample's area is 0 in float: A is 0 whatever
     * the count, and so is the early-exit test */
    size_t tiny = 0;
    for (size_t i = 3; i < n; i += 97) {
        const float keep = c.radius[i];
        c.radius[i] = 1e-23f;
        spr_overlap_row row;
        spr_overlap_row_init(&row, &c, i, 2.0);
        for (size_t j = 0; j < n; j++)
            if (j != i && spr_overlap_row_positive(&row, j) != (spr_overlap_area(&c, i, j, 2.0) > 0.0)) differ++;
        c.radius[i] = keep;
        tiny++;
    }
    printf("overlap: %zu ordered pairs, %zu partly overlapping, %zu whole (%zu rows of a tiny disk); %zu differ from the sample loop\n", pairs,
           partial, full, tiny, differ);
    ck_assert_uint_eq(differ, 0);
    ck_assert_uint_gt(partial, pairs / 20); /* the set exercises the boundaries */
    ck_assert_uint_gt(full, 1000);
    free(js);
    free(got);
    spr_cloud_free(&c);
}
END_TEST

/* Morton order (the working copy of the neighbour walks): the corners of
 * the bounds' cube quantise to 0 or 1023 on each axis, whose bits
 * interleave z, y, x from the top, so corners sort by z, then y, then x;
 * two splats on one corner keep their submission order. */
START_TEST(morton_order_of_cube_corners)
{
    /* index: (x, y, z) */
    const double xyz[] = {1, 1, 1, /* 0 */ 0, 0, 0, /* 1 */ 1, 0, 0, /* 2 */ 0, 1, 0, /* 3 */ 0, 0, 1, /* 4 */
                          1, 1, 0, /* 5 */ 0, 0, 0, /* 6: on corner 1 */ 1, 0, 1, /* 7 */ 0, 1, 1 /* 8 */};
    spr_cloud c;
    tu_cloud(&c, 9, xyz, 0.1f);
    spr_bounds b;
    spr_cloud_bounds(&c, &b);
    uint32_t order[9];
    spr_error err;
    ck_assert_int_eq(spr__morton_order(&c, &b, order, &err), SPR_OK);
    /* by (z, y, x): (0,0,0) 1, 6; (1,0,0) 2; (0,1,0) 3; (1,1,0) 5; (0,0,1) 4; (1,0,1) 7; (0,1,1) 8; (1,1,1) 0 */
    const uint32_t want[9] = {1, 6, 2, 3, 5, 4, 7, 8, 0};
    for (int k = 0; k < 9; k++) ck_assert_uint_eq(order[k], want[k]);
    spr__spatial s;
    ck_assert_int_eq(spr__spatial_make(&c, &b, 2, &s, &err), SPR_OK);
    for (int k = 0; k < 9; k++) {
        ck_assert_uint_eq(s.order[k], want[k]);
        ck_assert_uint_eq(s.rank[want[k]], (uint32_t)k);
        ck_assert(memcmp(s.c.pos + 3 * k, c.pos + 3 * want[k], 3 * sizeof(float)) == 0);
    }
    spr__spatial_free(&s);
    spr_cloud_free(&c);
}
END_TEST

/* The pair graphs of SPEC §5 ("all pairs with |p_i − p_j| < r_i + r_j",
 * f = 1) against every pair by brute force, in the test's own double
 * arithmetic: the whole graph (each pair found from one side, then both
 * rows), the graph of chosen rows, and those rows with only the neighbours
 * that come before them (before[j] < before[i], as hash collisions ask),
 * also among part of the cloud only (the splats of the box's lower half in x).
 * The clouds are hostile to a search that prunes by each column's largest
 * radius: radii over a factor 300 (a few giants among small splats), half
 * the centres on a lattice of step 1/8 (on the grid's cell borders, and at
 * exactly r_i + r_j from each other: the strict test refuses them), shared
 * centres, and the same cloud moved to 1e5 from the origin. */
START_TEST(pair_graphs_are_every_pair)
{
    const size_t n = tu_small() ? 600 : 2500;
    /* the box shrinks with the small size, so the density (and the counts asked for below) stays */
    const double side = tu_small() ? 3.0 : 6.0;
    uint64_t st = 0x2545F4914F6CDD1Dull;
#define RND() ((st = st * 6364136223846793005ull + 1442695040888963407ull), (double)(st >> 11) / 9007199254740992.0)
    for (int shift = 0; shift < 2; shift++) {
        spr_cloud c;
        double *xyz = malloc(3 * n * sizeof *xyz);
        ck_assert(xyz);
        for (size_t i = 0; i < n; i++)
            for (int k = 0; k < 3; k++) {
                const double u = i % 2 ? floor(RND() * 8.0 * side) / 8.0 : RND() * side; /* side x side x side/4 */
                xyz[3 * i + k] = (k == 2 ? 0.25 * u : u) + (shift ? 1e5 : 0.0);
            }
        for (size_t i = 7; i < n; i += 7) memcpy(xyz + 3 * i, xyz + 3 * (i - 1), 3 * sizeof *xyz);
        tu_cloud(&c, n, xyz, 1.0f);
        free(xyz);
        for (size_t i = 0; i < n; i++)
            c.radius[i] = i % 97 == 0 ? 1.5f : i % 2 ? 0.0625f * (float)(1 + i % 3) : (float)(0.005 + 0.15 * RND());
        unsigned char *row = malloc(n), *in = malloc(n);
        uint32_t *before = malloc(n * sizeof *before);
        size_t m = 0;
        for (size_t i = 0; i < n; i++) {
            in[i] = c.pos[3 * i] - (shift ? 1e5 : 0.0) < 0.5 * side;
            m += in[i];
            row[i] = (unsigned char)(i % 3 != 0);
            before[i] = i % 4 == 0 ? 0 : (uint32_t)(n - i); /* some placed (0), the others in reverse order */
        }
        spr_graph all, rows, gs, gp;
        spr__spatial sp, pp;
        spr_error err;
        ck_assert_int_eq(spr__pair_graph(&c, 1.0, 2, NULL, &all, &err), SPR_OK);
        ck_assert_int_eq(spr__pair_graph_rows(&c, 1.0, row, 1, 2, NULL, &rows, &err), SPR_OK);
        ck_assert_int_eq(spr__pair_graph_spatial(&c, 1.0, NULL, row, 1, before, 2, NULL, &sp, &gs, &err), SPR_OK);
        ck_assert_int_eq(spr__pair_graph_spatial(&c, 1.0, in, row, 1, before, 2, NULL, &pp, &gp, &err), SPR_OK);
        ck_assert_uint_eq(pp.c.n, m);
        ck_assert_uint_eq(gp.n, m);
        unsigned char *want = malloc(n), *got = malloc(n);
        size_t pairs = 0, ties = 0;
        for (size_t i = 0; i < n; i++) {
            for (size_t j = 0; j < n; j++) {
                double d2 = 0.0;
                for (int k = 0; k < 3; k++) {
                    const double d = (double)c.pos[3 * i + k] - (double)c.pos[3 * j + k];
                    d2 += d * d;
                }
                const double lim = (double)c.radius[i] + (double)c.radius[j];
                want[j] = j != i && d2 < lim * lim;
                ties += j != i && d2 == lim * lim;
                pairs += want[j];
            }
            /* the whole graph's row i, ascending */
            memset(got, 0, n);
            for (uint64_t e = all.start[i]; e < all.start[i + 1]; e++) {
                if (e > all.start[i]) ck_assert_uint_lt(all.adj[e - 1], all.adj[e]);
                got[all.adj[e]] = 1;
            }
            for (size_t j = 0; j < n; j++)
                if (got[j] != want[j]) ck_abort_msg("shift %d: pair (%zu, %zu) %s the whole graph", shift, i, j, want[j] ? "missing from" : "wrongly in");
            /* the graph of chosen rows */
            memset(got, 0, n);
            for (uint64_t e = rows.start[i]; e < rows.start[i + 1]; e++) got[rows.adj[e]] = 1;
            for (size_t j = 0; j < n; j++)
                if (got[j] != (row[i] && want[j])) ck_abort_msg("shift %d: pair (%zu, %zu) %s the graph of rows", shift, i, j, got[j] ? "wrongly in" : "missing from");
            /* the rows with the neighbours before them, in the copy's indices */
            memset(got, 0, n);
            const uint32_t q = sp.rank[i];
            for (uint64_t e = gs.start[q]; e < gs.start[q + 1]; e++) got[sp.order[gs.adj[e]]] = 1;
            for (size_t j = 0; j < n; j++)
                if (got[j] != (row[i] && want[j] && before[j] < before[i]))
                    ck_abort_msg("shift %d: pair (%zu, %zu) %s the rows with their neighbours before them", shift, i, j, got[j] ? "wrongly in" : "missing from");
            /* the same among the splats of x < 3 */
            memset(got, 0, n);
            if (!in[i]) ck_assert_uint_eq(pp.rank[i], UINT32_MAX);
            else
                for (uint64_t e = gp.start[pp.rank[i]]; e < gp.start[pp.rank[i] + 1]; e++) got[pp.order[gp.adj[e]]] = 1;
            for (size_t j = 0; j < n; j++)
                if (got[j] != (in[i] && in[j] && row[i] && want[j] && before[j] < before[i]))
                    ck_abort_msg("shift %d: pair (%zu, %zu) %s the part's rows with their neighbours before them", shift, i, j, got[j] ? "wrongly in" : "missing from");
        }
        printf("group: pair graphs of %zu splats%s: %zu ordered pairs, %zu at exactly r_i + r_j, all four graphs as brute force (%zu splats in "
               "the part)\n", n, shift ? " at 1e5" : "", pairs, ties, m);
        ck_assert(m > n / 3 && m < 2 * n / 3);
        ck_assert_uint_gt(pairs, 10 * n);
        ck_assert_uint_gt(ties, n / 50); /* the lattice ties are there */
        spr_graph_free(&all);
        spr_graph_free(&rows);
        spr_graph_free(&gs);
        spr__spatial_free(&sp);
        spr_graph_free(&gp);
        spr__spatial_free(&pp);
        free(in);
        free(want);
        free(got);
        free(row);
        free(before);
        spr_cloud_free(&c);
    }
#undef RND
}
END_TEST

Suite *make_group_suite(void)
{
    Suite *s = suite_create("group");
    TCase *tc = tcase_create("group");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, mgc_groups_have_no_conflicts);
    tcase_add_test(tc, mgc_bunny_has_no_conflicts);
    tcase_add_test(tc, mgc_k_falls_with_c);
    tcase_add_test(tc, hash_step_and_table);
    tcase_add_test(tc, groups_file_round_trip_and_errors);
    tcase_add_test(tc, overlap_area_hand_cases);
    tcase_add_test(tc, overlap_areas_are_the_sample_loop);
    tcase_add_test(tc, morton_order_of_cube_corners);
    tcase_add_test(tc, pair_graphs_are_every_pair);
    suite_add_tcase(s, tc);
    return s;
}
