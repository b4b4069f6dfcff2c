/* test_util.c — helpers for the suites. */
#include "test_util.h"
#include <cjson/cJSON.h>

#include <stdio.h>
#include <sys/wait.h>
#include <unistd.h>
#include <stdlib.h>
#include <string.h>
#include <string.h>

void tu_view(double eye_z, double fov_deg, double ortho_height, double near_plane, double far_plane, int W, int H, spr_view *v)
{
    spr_camera_desc c;
    spr_camera_defaults(&c);
    c.eye[2] = eye_z;
    c.ortho_height = ortho_height;
    c.fov_deg = fov_deg;
    c.near_plane = near_plane;
    c.far_plane = far_plane;
    c.width = W;
    c.height = H;
    spr_error err;
    ck_assert_int_eq(spr_view_make(&c, v, &err), SPR_OK);
}

void tu_hand_view(int W, int H, spr_view *v) { tu_view(2.0, 0.0, 2.0, 1.0, 3.0, W, H, v); }

void tu_cloud(spr_cloud *c, size_t n, const double *xyz, float r)
{
    ck_assert_int_eq(spr_cloud_alloc(c, n), SPR_OK);
    for (size_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) c->pos[3 * i + k] = (float)xyz[3 * i + k];
        c->radius[i] = r;
        c->color[3 * i] = c->color[3 * i + 1] = c->color[3 * i + 2] = 1.0f;
    }
}

double tu_uniform(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

void tu_set_color(spr_cloud *c, size_t i, float r, float g, float b)
{
    c->color[3 * i] = r;
    c->color[3 * i + 1] = g;
    c->color[3 * i + 2] = b;
}

void tu_render(const spr_view *v, const spr_cloud *c, const spr_render_desc *d, int threads, spr_render_result *out)
{
    spr_error err = {0};
    spr_backend *b = spr_swrast_create(threads, &err);
    ck_assert_ptr_nonnull(b);
    spr_result r = spr_render(b, v, c, d, out, &err);
    ck_assert_msg(r == SPR_OK, "render failed: %s", err.msg);
    spr_backend_destroy(b);
}

const char *tu_data(const char *rel)
{
    static char path[1024];
    snprintf(path, sizeof path, "%s/%s", SPR_DATA_DIR, rel);
    return path;
}

void tu_bunny_scene(tu_bunny *s, int W, int H, double c)
{
    tu_load("meshes/bunny00.off", &s->cloud);
    spr_bounds bd;
    spr_cloud_bounds(&s->cloud, &bd);
    spr_camera_desc cam;
    spr_camera_defaults(&cam);
    cam.width = W;
    cam.height = H;
    spr_camera_frame(&cam, &bd);
    spr_error err;
    ck_assert_int_eq(spr_view_make(&cam, &s->view, &err), SPR_OK);
    spr_mgc_desc md;
    spr_mgc_defaults(&md);
    md.c = c;
    int32_t *lab = malloc(s->cloud.n * sizeof *lab);
    spr_group_stats gs;
    ck_assert_int_eq(spr_group_mgc(&s->cloud, &md, lab, &gs, &err), SPR_OK);
    ck_assert_int_eq(spr_groups_from_labels(lab, s->cloud.n, gs.K, &s->groups, &err), SPR_OK);
    free(lab);
}

void tu_bunny_free(tu_bunny *s)
{
    spr_groups_free(&s->groups);
    spr_cloud_free(&s->cloud);
}

void tu_gl_desc(spr_gl_desc *d)
{
    spr_gl_defaults(d);
    const char *name = getenv("SPLATREF_TEST_GL_DRIVER");
    if (name && *name && spr_gl_driver_parse(name, &d->driver)) {
        fprintf(stderr, "splatref_tests: SPLATREF_TEST_GL_DRIVER='%s' is not %s\n", name, spr_gl_driver_names());
        exit(2);
    }
}

spr_cloud tu_builtin(const char *name, size_t n)
{
    spr_cloud c;
    spr_load_desc d;
    spr_load_defaults(&d);
    d.points = n;
    spr_error err = {0};
    spr_result r = spr_load(name, &d, &c, &err);
    ck_assert_msg(r == SPR_OK, "%s", err.msg);
    return c;
}

int tu_small(void)
{
    const char *s = getenv("SPLATREF_TEST_SIZE");
    return s && !strcmp(s, "small");
}

/* Keep every k-th splat, in order (the small test size of real models). */
static void subsample(spr_cloud *c, size_t k)
{
    size_t m = 0;
    for (size_t i = 0; i < c->n; i += k, m++) {
        memmove(c->pos + 3 * m, c->pos + 3 * i, 3 * sizeof(float));
        memmove(c->nrm + 3 * m, c->nrm + 3 * i, 3 * sizeof(float));
        memmove(c->color + 3 * m, c->color + 3 * i, 3 * sizeof(float));
        c->radius[m] = c->radius[i];
        c->alpha[m] = c->alpha[i];
    }
    c->n = m;
}

spr_cloud tu_model(const char *name, size_t n)
{
    if (strncmp(name, "builtin:", 8) == 0) return tu_builtin(name, tu_small() ? (n / 4 > 500 ? n / 4 : n) : n);
    spr_cloud c;
    tu_load(name, &c);
    if (tu_small()) subsample(&c, 8);
    return c;
}

void tu_load(const char *rel, spr_cloud *c)
{
    spr_error err = {0};
    spr_load_desc d;
    spr_load_defaults(&d);
    spr_result r = spr_load(tu_data(rel), &d, c, &err);
    ck_assert_msg(r == SPR_OK, "%s (run tools/install-deps.sh to extract the CGAL data)", err.msg);
}

int tu_run(const char *prog, const char *env, int out_too, char *const argv[], char *err, size_t cap)
{
    int pipefd[2];
    ck_assert_int_eq(pipe(pipefd), 0);
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid == 0) {
        dup2(pipefd[1], 2);
        close(pipefd[0]);
        if (out_too) dup2(pipefd[1], 1);
        else if (!freopen("/dev/null", "w", stdout)) _exit(126);
        if (env) putenv((char *)env);
        execv(prog ? prog : SPR_CLI, argv);
        _exit(127);
    }
    close(pipefd[1]);
    size_t n = 0;
    ssize_t got;
    while ((got = read(pipefd[0], err + n, cap - 1 - n)) > 0) n += (size_t)got;
    err[n] = 0;
    close(pipefd[0]);
    int st;
    waitpid(pid, &st, 0);
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

void tu_tmpdir(char dir[64], const char *tag)
{
    snprintf(dir, 64, "/tmp/spr_%s_XXXXXX", tag);
    ck_assert_ptr_nonnull(mkdtemp(dir));
}

struct cJSON *tu_read_json(const char *path)
{
    char *text = NULL;
    size_t len = 0;
    spr_error err = {0};
    ck_assert_msg(spr__read_file(path, &text, &len, &err) == SPR_OK, "%s", err.msg);
    cJSON *o = cJSON_Parse(text);
    free(text);
    ck_assert_msg(o != NULL, "%s: not JSON", path);
    return o;
}

const char *tu_in(const char *dir, const char *name)
{
    static char p[16][300];
    static int k;
    k = (k + 1) % 16;
    snprintf(p[k], sizeof p[k], "%s/%s", dir, name);
    return p[k];
}

int tu_same_file(const char *a, const char *b)
{
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    ck_assert_msg(fa && fb, "cannot open %s or %s", a, b);
    int same = 1, ca, cb;
    do {
        ca = fgetc(fa), cb = fgetc(fb);
        same &= ca == cb;
    } while (same && ca != EOF);
    fclose(fa);
    fclose(fb);
    return same;
}
