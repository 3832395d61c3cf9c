/* The thirteen dispersion formulas of Zemax AGF glass catalogs, by AGF formula number.
 * Coefficients come in the order of an AGF "CD" line; wavelengths in um. The formulas
 * (from the Zemax manual's glass catalog chapter; L-type constants are in um^2):
 *  1 Schott       n^2 = a0 + a1 l^2 + a2 l^-2 + a3 l^-4 + a4 l^-6 + a5 l^-8
 *  2 Sellmeier 1  n^2 - 1 = sum_{i<3} K_i l^2 / (l^2 - L_i)          (K1 L1 K2 L2 K3 L3)
 *  3 Herzberger   n = A + B L + C L^2 + D l^2 + E l^4 + F l^6,  L = 1 / (l^2 - 0.028)
 *  4 Sellmeier 2  n^2 - 1 = A + B1 l^2 / (l^2 - l1^2) + B2 / (l^2 - l2^2) (A B1 l1 B2 l2)
 *  5 Conrady      n = n0 + A / l + B / l^3.5
 *  6 Sellmeier 3  as 2 with four terms
 *  7 Handbook 1   n^2 = A + B / (l^2 - C) - D l^2
 *  8 Handbook 2   n^2 = A + B l^2 / (l^2 - C) - D l^2
 *  9 Sellmeier 4  n^2 = A + B l^2 / (l^2 - C) + D l^2 / (l^2 - E)
 * 10 Extended 1   Schott + a6 l^-10 + a7 l^-12
 * 11 Sellmeier 5  as 2 with five terms
 * 12 Extended 2   Schott + a6 l^4 + a7 l^6
 * 13 Extended 3   n^2 = a0 + a1 l^2 + a2 l^4 + a3 l^-2 + a4 l^-4 + a5 l^-6 + a6 l^-8
 *                       + a7 l^-10 + a8 l^-12 */
#include "sparselens/glass_formula.h"

#include <math.h>

#include "sparselens/glass.h"

static const struct {
    int ncoef;
    const char *name;
} formulas[] = {
    [GLASS_F_SCHOTT] = {6, "Schott"},         [GLASS_F_SELLMEIER1] = {6, "Sellmeier 1"},
    [GLASS_F_HERZBERGER] = {6, "Herzberger"}, [GLASS_F_SELLMEIER2] = {5, "Sellmeier 2"},
    [GLASS_F_CONRADY] = {3, "Conrady"},       [GLASS_F_SELLMEIER3] = {8, "Sellmeier 3"},
    [GLASS_F_HANDBOOK1] = {4, "Handbook of Optics 1"},
    [GLASS_F_HANDBOOK2] = {4, "Handbook of Optics 2"},
    [GLASS_F_SELLMEIER4] = {5, "Sellmeier 4"}, [GLASS_F_EXTENDED1] = {8, "Extended 1"},
    [GLASS_F_SELLMEIER5] = {10, "Sellmeier 5"}, [GLASS_F_EXTENDED2] = {8, "Extended 2"},
    [GLASS_F_EXTENDED3] = {9, "Extended 3"},
};

static int known(int formula)
{
    return formula >= GLASS_F_SCHOTT && formula <= GLASS_F_EXTENDED3;
}

/* sum of nterms resonance terms K l^2 / (l^2 - L), coefficients as K1 L1 K2 L2 ... */
static double resonances(const double *c, int nterms, double l2)
{
    double s = 0;
    for (int i = 0; i < nterms; i++)
        s += c[2 * i] * l2 / (l2 - c[2 * i + 1]);
    return s;
}

/* a0 + a1 l^2 + a2 l^-2 + a3 l^-4 + ... + a_{n-1} l^-(2(n-2)) (Schott and its extensions) */
static double laurent(const double *c, int n, double l2)
{
    double inv = 1.0 / l2, p = 0;
    for (int i = n - 1; i >= 2; i--)
        p = (p + c[i]) * inv;
    return c[0] + c[1] * l2 + p;
}

double glass_formula_eval(int formula, const double *c, double l)
{
    double l2 = l * l, n2;
    switch (formula) {
    case GLASS_F_SCHOTT:
        n2 = laurent(c, 6, l2);
        break;
    case GLASS_F_SELLMEIER1:
        n2 = 1.0 + resonances(c, 3, l2);
        break;
    case GLASS_F_HERZBERGER: {
        double L = 1.0 / (l2 - 0.028);
        return c[0] + L * (c[1] + L * c[2]) + l2 * (c[3] + l2 * (c[4] + l2 * c[5]));
    }
    case GLASS_F_SELLMEIER2:
        n2 = 1.0 + c[0] + c[1] * l2 / (l2 - c[2] * c[2]) + c[3] / (l2 - c[4] * c[4]);
        break;
    case GLASS_F_CONRADY:
        return c[0] + c[1] / l + c[2] / pow(l, 3.5);
    case GLASS_F_SELLMEIER3:
        n2 = 1.0 + resonances(c, 4, l2);
        break;
    case GLASS_F_HANDBOOK1:
        n2 = c[0] + c[1] / (l2 - c[2]) - c[3] * l2;
        break;
    case GLASS_F_HANDBOOK2:
        n2 = c[0] + c[1] * l2 / (l2 - c[2]) - c[3] * l2;
        break;
    case GLASS_F_SELLMEIER4:
        n2 = c[0] + c[1] * l2 / (l2 - c[2]) + c[3] * l2 / (l2 - c[4]);
        break;
    case GLASS_F_EXTENDED1:
        n2 = laurent(c, 8, l2);
        break;
    case GLASS_F_SELLMEIER5:
        n2 = 1.0 + resonances(c, 5, l2);
        break;
    case GLASS_F_EXTENDED2:
        n2 = laurent(c, 6, l2) + c[6] * l2 * l2 + c[7] * l2 * l2 * l2;
        break;
    case GLASS_F_EXTENDED3: {
        double inv = 1.0 / l2, p = 0;
        for (int i = 8; i >= 3; i--)
            p = (p + c[i]) * inv;
        n2 = c[0] + l2 * (c[1] + l2 * c[2]) + p;
        break;
    }
    default:
        return NAN;
    }
    return n2 > 0 ? sqrt(n2) : NAN;
}

int glass_formula_ncoef(int formula)
{
    return known(formula) ? formulas[formula].ncoef : 0;
}

const char *glass_formula_name(int formula)
{
    return known(formula) ? formulas[formula].name : "unknown";
}
