#include "glass_formula.h"

#include <math.h>

#include "glass.h"

double glass_formula_eval(int formula, const double *c, double l)
{
    double l2 = l * l, n2;
    switch (formula) {
    case GLASS_F_SELLMEIER1:
        n2 = 1.0 + c[0] * l2 / (l2 - c[1]) + c[2] * l2 / (l2 - c[3]) + c[4] * l2 / (l2 - c[5]);
        break;
    default:
        return NAN;
    }
    return n2 > 0 ? sqrt(n2) : NAN;
}

int glass_formula_ncoef(int formula)
{
    return formula == GLASS_F_SELLMEIER1 ? 6 : 0;
}

const char *glass_formula_name(int formula)
{
    return formula == GLASS_F_SELLMEIER1 ? "Sellmeier 1" : "unknown";
}
