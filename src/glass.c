/* Refractive index of the media a lens is made of.
 *
 * The (n_d, V_d) model glass: a two-term Cauchy law n(l) = A + B / l^2 with A and B
 * chosen so that n(d) = n_d and n(F) - n(C) = (n_d - 1) / V_d exactly. Assumptions:
 * the glass is a normal glass (no anomalous partial dispersion), and the law is used
 * only over 0.36 .. 1.0 um, where Cauchy's two terms follow catalog glasses to a few
 * 1e-4 in index; outside that range it is an error, not an extrapolation. */
#include "glass.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "glass_formula.h"

#define NDVD_LAMBDA_MIN 0.36
#define NDVD_LAMBDA_MAX 1.0

glass_t glass_air(void)
{
    glass_t g;
    memset(&g, 0, sizeof g);
    g.kind = GLASS_AIR;
    g.nd = 1.0;
    g.lambda_min = 0.0;
    g.lambda_max = INFINITY;
    return g;
}

glass_t glass_constant(double nd)
{
    glass_t g = glass_air();
    g.kind = GLASS_CONSTANT;
    g.nd = nd;
    return g;
}

glass_t glass_from_ndvd(double nd, double vd)
{
    glass_t g = glass_air();
    g.kind = GLASS_NDVD;
    g.nd = nd;
    g.vd = vd;
    double inv_f2 = 1.0 / (GLASS_F_LINE * GLASS_F_LINE);
    double inv_c2 = 1.0 / (GLASS_C_LINE * GLASS_C_LINE);
    double b = (nd - 1.0) / (vd * (inv_f2 - inv_c2));
    g.coef[1] = b;
    g.coef[0] = nd - b / (GLASS_D_LINE * GLASS_D_LINE);
    g.lambda_min = NDVD_LAMBDA_MIN;
    g.lambda_max = NDVD_LAMBDA_MAX;
    return g;
}

double glass_index_unchecked(const glass_t *g, double l)
{
    switch (g->kind) {
    case GLASS_AIR:
        return 1.0;
    case GLASS_CONSTANT:
        return g->nd;
    case GLASS_NDVD:
        return g->coef[0] + g->coef[1] / (l * l);
    case GLASS_FORMULA:
        return glass_formula_eval(g->formula, g->coef, l);
    }
    return NAN;
}

int glass_index(const glass_t *g, double l, double *n, lens_err *err)
{
    if (!(l >= g->lambda_min && l <= g->lambda_max)) {
        lens_errf(err, NULL, 0, "wavelength %g um is outside the range %g..%g um of %s", l,
                  g->lambda_min, g->lambda_max, g->name[0] ? g->name : "the glass model");
        return -1;
    }
    double v = glass_index_unchecked(g, l);
    if (!isfinite(v) || v < 1.0) {
        lens_errf(err, NULL, 0, "glass %s has no real index at %g um", g->name, l);
        return -1;
    }
    *n = v;
    return 0;
}
