/* spr_npy.h — NumPy arrays on disk: .npy files and .npz archives (issue 43).
 *
 * What the gradients work exchanges with Python: images, per-splat
 * parameters and their gradients as float32, counts as int32.  Reading takes
 * what numpy's np.save / np.savez / np.savez_compressed write (format
 * versions 1.0, 2.0 and 3.0; npz members stored or deflated, zip64 fields
 * included, through libzip); writing gives version 1.0 files that np.load
 * reads, an .npz as a stored zip like np.savez's.
 *
 * Invariants of every array handed out: 0 ≤ ndim ≤ 4 (0: a scalar, one
 * element), at most SPR_NPY_MAX_ELEMS elements, data malloc'd in C order
 * (last index fastest), host byte order, never NULL (one byte for an empty
 * array), type SPR_NPY_F4 or SPR_NPY_I4.  Conversions on reading:
 *   float  <f4 >f4 <f8 >f8 (and '=' / native)  → float32, f8 rounded once to nearest;
 *          NaN and infinities are kept (I/O does not judge values);
 *   int    i1 i2 i4 i8 u1 u2 u4 u8 and b1, either byte order → int32, exactly:
 *          a value outside int32 is refused, naming its element;
 *   other  (f2, complex, strings, objects, structured dtypes) are refused.
 * A Fortran-order array is refused (one line: it would need a transpose).
 * Every failure is one line naming the file and the byte offset, or the npz
 * member; nothing is allocated or handed out on failure.  Writing goes
 * through a temporary file renamed into place: a failure leaves no file.
 */
#ifndef SPR_NPY_H
#define SPR_NPY_H

#include <stddef.h>
#include "spr_result.h"

/* Elements one array may have (2^31): beyond it a file is refused before any allocation. */
#define SPR_NPY_MAX_ELEMS ((size_t)1 << 31)
#define SPR_NPY_MAX_DIMS 4

typedef enum spr_npy_type { SPR_NPY_F4, SPR_NPY_I4 } spr_npy_type; /* float32 / int32: what is read and written */

typedef struct spr_npy {
    char name[64];          /* npz member name without ".npy" ("" for a lone .npy) */
    int ndim;               /* 0 … 4 */
    size_t shape[SPR_NPY_MAX_DIMS];
    spr_npy_type type;
    void *data;             /* float or int32_t, C order, malloc'd */
} spr_npy;

/* Number of elements of a (the product of its shape; 1 for ndim 0). */
size_t spr_npy_count(const spr_npy *a);

/* One .npy file into *out (name ""); on failure *out is zeroed. */
spr_result spr_npy_read(const char *path, spr_npy *out, spr_error *err);
/* Every member of an .npz, in the zip's order, into a malloc'd array of *n (NULL when 0); free with spr_npz_free.
 * Members must be named NAME.npy (NAME 1 … 63 bytes) and distinct. */
spr_result spr_npz_read(const char *path, spr_npy **arrays, int *n, spr_error *err);
/* a as a version 1.0 .npy ('<f4' or '<i4'), through a temporary file. */
spr_result spr_npy_write(const char *path, const spr_npy *a, spr_error *err);
/* n arrays as an .npz of stored members NAME.npy (names distinct, not empty), through a temporary file.  The
 * bytes depend on the arrays only (every member's time is 1980-01-01 00:00); no zip64: an archive reaching
 * 4 GiB is refused. */
spr_result spr_npz_write(const char *path, const spr_npy *arrays, int n, spr_error *err);
/* Frees a->data and zeroes *a (a zeroed array is fine). */
void spr_npy_free(spr_npy *a);
/* Frees each of the n arrays and the array itself (NULL is fine). */
void spr_npz_free(spr_npy *arrays, int n);

/* ---- internal: the parsers over bytes in memory, used by the readers and tests/fuzz (path only names the input
 * in messages) ---- */
/* A whole .npy; name is copied into out->name (NULL: ""). */
spr_result spr__parse_npy(const char *path, const void *buf, size_t len, const char *name, spr_npy *out, spr_error *err);
/* A whole .npz (a zip). */
spr_result spr__parse_npz(const char *path, const void *buf, size_t len, spr_npy **arrays, int *n, spr_error *err);

#endif
