/* The samples' side of a fit (fit_internal.h): a chosen set of terms evaluated at a
 * sample, and the final least-squares solve by Householder QR on the sample columns,
 * which fit_select's moment-metric work only chooses the terms for. */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit/fit_internal.h"

double fit_eval_sample(const fit_basis *b, const fit_powers *p, size_t i, int k,
                       const int *cand, const double *coef)
{
    double sum = 0;
    for (int t = 0; t < k; t++) {
        const int *a = b->exps + (size_t)cand[t] * b->nvar;
        double m = coef[t];
        for (int v = 0; v < b->nvar; v++)
            if (a[v])
                m *= fit_pow_row(p, v, a[v])[i];
        sum += m;
    }
    return sum;
}

int fit_lsq(const fit_basis *b, const fit_powers *p, const double *y, int k, const int *cand,
            double *coef)
{
    size_t m = p->n;
    if (k < 1 || m < (size_t)k)
        return -1;
    double *A = malloc(m * (size_t)k * sizeof *A);
    double *B = malloc(m * sizeof *B);
    double *nrm = malloc((size_t)k * sizeof *nrm);
    int rc = -1;
    if (!A || !B || !nrm)
        goto out;
    for (int t = 0; t < k; t++) {
        double *col = A + (size_t)t * m;
        fit_column(p, b->exps + (size_t)cand[t] * b->nvar, col);
        double s = sqrt(fit_dot(col, col, m));
        if (!(s > 0))
            goto out;
        nrm[t] = s;
        for (size_t i = 0; i < m; i++)
            col[i] /= s;
    }
    memcpy(B, y, m * sizeof *B);
    lapack_int info = LAPACKE_dgels(LAPACK_COL_MAJOR, 'N', (lapack_int)m, k, 1, A,
                                    (lapack_int)m, B, (lapack_int)m);
    if (info != 0)
        goto out;
    double rmax = 0, rmin = INFINITY;
    for (int t = 0; t < k; t++) {
        double d = fabs(A[(size_t)t * m + t]);
        rmax = d > rmax ? d : rmax;
        rmin = d < rmin ? d : rmin;
    }
    if (!(rmin > 1e-13 * rmax))
        goto out;
    for (int t = 0; t < k; t++)
        coef[t] = B[t] / nrm[t];
    rc = 0;
out:
    free(A);
    free(B);
    free(nrm);
    return rc;
}
