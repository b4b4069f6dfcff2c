/* spr_pca.h — deterministic 3×3 symmetric eigensolver (cyclic Jacobi, SPEC §7.1). */
#ifndef SPR_PCA_H
#define SPR_PCA_H

#include <stddef.h>
#include <stdint.h>

/* A = {a00, a01, a02, a11, a12, a22}.  Eigenvalues ascending in eval[0..2];
 * evec[3k..3k+2] is the unit eigenvector of eval[k]. */
void spr_eigen3_sym(const double A[6], double eval[3], double evec[9]);

/* PCA of point i of pos (3 floats each) and its neighbours nb[0 … k)
 * (UINT32_MAX entries skipped): the covariance about their mean, in double,
 * through spr_eigen3_sym (SPEC §7.1; the normals of §1 use it too). */
void spr_pca_local(const float *pos, size_t i, const uint32_t *nb, int k, double eval[3], double evec[9]);

#endif
