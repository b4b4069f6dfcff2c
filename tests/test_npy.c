/* test_npy.c — NumPy .npy/.npz reading and writing (core/io/npy.c, issue 43).
 *
 * The files read come from numpy itself (tests/data/npy/make_npy.py wrote them; its README names the version);
 * their values are recomputed here from the script's formulas, never read back through our writer.  What our
 * writer makes is read by numpy (tests/data/npy/check_ours.py) and by our reader. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "spr_npy.h"
#include "test_util.h"

static const char *npy_data(const char *name)
{
    static char p[8][512];
    static int k;
    k = (k + 1) % 8;
    snprintf(p[k], sizeof p[k], "%s/tests/data/npy/%s", SPR_SOURCE_DIR, name);
    return p[k];
}

/* A failure: non-zero, one line naming `name`, nothing handed out. */
static void is_clear_failure(spr_result r, const spr_error *err, const char *name, const char *says)
{
    ck_assert_msg(r != SPR_OK, "%s: accepted", name);
    ck_assert_msg(strstr(err->msg, name) && !strchr(err->msg, '\n'), "%s: not one line naming it: [%s]", name, err->msg);
    if (says) ck_assert_msg(strstr(err->msg, says), "%s: [%s] does not say '%s'", name, err->msg, says);
}

static void shape_is(const spr_npy *a, int ndim, size_t s0, size_t s1, size_t s2, spr_npy_type type)
{
    const size_t s[3] = {s0, s1, s2};
    ck_assert_msg(a->ndim == ndim, "%s: ndim %d, expected %d", a->name, a->ndim, ndim);
    for (int d = 0; d < ndim && d < 3; d++) ck_assert_msg(a->shape[d] == s[d], "%s: dimension %d is %zu, expected %zu", a->name, d, a->shape[d], s[d]);
    ck_assert_msg(a->type == type, "%s: type %d", a->name, (int)a->type);
    ck_assert_ptr_nonnull(a->data);
}

static void floats_are(const spr_npy *a, const char *what, float (*want)(size_t))
{
    const float *f = a->data;
    for (size_t i = 0; i < spr_npy_count(a); i++)
        ck_assert_msg(memcmp(&f[i], &(float){want(i)}, 4) == 0, "%s element %zu: %.9g, expected %.9g", what, i, f[i], want(i));
}

/* make_npy.py's formulas, in the same arithmetic (float32 where numpy's was float32, double where float64) */
static float img_v(size_t i) { return (float)i * 0.25f; }
static float f8_v(size_t i) { return (float)((double)i / 3.0 + 1e-9); }
static float be_f4_v(size_t i) { return (float)i * 0.75f - 1.5f; }
static float be_f8_v(size_t i) { return (float)(1.0 / ((double)i + 1.0)); }
static float ar_v(size_t i) { return (float)i; }
static float grad_v(size_t i) { return (float)(((double)i - 3.5) * 0.1); }

START_TEST(numpy_written_npy)
{
    static const struct { const char *file; int ndim; size_t s0, s1, s2; float (*v)(size_t); } F[] = {
        {"img_f4.npy", 3, 4, 5, 3, img_v},  {"f8.npy", 2, 2, 3, 0, f8_v},       {"be_f4.npy", 1, 7, 0, 0, be_f4_v},
        {"be_f8.npy", 1, 3, 0, 0, be_f8_v}, {"v2_f4.npy", 1, 5, 0, 0, ar_v},    {"v3_f4.npy", 1, 5, 0, 0, ar_v},
        {"empty_f4.npy", 2, 0, 3, 0, ar_v},
    };
    spr_error err = {0};
    spr_npy a;
    for (size_t k = 0; k < sizeof F / sizeof F[0]; k++) {
        ck_assert_msg(spr_npy_read(npy_data(F[k].file), &a, &err) == SPR_OK, "%s", err.msg);
        snprintf(a.name, sizeof a.name, "%s", F[k].file);
        shape_is(&a, F[k].ndim, F[k].s0, F[k].s1, F[k].s2, SPR_NPY_F4);
        floats_are(&a, F[k].file, F[k].v);
        spr_npy_free(&a);
    }
    /* f8 rounds once: 1/3 + 1e-9 is not a float, and the nearest one is what comes back */
    ck_assert_int_eq(spr_npy_read(npy_data("f8.npy"), &a, &err), SPR_OK);
    ck_assert(((float *)a.data)[1] != (float)(1.0 / 3.0) || (float)(1.0 / 3.0 + 1e-9) == (float)(1.0 / 3.0));
    spr_npy_free(&a);
    ck_assert_int_eq(spr_npy_read(npy_data("scalar_f4.npy"), &a, &err), SPR_OK);
    ck_assert(a.ndim == 0 && spr_npy_count(&a) == 1 && a.type == SPR_NPY_F4 && ((float *)a.data)[0] == 3.25f && !a.name[0]);
    spr_npy_free(&a);
    /* integers: int32 as is, int64 and uint8 converted exactly */
    ck_assert_int_eq(spr_npy_read(npy_data("counts_i4.npy"), &a, &err), SPR_OK);
    shape_is(&a, 1, 6, 0, 0, SPR_NPY_I4);
    for (int i = 0; i < 6; i++) ck_assert_int_eq(((int32_t *)a.data)[i], i * i - 10);
    spr_npy_free(&a);
    ck_assert_int_eq(spr_npy_read(npy_data("i8.npy"), &a, &err), SPR_OK);
    shape_is(&a, 1, 4, 0, 0, SPR_NPY_I4);
    for (int i = 0; i < 4; i++) ck_assert_int_eq(((int32_t *)a.data)[i], 1000000 * i - 5);
    spr_npy_free(&a);
    ck_assert_int_eq(spr_npy_read(npy_data("u1.npy"), &a, &err), SPR_OK);
    shape_is(&a, 2, 2, 2, 0, SPR_NPY_I4);
    for (int i = 0; i < 4; i++) ck_assert_int_eq(((int32_t *)a.data)[i], 250 + i);
    spr_npy_free(&a);
}
END_TEST

START_TEST(numpy_written_npz)
{
    const char *files[] = {"several.npz", "several_compressed.npz"}; /* np.savez (stored), np.savez_compressed (deflated) */
    for (int f = 0; f < 2; f++) {
        spr_error err = {0};
        spr_npy *a = NULL;
        int n = 0;
        ck_assert_msg(spr_npz_read(npy_data(files[f]), &a, &n, &err) == SPR_OK, "%s", err.msg);
        ck_assert_int_eq(n, 4);
        ck_assert_str_eq(a[0].name, "image");
        shape_is(&a[0], 3, 4, 5, 3, SPR_NPY_F4);
        floats_are(&a[0], files[f], img_v);
        ck_assert_str_eq(a[1].name, "grad");
        shape_is(&a[1], 2, 2, 4, 0, SPR_NPY_F4);
        floats_are(&a[1], files[f], grad_v);
        ck_assert_str_eq(a[2].name, "counts");
        shape_is(&a[2], 1, 5, 0, 0, SPR_NPY_I4);
        for (int i = 0; i < 5; i++) ck_assert_int_eq(((int32_t *)a[2].data)[i], 7 * i);
        ck_assert_str_eq(a[3].name, "scale");
        ck_assert(a[3].ndim == 0 && ((float *)a[3].data)[0] == 2.5f);
        spr_npz_free(a, n);
    }
}
END_TEST

START_TEST(refused_files_say_why)
{
    static const struct { const char *file, *says; int npz; } R[] = {
        {"fortran_f4.npy", "fortran_order is True", 0},
        {"c8.npy", "dtype '<c8' is not read", 0},
        {"i8_big.npy", "element 2 (2147483648) does not fit int32", 0},
        {"dup.npz", "two members of the zip have one name", 1},
        {"not_npy.npz", "member readme.txt: not named NAME.npy", 1},
        {"img_f4.npy", "not a zip archive", 1},
        {"several.npz", "not a .npy file", 0},
    };
    for (size_t k = 0; k < sizeof R / sizeof R[0]; k++) {
        spr_error err = {0};
        spr_npy a, *v = (spr_npy *)&err;
        int n = 7;
        const char *p = npy_data(R[k].file);
        spr_result r = R[k].npz ? spr_npz_read(p, &v, &n, &err) : spr_npy_read(p, &a, &err);
        is_clear_failure(r, &err, p, R[k].says);
        if (R[k].npz) ck_assert(v == NULL && n == 0);
        else ck_assert(a.data == NULL && a.ndim == 0);
    }
    spr_error err = {0};
    spr_npy a;
    is_clear_failure(spr_npy_read("/nonexistent/x.npy", &a, &err), &err, "/nonexistent/x.npy", "cannot open");
}
END_TEST

/* The bytes of a file from tests/data/npy. */
static char *slurp(const char *name, size_t *len)
{
    char *b = NULL;
    spr_error err = {0};
    ck_assert_msg(spr__read_file(npy_data(name), &b, len, &err) == SPR_OK, "%s", err.msg);
    return b;
}

/* Every prefix of a small .npy and of a deflated .npz is refused in one line (no crash; ASan / valgrind: no leak);
 * every single byte flipped is refused or read, never a crash. */
START_TEST(truncated_at_every_byte)
{
    size_t len;
    char *b = slurp("img_f4.npy", &len);
    for (size_t k = 0; k < len; k++) {
        spr_error err = {0};
        spr_npy a;
        is_clear_failure(spr__parse_npy("cut.npy", b, k, NULL, &a, &err), &err, "cut.npy", NULL);
        ck_assert(a.data == NULL);
    }
    for (size_t k = 0; k < len; k++) {
        spr_error err = {0};
        spr_npy a;
        b[k] ^= 0x5a;
        if (spr__parse_npy("flip.npy", b, len, NULL, &a, &err) == SPR_OK) spr_npy_free(&a);
        else is_clear_failure(SPR_E_FORMAT, &err, "flip.npy", NULL);
        b[k] ^= 0x5a;
    }
    /* and through the file reader, which names the path: cut inside the header, inside the data */
    char dir[64];
    tu_tmpdir(dir, "npy");
    const size_t cuts[] = {0, 5, 9, 60, 128, len - 1};
    for (size_t c = 0; c < sizeof cuts / sizeof cuts[0]; c++) {
        const char *p = tu_in(dir, "cut.npy");
        FILE *f = fopen(p, "wb");
        ck_assert(f && fwrite(b, 1, cuts[c], f) == cuts[c] && !fclose(f));
        spr_error err = {0};
        spr_npy a;
        is_clear_failure(spr_npy_read(p, &a, &err), &err, p, cuts[c] >= 128 ? "byte 128: 60 elements of 4 bytes need 240 bytes" : NULL);
        remove(p);
    }
    rmdir(dir);
    free(b);
    b = slurp("several_compressed.npz", &len);
    for (size_t k = 0; k < len; k++) {
        spr_error err = {0};
        spr_npy *v = NULL;
        int n = 0;
        is_clear_failure(spr__parse_npz("cut.npz", b, k, &v, &n, &err), &err, "cut.npz", NULL);
        ck_assert(v == NULL && n == 0);
    }
    free(b);
}
END_TEST

/* A version 1.0 .npy of the header text `dict` and `data` bytes of zeros. */
static size_t make_npy(unsigned char *out, size_t cap, const char *dict, size_t data)
{
    const size_t dl = strlen(dict), len = 10 + dl + data;
    ck_assert(len <= cap);
    memcpy(out, "\x93NUMPY\x01\x00", 8);
    out[8] = (unsigned char)(dl & 0xff), out[9] = (unsigned char)(dl >> 8);
    memcpy(out + 10, dict, dl);
    memset(out + 10 + dl, 0, data);
    return len;
}

START_TEST(bad_headers_are_one_line)
{
    static const struct { const char *dict; size_t data; spr_result code; const char *says; } B[] = {
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (2,), }\n", 8, SPR_OK, NULL},
        {"{\"shape\": (2L,), \"descr\": \"<f4\", \"fortran_order\": False}", 8, SPR_OK, NULL}, /* any order, either quote, Python 2's 2L */
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (2,), }\n", 4, SPR_E_TRUNCATED, "2 elements of 4 bytes need 8 bytes, 4 follow"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (2,), }\n", 9, SPR_E_FORMAT, "1 bytes after the array's data"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (2), }\n", 8, SPR_E_FORMAT, "a tuple of one is (n,)"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (1, 1, 1, 1, 1), }\n", 4, SPR_E_TOO_LARGE, "more than 4 dimensions"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (65536, 65536), }\n", 0, SPR_E_TOO_LARGE, "more than 2147483648 elements"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (99999999999999999999999,), }\n", 0, SPR_E_TOO_LARGE, "byte 61: a dimension"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (0, 99999999999,), }\n", 0, SPR_E_TOO_LARGE, "a dimension"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (-1,), }\n", 0, SPR_E_FORMAT, "non-negative integer"},
        {"{'descr': '<f4', 'fortran_order': False, 'descr': '<f4', 'shape': (), }\n", 4, SPR_E_FORMAT, "byte 51: repeated key 'descr'"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (), 'x': 1}\n", 4, SPR_E_FORMAT, "unknown key 'x'"},
        {"{'descr': '<f4', 'shape': ()}\n", 4, SPR_E_FORMAT, "has no 'fortran_order'"},
        {"{'descr': '<f2', 'fortran_order': False, 'shape': (), }\n", 2, SPR_E_FORMAT, "dtype '<f2' is not read"},
        {"{'descr': '|f4', 'fortran_order': False, 'shape': (), }\n", 4, SPR_E_FORMAT, "dtype '|f4'"},
        {"{'descr': [('x', '<f4')], 'fortran_order': False, 'shape': (), }\n", 4, SPR_E_FORMAT, "structured dtype"},
        {"{'descr': '<f4', 'fortran_order': maybe, 'shape': (), }\n", 4, SPR_E_FORMAT, "neither True nor False"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (), } x\n", 4, SPR_E_FORMAT, "only spaces may follow"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (), \n", 4, SPR_E_FORMAT, "the header dict ends early"},
        {"{'descr': '<f4\n", 4, SPR_E_FORMAT, "control character"},
        {"['descr']", 4, SPR_E_FORMAT, "byte 10: '{' expected"},
    };
    unsigned char buf[512];
    for (size_t k = 0; k < sizeof B / sizeof B[0]; k++) {
        const size_t len = make_npy(buf, sizeof buf, B[k].dict, B[k].data);
        spr_error err = {0};
        spr_npy a;
        spr_result r = spr__parse_npy("hand.npy", buf, len, "h", &a, &err);
        ck_assert_msg(r == B[k].code, "case %zu: %d, expected %d: %s", k, r, B[k].code, err.msg);
        if (r) is_clear_failure(r, &err, "hand.npy", B[k].says);
        else ck_assert(!strcmp(a.name, "h") && a.ndim == 1 && a.shape[0] == 2);
        spr_npy_free(&a);
    }
    /* the preamble: a version we do not know, a header longer than the file */
    size_t len = make_npy(buf, sizeof buf, "{}", 0);
    buf[6] = 4;
    spr_error err = {0};
    spr_npy a;
    is_clear_failure(spr__parse_npy("hand.npy", buf, len, NULL, &a, &err), &err, "hand.npy", "byte 6: .npy format version 4.0");
    buf[6] = 1, buf[8] = 0xff;
    is_clear_failure(spr__parse_npy("hand.npy", buf, len, NULL, &a, &err), &err, "hand.npy", "byte 8: the header says 255 bytes, 2 follow");
}
END_TEST

/* The arrays of the round trips; check_ours.py computes the same values. */
typedef struct rt_arrays { float a[24]; int32_t n[5]; float s, q[6]; spr_npy v[5]; } rt_arrays;
static void rt_make(rt_arrays *t)
{
    memset(t, 0, sizeof *t);
    for (int i = 0; i < 24; i++) t->a[i] = (float)(i * 0.5 - 3.0);
    for (int i = 0; i < 5; i++) t->n[i] = i * i * 1000 - 7;
    for (int i = 0; i < 6; i++) t->q[i] = (float)i;
    t->s = 1.25f;
    t->v[0] = (spr_npy){"a", 3, {3, 4, 2}, SPR_NPY_F4, t->a};
    t->v[1] = (spr_npy){"n", 1, {5}, SPR_NPY_I4, t->n};
    t->v[2] = (spr_npy){"s", 0, {0}, SPR_NPY_F4, &t->s};
    t->v[3] = (spr_npy){"e", 1, {0}, SPR_NPY_F4, NULL};
    t->v[4] = (spr_npy){"q", 4, {1, 2, 1, 3}, SPR_NPY_F4, t->q};
}

static void same_array(const spr_npy *got, const spr_npy *want)
{
    ck_assert_str_eq(got->name, want->name);
    ck_assert_int_eq(got->ndim, want->ndim);
    ck_assert_int_eq(got->type, want->type);
    for (int d = 0; d < want->ndim; d++) ck_assert_uint_eq(got->shape[d], want->shape[d]);
    ck_assert_msg(!spr_npy_count(want) || !memcmp(got->data, want->data, 4 * spr_npy_count(want)), "%s: other bits", want->name);
}

START_TEST(round_trip_ours)
{
    rt_arrays t;
    rt_make(&t);
    /* the bits that must survive: −0, NaN with a payload, infinities, a subnormal, the int32 extremes */
    t.a[1] = -0.0f, t.a[2] = INFINITY, t.a[3] = -INFINITY, t.a[4] = 1e-45f;
    const uint32_t nan = 0x7fc12345u;
    memcpy(&t.a[5], &nan, 4);
    t.n[0] = INT32_MIN, t.n[4] = INT32_MAX;
    char dir[64];
    tu_tmpdir(dir, "npy");
    spr_error err = {0};
    const char *p = tu_in(dir, "ours.npz");
    ck_assert_msg(spr_npz_write(p, t.v, 5, &err) == SPR_OK, "%s", err.msg);
    spr_npy *v;
    int n;
    ck_assert_msg(spr_npz_read(p, &v, &n, &err) == SPR_OK, "%s", err.msg);
    ck_assert_int_eq(n, 5);
    for (int k = 0; k < 5; k++) same_array(&v[k], &t.v[k]);
    spr_npz_free(v, n);
    /* the bytes depend on the arrays only */
    ck_assert_int_eq(spr_npz_write(tu_in(dir, "again.npz"), t.v, 5, &err), SPR_OK);
    ck_assert(tu_same_file(p, tu_in(dir, "again.npz")));
    for (int k = 0; k < 5; k++) {
        spr_npy a;
        ck_assert_msg(spr_npy_write(tu_in(dir, "one.npy"), &t.v[k], &err) == SPR_OK, "%s", err.msg);
        ck_assert_msg(spr_npy_read(tu_in(dir, "one.npy"), &a, &err) == SPR_OK, "%s", err.msg);
        snprintf(a.name, sizeof a.name, "%s", t.v[k].name);
        same_array(&a, &t.v[k]);
        spr_npy_free(&a);
    }
    /* an empty archive */
    ck_assert_int_eq(spr_npz_write(p, NULL, 0, &err), SPR_OK);
    ck_assert_int_eq(spr_npz_read(p, &v, &n, &err), SPR_OK);
    ck_assert(v == NULL && n == 0);
    remove(p), remove(tu_in(dir, "again.npz")), remove(tu_in(dir, "one.npy"));
    rmdir(dir);
}
END_TEST

/* numpy reads what we write: check_ours.py loads it and recomputes every value. */
START_TEST(round_trip_numpy)
{
    if (access("/usr/bin/python3", X_OK)) {
        ck_abort_msg("/usr/bin/python3 (with python3-numpy) is needed: tools/install-deps.sh installs it");
    }
    rt_arrays t;
    rt_make(&t);
    char dir[64];
    tu_tmpdir(dir, "npy");
    spr_error err = {0};
    ck_assert_msg(spr_npz_write(tu_in(dir, "ours.npz"), t.v, 5, &err) == SPR_OK, "%s", err.msg);
    ck_assert_msg(spr_npy_write(tu_in(dir, "a.npy"), &t.v[0], &err) == SPR_OK, "%s", err.msg);
    char script[512], out[4096];
    snprintf(script, sizeof script, "%s/tests/data/npy/check_ours.py", SPR_SOURCE_DIR);
    char *argv[] = {"python3", script, dir, NULL};
    const int rc = tu_run("/usr/bin/python3", NULL, 1, argv, out, sizeof out);
    ck_assert_msg(rc == 0 && strstr(out, "check_ours: numpy"), "check_ours.py: exit %d: %s", rc, out);
    remove(tu_in(dir, "ours.npz")), remove(tu_in(dir, "a.npy"));
    rmdir(dir);
}
END_TEST

/* A write that cannot happen says why in one line and leaves no file. */
START_TEST(write_failures_leave_nothing)
{
    rt_arrays t;
    rt_make(&t);
    char dir[64];
    tu_tmpdir(dir, "npy");
    const char *p = tu_in(dir, "bad.npz");
    spr_npy v[2] = {t.v[0], t.v[1]};
    spr_error err = {0};
    strcpy(v[1].name, "a");
    is_clear_failure(spr_npz_write(p, v, 2, &err), &err, p, "arrays 0 and 1 are both named 'a'");
    v[1].name[0] = '\0';
    is_clear_failure(spr_npz_write(p, v, 2, &err), &err, p, "array 1: a member's name has 1 to 63 bytes");
    v[1] = t.v[1], v[1].ndim = 5;
    is_clear_failure(spr_npz_write(p, v, 2, &err), &err, p, "array 1: 5 dimensions");
    v[1] = t.v[1], v[1].data = NULL;
    is_clear_failure(spr_npz_write(p, v, 2, &err), &err, p, "array 1: no data");
    v[1] = t.v[1], v[1].shape[0] = SPR_NPY_MAX_ELEMS + 1;
    is_clear_failure(spr_npy_write(p, &v[1], &err), &err, p, "more than 2147483648 elements");
    ck_assert_msg(access(p, F_OK) != 0, "%s was left behind", p);
    is_clear_failure(spr_npy_write("/nonexistent/dir/x.npy", &t.v[0], &err), &err, "/nonexistent/dir/x.npy", "cannot create");
    rmdir(dir);
    ck_assert_msg(access(dir, F_OK) != 0, "%s: a temporary file was left behind", dir);
}
END_TEST

Suite *make_npy_suite(void)
{
    Suite *s = suite_create("npy");
    TCase *tc = tcase_create("npy");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, numpy_written_npy);
    tcase_add_test(tc, numpy_written_npz);
    tcase_add_test(tc, refused_files_say_why);
    tcase_add_test(tc, truncated_at_every_byte);
    tcase_add_test(tc, bad_headers_are_one_line);
    tcase_add_test(tc, round_trip_ours);
    tcase_add_test(tc, round_trip_numpy);
    tcase_add_test(tc, write_failures_leave_nothing);
    suite_add_tcase(s, tc);
    return s;
}
