/* A glass given as a table of indices (CODE V private glasses, PRV): the Schott power
 * series fitted to the table by least squares, so that it disperses between and around
 * the tabulated lines as the glass does, rather than through n_d and V_d alone (which
 * also need the d, F and C lines to be in the table). */
#include "sparselens/glass.h"
#include "sparselens/glass_formula.h"

#include <math.h>
#include <string.h>

/* The Schott formula's terms in the order they are taken (fewer points, fewer terms):
 * n^2 = c0 + c1 l^2 + c2 l^-2 + c3 l^-4 + c4 l^-6 + c5 l^-8. */
static const int term_order[6] = {0, 2, 1, 3, 4, 5};

static double term(int k, double l)
{
    double l2 = l * l;
    switch (k) {
    case 0: return 1;
    case 1: return l2;
    default: return pow(l2, -(k - 1));
    }
}

int glass_fit_table(const double *lambda_um, const double *index, int count, glass_t *g,
                    double *max_residual)
{
    enum { MAXP = 64, MAXT = 6 };
    if (count < 2 || count > MAXP)
        return -1;
    int m = count < MAXT ? count : MAXT;
    double a[MAXP][MAXT], b[MAXP], r[MAXT][MAXT] = {{0}}, qb[MAXT];
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < count; i++) {
        if (!(lambda_um[i] > 0) || !(index[i] >= 1) || !isfinite(index[i]))
            return -1;
        lo = fmin(lo, lambda_um[i]), hi = fmax(hi, lambda_um[i]);
        for (int j = 0; j < m; j++)
            a[i][j] = term(term_order[j], lambda_um[i]);
        b[i] = index[i] * index[i];
    }
    /* modified Gram-Schmidt: the powers of l^-2 span four decades over a glass's range,
     * where the normal equations would lose the digits the fit is for */
    for (int j = 0; j < m; j++) {
        for (int k = 0; k < j; k++) {
            double d = 0;
            for (int i = 0; i < count; i++)
                d += a[i][k] * a[i][j];
            r[k][j] = d;
            for (int i = 0; i < count; i++)
                a[i][j] -= d * a[i][k];
        }
        double nn = 0;
        for (int i = 0; i < count; i++)
            nn += a[i][j] * a[i][j];
        nn = sqrt(nn);
        if (!(nn > 0))
            return -1;
        r[j][j] = nn;
        for (int i = 0; i < count; i++)
            a[i][j] /= nn;
    }
    for (int j = 0; j < m; j++) {
        double d = 0;
        for (int i = 0; i < count; i++)
            d += a[i][j] * b[i];
        qb[j] = d;
    }
    double x[MAXT];
    for (int j = m - 1; j >= 0; j--) {
        double s = qb[j];
        for (int k = j + 1; k < m; k++)
            s -= r[j][k] * x[k];
        x[j] = s / r[j][j];
    }
    glass_t out = glass_air();
    out.kind = GLASS_FORMULA;
    out.formula = GLASS_F_SCHOTT;
    memset(out.coef, 0, sizeof out.coef);
    for (int j = 0; j < m; j++)
        out.coef[term_order[j]] = x[j];
    out.lambda_min = lo, out.lambda_max = hi;
    double worst = 0;
    for (int i = 0; i < count; i++) {
        double n = glass_formula_eval(GLASS_F_SCHOTT, out.coef, lambda_um[i]);
        if (!(n > 0))
            return -1;
        worst = fmax(worst, fabs(n - index[i]));
    }
    double nf = glass_formula_eval(GLASS_F_SCHOTT, out.coef, 0.4861327);
    double nc = glass_formula_eval(GLASS_F_SCHOTT, out.coef, 0.6562725);
    out.nd = glass_formula_eval(GLASS_F_SCHOTT, out.coef, GLASS_D_LINE);
    out.vd = nf > nc ? (out.nd - 1) / (nf - nc) : 0;
    *g = out;
    *max_residual = worst;
    return 0;
}
