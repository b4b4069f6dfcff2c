/* csr.c — the small sparse-matrix type of the decomposition (SPEC §7.2).
 * A library would be one more dependency for a product and a transpose;
 * Debian's sparse libraries (SuiteSparse) bring far more than this needs. */
#include "spr_domain.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void spr_csr_free(spr_csr *m)
{
    free(m->ptr);
    free(m->col);
    free(m->val);
    memset(m, 0, sizeof *m);
}

/* Row by row with a dense accumulator over b's columns (Gustavson): the
 * columns touched are collected, sorted, and read out in order. */
spr_result spr_csr_mul(const spr_csr *a, const spr_csr *b, double drop, spr_csr *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    if (a->cols != b->rows) return spr__fail(err, SPR_E_ARG, "csr: %zu×%zu times %zu×%zu", a->rows, a->cols, b->rows, b->cols);
    double *acc = calloc(b->cols ? b->cols : 1, sizeof *acc);
    unsigned char *seen = calloc(b->cols ? b->cols : 1, 1);
    uint32_t *touched = malloc((b->cols ? b->cols : 1) * sizeof *touched);
    size_t cap = a->ptr[a->rows] + 16, nnz = 0;
    out->rows = a->rows;
    out->cols = b->cols;
    out->ptr = malloc((a->rows + 1) * sizeof *out->ptr);
    out->col = malloc(cap * sizeof *out->col);
    out->val = malloc(cap * sizeof *out->val);
    if (!acc || !seen || !touched || !out->ptr || !out->col || !out->val) goto oom;
    out->ptr[0] = 0;
    for (size_t i = 0; i < a->rows; i++) {
        size_t nt = 0;
        for (size_t p = a->ptr[i]; p < a->ptr[i + 1]; p++) {
            const uint32_t k = a->col[p];
            const double av = a->val[p];
            for (size_t q = b->ptr[k]; q < b->ptr[k + 1]; q++) {
                const uint32_t j = b->col[q];
                if (!seen[j]) seen[j] = 1, touched[nt++] = j, acc[j] = 0.0;
                acc[j] += av * b->val[q];
            }
        }
        /* ascending columns: a counting-free insertion sort (rows are short) */
        for (size_t x = 1; x < nt; x++) {
            uint32_t v = touched[x];
            size_t y = x;
            while (y > 0 && touched[y - 1] > v) touched[y] = touched[y - 1], y--;
            touched[y] = v;
        }
        double big = 0.0, sum = 0.0, kept = 0.0;
        for (size_t x = 0; x < nt; x++) {
            double v = acc[touched[x]];
            sum += v;
            if (fabs(v) > big) big = fabs(v);
        }
        if (nnz + nt > cap) {
            cap = 2 * (nnz + nt);
            uint32_t *nc = realloc(out->col, cap * sizeof *nc);
            if (nc) out->col = nc;
            double *nv = realloc(out->val, cap * sizeof *nv);
            if (nv) out->val = nv;
            if (!nc || !nv) goto oom;
        }
        const size_t row0 = nnz;
        for (size_t x = 0; x < nt; x++) {
            const uint32_t j = touched[x];
            seen[j] = 0;
            if (drop > 0.0 && fabs(acc[j]) < drop * big) continue;
            out->col[nnz] = j;
            out->val[nnz++] = acc[j];
            kept += acc[j];
        }
        if (drop > 0.0 && kept != 0.0 && kept != sum) /* the dropped mass goes back to the kept entries */
            for (size_t x = row0; x < nnz; x++) out->val[x] *= sum / kept;
        out->ptr[i + 1] = nnz;
    }
    free(acc);
    free(seen);
    free(touched);
    return SPR_OK;
oom:
    free(acc);
    free(seen);
    free(touched);
    spr_csr_free(out);
    return spr__fail(err, SPR_E_NOMEM, "csr: out of memory for a %zu×%zu product", a->rows, b->cols);
}

void spr_domain_strict(const spr_csr *basis, int32_t *domain)
{
    for (size_t i = 0; i < basis->rows; i++) {
        int32_t best = -1;
        double bv = -1.0;
        for (size_t p = basis->ptr[i]; p < basis->ptr[i + 1]; p++)
            if (basis->val[p] > bv) bv = basis->val[p], best = (int32_t)basis->col[p]; /* ascending columns: ties keep the lowest */
        domain[i] = best;
    }
}

/* Entry q of row i belongs to its domain: φ ≥ K, or (strict) it is the
 * row's largest (the first of equal ones: the lowest region). */
static int member(const spr_csr *b, size_t i, size_t q, int strict, double K)
{
    if (!strict) return b->val[q] >= K;
    for (size_t p = b->ptr[i]; p < b->ptr[i + 1]; p++)
        if (b->val[p] > b->val[q] || (b->val[p] == b->val[q] && p < q)) return 0;
    return 1;
}

spr_result spr_domain_members(const spr_csr *basis, int strict, double K, spr_csr *out, spr_error *err)
{
    memset(out, 0, sizeof *out);
    out->rows = basis->cols;
    out->cols = basis->rows;
    size_t nnz = 0;
    out->ptr = calloc(out->rows + 1, sizeof *out->ptr);
    if (!out->ptr) return spr__fail(err, SPR_E_NOMEM, "domains: out of memory");
    for (size_t i = 0; i < basis->rows; i++)
        for (size_t p = basis->ptr[i]; p < basis->ptr[i + 1]; p++)
            if (member(basis, i, p, strict, K)) out->ptr[basis->col[p] + 1]++, nnz++;
    for (size_t j = 0; j < out->rows; j++) out->ptr[j + 1] += out->ptr[j];
    out->col = malloc((nnz ? nnz : 1) * sizeof *out->col);
    out->val = malloc((nnz ? nnz : 1) * sizeof *out->val);
    size_t *fill = malloc((out->rows ? out->rows : 1) * sizeof *fill);
    if (!out->col || !out->val || !fill) {
        free(fill);
        spr_csr_free(out);
        return spr__fail(err, SPR_E_NOMEM, "domains: out of memory");
    }
    memcpy(fill, out->ptr, out->rows * sizeof *fill);
    for (size_t i = 0; i < basis->rows; i++) /* points in ascending order within each domain */
        for (size_t p = basis->ptr[i]; p < basis->ptr[i + 1]; p++)
            if (member(basis, i, p, strict, K)) {
                size_t q = fill[basis->col[p]]++;
                out->col[q] = (uint32_t)i;
                out->val[q] = basis->val[p];
            }
    free(fill);
    return SPR_OK;
}
