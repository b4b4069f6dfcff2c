/* gauss_bin.c — items binned to the 16×16 tiles of the Gaussian
 * algorithms, each tile's items in item order (SPEC §10.3 step 8, §10.7).
 *
 * The items are cut into chunks; each chunk counts its entries per tile, a
 * prefix over (tile, chunk) gives every chunk its place in every tile's
 * run, and each chunk writes its entries there.  The chunks follow each
 * other in item order, so the lists are the same for any thread count.
 * Used by the host's tile lists (core/algo/gauss.c) and by the CPU
 * backend's gauss-blend draw (swrast/sw_gauss.c).
 */
#include "spr_backend.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

void *spr__big_alloc(size_t bytes);

spr_result spr__gauss_bin(size_t n, spr__gauss_rect_fn rect, const void *user, int gx, int gy, int threads, uint32_t **range_out,
                          uint32_t **list_out, spr_error *err)
{
    const size_t nt = (size_t)gx * gy;
    if (threads <= 0) threads = omp_get_max_threads();
    const int nchunks = threads * 4; /* any count: the chunks are concatenated in order */
    uint32_t *cnt = calloc(nt * (size_t)nchunks, sizeof *cnt), *range = calloc(nt + 1, sizeof *range), *list = NULL;
    if (!cnt || !range) {
        free(cnt), free(range);
        return spr__fail(err, SPR_E_NOMEM, "gauss: out of memory for %zu tiles", nt);
    }
    const size_t chunk = (n + (size_t)nchunks - 1) / (size_t)nchunks;
#pragma omp parallel for num_threads(threads) schedule(static, 1)
    for (int ch = 0; ch < nchunks; ch++) {
        uint32_t *c = cnt + (size_t)ch * nt;
        for (size_t k = (size_t)ch * chunk; k < n && k < (size_t)(ch + 1) * chunk; k++) {
            int r[4];
            rect(user, k, r);
            for (int ty = r[1]; ty < r[3]; ty++)
                for (int tx = r[0]; tx < r[2]; tx++) c[(size_t)ty * gx + tx]++;
        }
    }
    uint64_t total = 0;
    for (size_t t = 0; t < nt; t++) { /* (tile, chunk) order: each tile's entries in item order */
        range[t] = (uint32_t)total;
        for (int ch = 0; ch < nchunks; ch++) {
            uint32_t k = cnt[(size_t)ch * nt + t];
            cnt[(size_t)ch * nt + t] = (uint32_t)total;
            total += k;
        }
        if (total > UINT32_MAX || total - range[t] > (1u << 24)) {
            free(cnt), free(range);
            return spr__fail(err, SPR_E_TOO_LARGE, "gauss: tile %zu lists more than 2^24 Gaussians (or all tiles more than 2^32)", t);
        }
    }
    range[nt] = (uint32_t)total;
    if (!(list = spr__big_alloc(total * sizeof *list))) {
        free(cnt), free(range);
        return spr__fail(err, SPR_E_NOMEM, "gauss: out of memory for %llu tile entries", (unsigned long long)total);
    }
#pragma omp parallel for num_threads(threads) schedule(static, 1)
    for (int ch = 0; ch < nchunks; ch++) {
        uint32_t *off = cnt + (size_t)ch * nt;
        for (size_t k = (size_t)ch * chunk; k < n && k < (size_t)(ch + 1) * chunk; k++) {
            int r[4];
            rect(user, k, r);
            for (int ty = r[1]; ty < r[3]; ty++)
                for (int tx = r[0]; tx < r[2]; tx++) list[off[(size_t)ty * gx + tx]++] = (uint32_t)k;
        }
    }
    free(cnt);
    *range_out = range;
    *list_out = list;
    return SPR_OK;
}
