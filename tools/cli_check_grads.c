/* cli_check_grads.c — `splatref check --grads THEIRS.npz`: a training
 * renderer's gradients of a gauss3d frame (gsplat's names and shapes, as
 * `splatref grad` writes them) against the reference's, computed here on the
 * CPU with the same scene and upstream-gradient options (SPEC 10.10): one
 * verdict per array, the worst Gaussians of each failing one, exit 0 / 1.
 *
 * The tolerance (also in --help, and quoted by docs/gradients.md):
 *
 * An entry of array X for Gaussian G passes when
 *     |theirs − ref| ≤ rtol·S_G + atol,
 * S_G the largest |ref| over G's row of X (the 3 components of means, the 4
 * of quats, …; for means2d also G's absgrad row, which is exactly Σ over
 * pixels of |∂L/∂means2d| per axis, the magnitude of that very sum);
 * rtol = 2^-10 and atol = 1e-6·max |ref| over the whole array; counts exact.
 *
 * Why.  A training renderer is not the reference's arithmetic, and each of its
 * differences is a relative error of a pixel's term, not of the sum:
 *   - it recovers T by division by 1 − α (inria, gsplat, OpenSplat): ≤ 3× the
 *     rounding of the forward's own T, below 1e-6 relative per term
 *     (docs/gradients.md, "Measured: the colour behind a Gaussian");
 *   - it uses float32 fast-math exp (__expf): a few ulps, ~1e-7..1e-6 relative
 *     per term, carried through α into every term;
 *   - it sums the pixels' terms with atomics in an unspecified order: float32
 *     summation of n terms in any order errs by at most (n − 1)·2^-24·Σ|terms|.
 * So |theirs − ref| ≲ (ε + n·2^-24)·Σ|terms| with ε ≈ 1e-6.  That bound scales
 * with Σ|terms|, the magnitude of the sum, not with its value: terms of both
 * signs cancel in the sum over pixels.  S_G stands for that magnitude by the
 * largest value of G's row: the chain (means2d, conics → Σ′ → Σ → means, quats,
 * scales) mixes the components, so an error in one reaches all of them at the
 * size of the largest.  rtol = 2^-10 ≈ 1e-3 is about 1000·ε: it leaves room
 * for Σ|terms| up to ~100× the row's largest value (with n ≤ a few thousand
 * pixels a Gaussian, n·2^-24 ≤ 1e-4).  The floor atol = 1e-6·max|ref| (ε of
 * the array's largest value) holds Gaussians whose whole row is near zero (a
 * few pixels at an edge, or cancellation beyond that) to the rounding of the
 * array's large sums rather than to a bound below any float32 renderer's.  A
 * bug — a wrong sign, a missing term, an ungated cap, inria's doubled t.z term
 * — changes an entry by O(1) of its value, far beyond 2^-10.  Not covered: a
 * Gaussian at a decision (the 1/255 skip, the cap, the stop, a tile's edge)
 * that the other renderer's rounding flips, which moves it by a whole pixel's
 * term; the worst Gaussians listed show whether a failure is that (one or two
 * Gaussians, a pixel's term) or systematic.  The numbers were set from this
 * argument, not from runs; --rtol and --atol override them (printed in the
 * verdict line).
 */
#include "cli.h"
#include "cli_grad.h"
#include "spr__scene_opts.h"
#include "spr_npy.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define WORST 5

typedef struct grad_cmp {
    const char *name;
    size_t n, per, fail;
    double max_abs, atol;
    size_t worst[WORST];   /* by |Δ|/tolerance, largest first */
    double ratio[WORST];
    int nworst;
} grad_cmp;

static void shape_text(const spr_npy *m, char *s, size_t cap)
{
    int o = snprintf(s, cap, "[");
    for (int d = 0; d < m->ndim && o < (int)cap; d++) o += snprintf(s + o, cap - (size_t)o, "%s%zu", d ? ", " : "", m->shape[d]);
    if (o < (int)cap) snprintf(s + o, cap - (size_t)o, "]");
}

static double val(const spr_npy *m, size_t i) { return m->type == SPR_NPY_F4 ? (double)((const float *)m->data)[i] : (double)((const int32_t *)m->data)[i]; }

static void row_text(const spr_npy *m, size_t G, size_t per, char *s, size_t cap)
{
    int o = snprintf(s, cap, per == 1 ? "" : "(");
    for (size_t k = 0; k < per && k < 12 && o < (int)cap; k++) o += snprintf(s + o, cap - (size_t)o, "%s%.9g", k ? ", " : "", val(m, G * per + k));
    if (per > 12 && o < (int)cap) o += snprintf(s + o, cap - (size_t)o, ", …");
    if (per != 1 && o < (int)cap) snprintf(s + o, cap - (size_t)o, ")");
}

/* Compare one array: ref and theirs of the same shape [n, per…]; absg: G's absgrad rows for means2d (NULL otherwise). */
static void compare(grad_cmp *c, const spr_npy *ref, const spr_npy *th, const float *absg, double rtol, double atol_given)
{
    const size_t n = c->n, per = c->per;
    const int exact = !strcmp(c->name, "counts");
    double amax = 0.0;
    for (size_t i = 0; i < n * per; i++) amax = fmax(amax, fabs(val(ref, i)));
    c->atol = exact ? 0.0 : atol_given >= 0.0 ? atol_given : 1e-6 * amax;
    for (size_t G = 0; G < n; G++) {
        double S = 0.0, worst = 0.0;
        for (size_t k = 0; k < per; k++) S = fmax(S, fabs(val(ref, G * per + k)));
        if (absg) S = fmax(S, fmax(fabs((double)absg[2 * G]), fabs((double)absg[2 * G + 1])));
        const double tol = exact ? 0.0 : rtol * S + c->atol;
        int bad = 0;
        for (size_t k = 0; k < per; k++) {
            const double d = fabs(val(th, G * per + k) - val(ref, G * per + k));
            if (!(d <= tol)) bad = 1; /* NaN fails */
            const double r = isnan(d) ? INFINITY : tol > 0.0 ? d / tol : d > 0.0 ? INFINITY : 0.0;
            if (r > worst || (isinf(r) && !isinf(worst))) worst = r;
            if (!(d <= c->max_abs)) c->max_abs = isnan(d) ? NAN : fmax(c->max_abs, d);
        }
        c->fail += (size_t)bad;
        /* keep the WORST largest ratios, largest first (the worst Gaussian is shown even when none fails) */
        if (c->nworst < WORST || worst > c->ratio[c->nworst - 1]) {
            int at = c->nworst < WORST ? c->nworst : WORST - 1;
            while (at > 0 && worst > c->ratio[at - 1]) c->worst[at] = c->worst[at - 1], c->ratio[at] = c->ratio[at - 1], at--;
            c->worst[at] = G, c->ratio[at] = worst;
            if (c->nworst < WORST) c->nworst++;
        }
    }
}

int cli_check_grads(spr__args *a, const char *path, const char *out, const char *junit)
{
    double rtol = 1.0 / 1024.0, atol = -1.0;
    if (spr__get_double(a, "rtol", &rtol, 0.0, 1e30) < 0 || spr__get_double(a, "atol", &atol, 0.0, 1e30) < 0) return 2;
    if (a->camera_all) { spr__error(a, "--grads checks one view: give one --camera"); return 2; }
    spr_error err = {0};
    spr_npy *th = NULL, ref[16];
    int nth = 0, nref = 0, rc = 2;
    float *sh0 = NULL, *shN = NULL;
    spr_scene s;
    spr_render_desc rd;
    spr_grad_desc gd;
    cli_grad_inputs in = {0};
    spr_gauss_grads g = {0};
    spr_backend *b = NULL;
    cli_junit *ju = junit ? cli_junit_new("splatref check --grads") : NULL;
    cJSON *rep = NULL;
    memset(&s, 0, sizeof s);
    if (spr_npz_read(path, &th, &nth, &err)) { fprintf(stderr, "splatref check: --grads: %s\n", err.msg); goto done; }
    if (cli_grad_frame(a, "cpu", NULL, &s, &rd, &gd, &in, &b, &g)) goto done;
    if ((nref = cli_grad_npz(&g, ref, 16, &sh0, &shN)) < 0) { spr__error(a, "out of memory"); goto done; }
    /* every array present, of the reference's shape, float where float is expected: refused in one line otherwise */
    const spr_npy *match[16];
    for (int i = 0; i < nref; i++) {
        match[i] = NULL;
        for (int k = 0; k < nth; k++)
            if (!strcmp(th[k].name, ref[i].name)) match[i] = &th[k];
        char want[96], have[96];
        shape_text(&ref[i], want, sizeof want);
        if (!match[i]) {
            char names[600] = "";
            for (int k = 0, o = 0; k < nth && o < (int)sizeof names; k++) o += snprintf(names + o, sizeof names - (size_t)o, "%s%s", k ? ", " : "", th[k].name);
            spr__error(a, "--grads: %s has no array '%s' (expected %s; it holds: %s)", path, ref[i].name, want, nth ? names : "nothing");
            goto done;
        }
        shape_text(match[i], have, sizeof have);
        if (match[i]->ndim != ref[i].ndim || memcmp(match[i]->shape, ref[i].shape, (size_t)ref[i].ndim * sizeof ref[i].shape[0])) {
            spr__error(a, "--grads: %s: %s has shape %s; expected %s (%zu Gaussians of the scene)", path, ref[i].name, have, want, g.n);
            goto done;
        }
        if (ref[i].type == SPR_NPY_F4 && match[i]->type != SPR_NPY_F4) {
            spr__error(a, "--grads: %s: %s is an integer array of shape %s; expected float (float32 or float64)", path, ref[i].name, have);
            goto done;
        }
    }
    const spr_gauss_profile *pf = spr_gauss_profile_of(rd.algo, rd.gauss_profile);
    char atol_text[64];
    if (atol >= 0.0) snprintf(atol_text, sizeof atol_text, "atol %.9g", atol);
    else snprintf(atol_text, sizeof atol_text, "atol 1e-6*max|ref| of each array");
    printf("check: %s vs the reference's gradients (cpu, gauss3d under %s), %s, %zu Gaussians, %dx%d\n", path, pf->name, s.model, g.n, g.width, g.height);
    printf("check: an entry passes when |theirs - ref| <= rtol*S_G + atol, S_G the largest |ref| of the Gaussian's row (means2d: and its absgrad); "
           "rtol %.9g, %s; counts exact\n", rtol, atol_text);
    if (out) rep = cJSON_CreateObject(), cJSON_AddStringToObject(rep, "grads", path), cJSON_AddNumberToObject(rep, "rtol", rtol);
    cJSON *jarr = rep ? cJSON_AddArrayToObject(rep, "arrays") : NULL;
    char failed[400] = "";
    int nfail = 0;
    for (int i = 0; i < nref; i++) {
        grad_cmp c;
        memset(&c, 0, sizeof c);
        c.name = ref[i].name, c.n = g.n;
        c.per = 1;
        for (int d = 1; d < ref[i].ndim; d++) c.per *= ref[i].shape[d];
        compare(&c, &ref[i], match[i], !strcmp(c.name, "means2d") ? g.absgrad : NULL, rtol, atol);
        char text[4096], r1[400], r2[400];
        int o = snprintf(text, sizeof text, "check: %s: %zu Gaussians, %zu fail, max |diff| %.9g (atol %.9g)", c.name, c.n, c.fail, c.max_abs, c.atol);
        if (c.nworst && c.per) {
            row_text(&ref[i], c.worst[0], c.per, r1, sizeof r1);
            row_text(match[i], c.worst[0], c.per, r2, sizeof r2);
            o += snprintf(text + o, sizeof text - (size_t)o, ", worst Gaussian %zu (ref %s, theirs %s)", c.worst[0], r1, r2);
        }
        o += snprintf(text + o, sizeof text - (size_t)o, "\n");
        for (int w = 0; c.fail && w < c.nworst && o < (int)sizeof text; w++) {
            if (!(c.ratio[w] > 1.0)) break;
            row_text(&ref[i], c.worst[w], c.per, r1, sizeof r1);
            row_text(match[i], c.worst[w], c.per, r2, sizeof r2);
            o += snprintf(text + o, sizeof text - (size_t)o, "check:   %s Gaussian %zu: ref %s, theirs %s, |diff| %.3g x its tolerance\n", c.name, c.worst[w], r1, r2,
                          c.ratio[w]);
        }
        fputs(text, stdout);
        if (c.fail) {
            const size_t l = strlen(failed);
            snprintf(failed + l, sizeof failed - l, "%s%.63s", nfail ? ", " : "", c.name);
            nfail++;
        }
        char msg[200];
        snprintf(msg, sizeof msg, "%.63s: %zu of %zu Gaussians outside rtol %.9g, atol %.9g", c.name, c.fail, c.n, rtol, c.atol);
        cli_junit_add(ju, "splatref.check.grads", c.name, 0.0, c.fail ? CLI_JUNIT_FAILURE : CLI_JUNIT_PASS, msg, text);
        if (jarr) {
            cJSON *o2 = cJSON_CreateObject();
            cJSON_AddStringToObject(o2, "name", c.name);
            cJSON_AddNumberToObject(o2, "gaussians", (double)c.n);
            cJSON_AddNumberToObject(o2, "fail", (double)c.fail);
            cJSON_AddNumberToObject(o2, "max_abs", isfinite(c.max_abs) ? c.max_abs : -1.0);
            cJSON_AddNumberToObject(o2, "atol", c.atol);
            cJSON *wl = cJSON_AddArrayToObject(o2, "worst");
            for (int w = 0; w < c.nworst && c.per; w++) {
                cJSON *e = cJSON_CreateObject();
                cJSON_AddNumberToObject(e, "gaussian", (double)c.worst[w]);
                cJSON_AddNumberToObject(e, "ratio", isfinite(c.ratio[w]) ? c.ratio[w] : -1.0);
                cJSON *rv = cJSON_AddArrayToObject(e, "ref"), *tv = cJSON_AddArrayToObject(e, "theirs");
                for (size_t k = 0; k < c.per; k++) {
                    cJSON_AddItemToArray(rv, cJSON_CreateNumber(val(&ref[i], c.worst[w] * c.per + k)));
                    const double t = val(match[i], c.worst[w] * c.per + k);
                    cJSON_AddItemToArray(tv, isfinite(t) ? cJSON_CreateNumber(t) : cJSON_CreateNull());
                }
                cJSON_AddItemToArray(wl, e);
            }
            cJSON_AddItemToArray(jarr, o2);
        }
    }
    rc = nfail ? 1 : 0;
    if (rep) {
        char tmp[1200], p[1400];
        cJSON_AddStringToObject(rep, "verdict", rc ? "fail" : "pass");
        if (cli_outdir_begin(a, "out", out, tmp, sizeof tmp)) rc = 2;
        else {
            snprintf(p, sizeof p, "%s/report.json", tmp);
            const int bad = spr__write_json(a, p, rep) != 0; /* it takes rep */
            rep = NULL;
            if (cli_outdir_end(a, "out", tmp, out, !bad) || bad) rc = 2;
            else printf("check: report %s/report.json\n", out);
        }
    }
    if (ju && rc != 2 && cli_junit_write(a, ju, junit)) rc = 2;
    if (rc == 0) printf("verdict: PASS (%d arrays; rtol %.9g, %s)\n", nref, rtol, atol_text);
    else if (rc == 1) printf("verdict: FAIL (%s; rtol %.9g, %s)\n", failed, rtol, atol_text);
done:
    cJSON_Delete(rep);
    cli_junit_free(ju);
    free(sh0), free(shN);
    spr_npz_free(th, nth);
    spr_gauss_grads_free(&g);
    cli_grad_inputs_free(&in);
    if (b) spr_backend_destroy(b);
    spr_scene_free(&s);
    return rc;
}
