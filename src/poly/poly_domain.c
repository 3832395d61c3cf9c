/* Where a system may be asked: the sensor region and wavelengths it was fitted over.
 * A system answers anywhere (a polynomial extrapolates without a sign of it), so the
 * imaging analyses ask this before they trust a field (imaging.c, imaging_chief). */
#include <math.h>
#include <stdio.h>

#include "sparselens/poly.h"
#include "poly/poly_impl.h"

/* Rounding of the training range: the last sample of a range lies a hair inside the
 * sensor edge it was drawn from, and a field on that edge is inside. */
#define DOMAIN_SLACK 1e-3

static double reach(double lo, double hi)
{
    return fmax(fabs(lo), fabs(hi));
}

int poly_sensor_in_domain(const poly_system *s, double x, double y, double lambda, char *why,
                          size_t n)
{
    int ix = poly_input_index(s, "x"), iy = poly_input_index(s, "y");
    int il = poly_input_index(s, "lambda");
    if (ix >= 0 && iy >= 0 && isfinite(s->lo[ix]) && isfinite(s->hi[ix]) &&
        isfinite(s->lo[iy]) && isfinite(s->hi[iy])) {
        double rx = reach(s->lo[ix], s->hi[ix]), ry = reach(s->lo[iy], s->hi[iy]);
        if (poly_get_frame(s) == POLY_FRAME_MERIDIONAL) {
            /* the polynomials see the radius only: the training sensor's corner radius */
            double rmax = hypot(rx, ry), r = hypot(x, y);
            if (!(r <= rmax * (1 + DOMAIN_SLACK))) {
                snprintf(why, n, "the sensor point at radius %.4g mm lies outside the system's "
                                 "training domain (sensor radius up to %.4g mm)", r, rmax);
                return 0;
            }
        } else if (!(x >= s->lo[ix] - DOMAIN_SLACK * rx && x <= s->hi[ix] + DOMAIN_SLACK * rx &&
                     y >= s->lo[iy] - DOMAIN_SLACK * ry && y <= s->hi[iy] + DOMAIN_SLACK * ry)) {
            snprintf(why, n, "the sensor point (%.4g, %.4g) mm lies outside the system's training "
                             "domain (x %.4g..%.4g, y %.4g..%.4g mm)",
                     x, y, s->lo[ix], s->hi[ix], s->lo[iy], s->hi[iy]);
            return 0;
        }
    }
    if (il >= 0 && isfinite(lambda)) {
        double lo = s->lo[il], hi = s->hi[il], tol = DOMAIN_SLACK * (isfinite(hi - lo) ? hi - lo : 0);
        if (!(lambda >= lo - tol && lambda <= hi + tol)) {
            snprintf(why, n, "%g um lies outside the system's training wavelengths (%g..%g um)",
                     lambda, lo, hi);
            return 0;
        }
    }
    return 1;
}
