/* Ray-surface intersection: closed form for quadrics, safeguarded Newton for aspheres.
 * Conventions in intersect.h and lens.h. */
#include "sparselens/intersect.h"

#include <math.h>

static double curvature(const lens_surface *s)
{
    return isfinite(s->radius) ? 1.0 / s->radius : 0.0;
}

void surface_normal(const lens_surface *s, double x, double y, double nrm[3])
{
    double sl = lens_sag_slope(s, x * x + y * y);
    double a = 2.0 * x * sl, b = 2.0 * y * sl;
    double inv = 1.0 / sqrt(a * a + b * b + 1.0);
    nrm[0] = a * inv;
    nrm[1] = b * inv;
    nrm[2] = -inv;
}

/* Roots of the base quadric along the ray, vertex-relative origin q. Returns the
 * smallest root > ISECT_T_MIN on the vertex branch, or NAN. */
static double quadric_root(double c, double k1, const double q[3], const double d[3])
{
    /* c (x^2 + y^2 + k1 z^2) - 2 z = 0 with x = q + t d:  A t^2 + 2 B t + C = 0 */
    double A = c * (d[0] * d[0] + d[1] * d[1] + k1 * d[2] * d[2]);
    double B = c * (q[0] * d[0] + q[1] * d[1] + k1 * q[2] * d[2]) - d[2];
    double C = c * (q[0] * q[0] + q[1] * q[1] + k1 * q[2] * q[2]) - 2.0 * q[2];
    double disc = B * B - A * C;
    if (!(disc >= 0))
        return NAN;
    /* q = -(B + sign(B) sqrt(disc)) never cancels; the roots are q / A and C / q. */
    double qq = -(B + copysign(sqrt(disc), B));
    double r[2] = {NAN, NAN};
    if (qq != 0)
        r[0] = C / qq;
    if (A != 0)
        r[1] = qq / A;
    double best = NAN;
    for (int i = 0; i < 2; i++) {
        double t = r[i];
        if (!(t > ISECT_T_MIN) || !isfinite(t))
            continue;
        /* Vertex branch: (1 + k) c z <= 1 (the far half of a sphere has c z > 1). */
        double z = q[2] + t * d[2];
        if (k1 * c * z > 1.0 + 1e-12)
            continue;
        if (isnan(best) || t < best)
            best = t;
    }
    return best;
}

/* The sag of lens.h and its slope d(sag)/d(h^2) together, sharing the square root
 * (Newton needs both at every step). NAN where the conic is not defined. */
static double sag_slope(const lens_surface *s, double h2, double *slope)
{
    double c = isfinite(s->radius) ? 1.0 / s->radius : 0.0;
    double disc = 1.0 - (1.0 + s->conic) * c * c * h2;
    if (!(disc > 0)) {
        *slope = NAN;
        return disc == 0 ? lens_sag(s, h2) : NAN;
    }
    double r = sqrt(disc);
    double p = 0, dp = 0; /* sum a_{2j+4} h2^(j+2) and its derivative, by Horner */
    for (int i = LENS_ASPHERE_TERMS - 1; i >= 0; i--) {
        p = p * h2 + s->asphere[i];
        dp = dp * h2 + (i + 2) * s->asphere[i];
    }
    *slope = c / (2.0 * r) + dp * h2;
    return c * h2 / (1.0 + r) + p * h2 * h2;
}

/* g(t) = z(t) - sag(h^2(t)): negative in front of the surface. */
static double asph_g(const lens_surface *s, const double q[3], const double d[3], double t,
                     double *dg)
{
    double x = q[0] + t * d[0], y = q[1] + t * d[1];
    double h2 = x * x + y * y;
    if (!dg)
        return q[2] + t * d[2] - lens_sag(s, h2);
    double sl, z = sag_slope(s, h2, &sl);
    *dg = d[2] - 2.0 * sl * (x * d[0] + y * d[1]);
    return q[2] + t * d[2] - z;
}

/* A root of g in [lo, hi] where g changes sign: Newton steps that stay inside the
 * shrinking bracket, bisection otherwise. */
static double asph_solve(const lens_surface *s, const double q[3], const double d[3], double lo,
                         double hi, double glo, double t0)
{
    double t = (t0 > lo && t0 < hi) ? t0 : 0.5 * (lo + hi);
    for (int it = 0; it < 100; it++) {
        double dg;
        double g = asph_g(s, q, d, t, &dg);
        if (g == 0)
            return t;
        if ((g < 0) == (glo < 0)) {
            lo = t;
            glo = g;
        } else {
            hi = t;
        }
        double tn = t - g / dg;
        if (!(tn > lo && tn < hi) || !isfinite(tn))
            tn = 0.5 * (lo + hi);
        if (fabs(tn - t) <= 1e-13 * (1.0 + fabs(t)) || hi - lo <= 1e-13 * (1.0 + fabs(t)))
            return tn;
        t = tn;
    }
    return t;
}

static isect_status asphere_root(const lens_surface *s, double c, double k1, const double q[3],
                                 const double d[3], double clip_r2, double *tout)
{
    /* Search the part of the ray inside the cylinder of radius hlim: inside the clear
     * aperture when clipping (a hit beyond it is clipped anyway), and where the sag is
     * defined. */
    double sd = s->semi_diameter;
    double hlim2 = isfinite(clip_r2) ? clip_r2 : 2.25 * sd * sd;
    if (k1 * c * c > 0)
        hlim2 = fmin(hlim2, (1.0 - 1e-12) / (k1 * c * c));
    double a = d[0] * d[0] + d[1] * d[1];
    double b = q[0] * d[0] + q[1] * d[1];
    double cc = q[0] * q[0] + q[1] * q[1] - hlim2;
    double lo, hi;
    if (a < 1e-300) {
        /* Parallel to the axis: the hit is where z meets the sag at this height. */
        if (cc > 0)
            return ISECT_OUTSIDE;
        if (d[2] == 0)
            return ISECT_MISS;
        double t = (lens_sag(s, q[0] * q[0] + q[1] * q[1]) - q[2]) / d[2];
        if (!(t > ISECT_T_MIN))
            return ISECT_MISS;
        *tout = t;
        return ISECT_HIT;
    }
    double disc = b * b - a * cc;
    if (disc < 0)
        return ISECT_OUTSIDE;
    double sq = sqrt(disc);
    lo = (-b - sq) / a;
    hi = (-b + sq) / a;
    if (lo < ISECT_T_MIN)
        lo = ISECT_T_MIN;
    if (!(hi > lo))
        return ISECT_OUTSIDE;
    /* Keep the bracket strictly inside the cylinder so the sag stays defined. */
    double pad = 1e-12 * (hi - lo);
    lo += pad;
    hi -= pad;
    double glo = asph_g(s, q, d, lo, NULL), ghi = asph_g(s, q, d, hi, NULL);
    double t0 = quadric_root(c, k1, q, d);
    if (isfinite(glo) && isfinite(ghi) && (glo < 0) != (ghi < 0)) {
        *tout = asph_solve(s, q, d, lo, hi, glo, t0);
        return ISECT_HIT;
    }
    /* No sign change end to end: the ray crosses the surface twice inside the aperture
     * (a grazing ray over a bump) or not at all (the common case: it crosses outside,
     * i.e. it is clipped). Look for the first sign change on a grid coarse enough to
     * keep clipped rays cheap; double crossings closer than 1/16 of the chord are
     * treated as a miss. */
    enum { NSCAN = 16 };
    double tp = lo, gp = glo;
    for (int i = 1; i <= NSCAN; i++) {
        double tn = lo + (hi - lo) * i / NSCAN;
        double gn = asph_g(s, q, d, tn, NULL);
        if (isfinite(gp) && isfinite(gn) && (gp < 0) != (gn < 0)) {
            *tout = asph_solve(s, q, d, tp, tn, gp, t0);
            return ISECT_HIT;
        }
        tp = tn;
        gp = gn;
    }
    return isfinite(clip_r2) ? ISECT_OUTSIDE : ISECT_MISS;
}

isect_status intersect_surface(const lens_surface *s, double vz, const double o[3],
                               const double d[3], double clip_r2, double *t, double p[3],
                               double nrm[3])
{
    double c = curvature(s), k1 = 1.0 + s->conic;
    double q[3] = {o[0], o[1], o[2] - vz};
    int asph = 0;
    for (int i = 0; i < LENS_ASPHERE_TERMS; i++)
        asph |= s->asphere[i] != 0;
    double tt;
    if (!asph) {
        tt = quadric_root(c, k1, q, d);
        if (isnan(tt))
            return ISECT_MISS;
    } else {
        isect_status st = asphere_root(s, c, k1, q, d, clip_r2, &tt);
        if (st != ISECT_HIT)
            return st;
    }
    double x = q[0] + tt * d[0], y = q[1] + tt * d[1], z = q[2] + tt * d[2];
    double h2 = x * x + y * y;
    if (h2 > clip_r2)
        return ISECT_OUTSIDE;
    *t = tt;
    p[0] = x;
    p[1] = y;
    p[2] = z + vz;
    if (!asph) {
        /* Gradient of the implicit quadric; exactly unit for a sphere on its vertex branch. */
        double nx = c * x, ny = c * y, nz = k1 * c * z - 1.0;
        if (s->conic != 0) {
            double inv = 1.0 / sqrt(nx * nx + ny * ny + nz * nz);
            nx *= inv;
            ny *= inv;
            nz *= inv;
        }
        nrm[0] = nx;
        nrm[1] = ny;
        nrm[2] = nz;
    } else {
        surface_normal(s, x, y, nrm);
    }
    return ISECT_HIT;
}
