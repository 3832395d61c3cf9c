#ifndef RENDER_RENDER_MATH_H
#define RENDER_RENDER_MATH_H
/* Small inline helpers of the renderer's per-sample code (scene_geometry.c,
 * scene_light.c, render_image.c). Why they exist: at -O2 without -ffast-math the
 * compiler calls libm for fmax and fmin (their NaN and signed-zero rules), and glibc's
 * sin and cos reduce any argument, about 130 instructions a pair; every camera sample
 * pays for several of each. */
#include <math.h>

static inline double rm_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* max(x, 0), and 0 for NaN (as fmax(0, x)) */
static inline double rm_pos(double x)
{
    return x > 0 ? x : 0;
}

/* sin and cos of 2 pi t, for |t| < 2^50 (here a uniform in [0, 1]): t is reduced
 * exactly to a quarter turn (4 t less its nearest integer), then Taylor series to x^15
 * and x^16 on |x| <= pi/4 (truncation below 5e-17), turned by the quadrant. Within a few
 * units in the last place of libm's. */
static inline void rm_sincos_turn(double t, double *s, double *c)
{
#ifdef RM_LIBM_SINCOS /* libm's, to tell this change from others in a comparison */
    *s = sin(2 * M_PI * t), *c = cos(2 * M_PI * t);
    return;
/* An orthonormal frame t, b around unit n (Duff et al. 2017, "Building an orthonormal
 * basis, revisited"). */
static inline void rm_frame(const double n[3], double t[3], double b[3])
{
    double s = n[2] >= 0 ? 1 : -1, a = -1 / (s + n[2]), c = n[0] * n[1] * a;
    t[0] = 1 + s * n[0] * n[0] * a, t[1] = s * c, t[2] = -s * n[0];
    b[0] = c, b[1] = s + n[1] * n[1] * a, b[2] = -n[1];
}

#endif
    double q = 4 * t, n = floor(q + 0.5), x = (q - n) * 1.5707963267948966, x2 = x * x;
    double sn = x + x * x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 +
                x2 * (-1.0 / 39916800 + x2 * (1.0 / 6227020800 + x2 * (-1.0 / 1307674368000)))))));
    double cs = 1 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 +
                x2 * (-1.0 / 3628800 + x2 * (1.0 / 479001600 + x2 * (-1.0 / 87178291200 +
                x2 * (1.0 / 20922789888000))))))));
    switch ((long)n & 3) {
    case 0: *s = sn, *c = cs; break;
    case 1: *s = cs, *c = -sn; break;
    case 2: *s = -sn, *c = -cs; break;
    default: *s = -cs, *c = sn; break;
    }
}

/* An orthonormal frame t, b around unit n (Duff et al. 2017, "Building an orthonormal
 * basis, revisited"). */
static inline void rm_frame(const double n[3], double t[3], double b[3])
{
    double s = n[2] >= 0 ? 1 : -1, a = -1 / (s + n[2]), c = n[0] * n[1] * a;
    t[0] = 1 + s * n[0] * n[0] * a, t[1] = s * c, t[2] = -s * n[0];
    b[0] = c, b[1] = s + n[1] * n[1] * a, b[2] = -n[1];
}

#endif
