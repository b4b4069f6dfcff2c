/* pca.c — cyclic Jacobi for 3×3 symmetric matrices: a fixed sequence of
 * rotations, so the result is reproducible to the bit. */
#include "spr_pca.h"

#include <math.h>

void spr_eigen3_sym(const double A[6], double eval[3], double evec[9])
{
    double a[3][3] = {{A[0], A[1], A[2]}, {A[1], A[3], A[4]}, {A[2], A[4], A[5]}};
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
        double scale = fabs(a[0][0]) + fabs(a[1][1]) + fabs(a[2][2]);
        if (off <= 1e-300 || off <= 1e-17 * scale) break;
        for (int p = 0; p < 2; p++) {
            for (int q = p + 1; q < 3; q++) {
                if (a[p][q] == 0.0) continue;
                double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; k++) {
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; k++) {
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; k++) {
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }
    int order[3] = {0, 1, 2};
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++)
            if (a[order[j]][order[j]] < a[order[i]][order[i]]) { int t = order[i]; order[i] = order[j]; order[j] = t; }
    for (int k = 0; k < 3; k++) {
        eval[k] = a[order[k]][order[k]];
        for (int r = 0; r < 3; r++) evec[3 * k + r] = v[r][order[k]];
    }
}

void spr_pca_local(const float *pos, size_t i, const uint32_t *nb, int k, double eval[3], double evec[9])
{
    double mean[3] = {pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]};
    int m = 1;
    for (int j = 0; j < k; j++) {
        if (nb[j] == UINT32_MAX) continue;
        for (int d = 0; d < 3; d++) mean[d] += pos[3 * (size_t)nb[j] + d];
        m++;
    }
    for (int d = 0; d < 3; d++) mean[d] /= m;
    double A[6] = {0};
    for (int j = -1; j < k; j++) {
        uint32_t o = j < 0 ? (uint32_t)i : nb[j];
        if (o == UINT32_MAX) continue;
        double q[3] = {pos[3 * (size_t)o] - mean[0], pos[3 * (size_t)o + 1] - mean[1], pos[3 * (size_t)o + 2] - mean[2]};
        A[0] += q[0] * q[0]; A[1] += q[0] * q[1]; A[2] += q[0] * q[2];
        A[3] += q[1] * q[1]; A[4] += q[1] * q[2]; A[5] += q[2] * q[2];
    }
    spr_eigen3_sym(A, eval, evec);
}
