/* Vector Snell refraction and Fresnel transmittance for the exact tracer. */
#include "sparselens/refract.h"

#include <math.h>
#include <stddef.h>

void fresnel_unpolarised(double n1, double n2, double cos_i, double cos_t, double *R, double *T)
{
    double a = n1 * cos_i, b = n2 * cos_t; /* s polarisation */
    double c = n2 * cos_i, e = n1 * cos_t; /* p polarisation */
    if (R) {
        double rs = (a - b) / (a + b), rp = (e - c) / (e + c);
        *R = 0.5 * (rs * rs + rp * rp);
    }
    if (T) {
        /* Power transmittance = (n2 cos_t) / (n1 cos_i) * |t|^2. */
        double ts = 2.0 * a / (a + b), tp = 2.0 * a / (c + e);
        double f = b / a;
        *T = cos_i > 0 ? 0.5 * f * (ts * ts + tp * tp) : 0.0;
    }
}

int refract(const double d[3], const double nrm[3], double n1, double n2, double out[3],
            double *T)
{
    double cosi = -(d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2]);
    double nx = nrm[0], ny = nrm[1], nz = nrm[2];
    if (cosi < 0) { /* orient the normal against the incoming ray */
        cosi = -cosi;
        nx = -nx;
        ny = -ny;
        nz = -nz;
    }
    double eta = n1 / n2;
    double k = 1.0 - eta * eta * (1.0 - cosi * cosi);
    if (k < 0)
        return -1;
    double cost = sqrt(k);
    double m = eta * cosi - cost;
    double o0 = eta * d[0] + m * nx, o1 = eta * d[1] + m * ny, o2 = eta * d[2] + m * nz;
    /* Unit in exact arithmetic; renormalise so errors do not accumulate over surfaces. */
    double inv = 1.0 / sqrt(o0 * o0 + o1 * o1 + o2 * o2);
    out[0] = o0 * inv;
    out[1] = o1 * inv;
    out[2] = o2 * inv;
    fresnel_unpolarised(n1, n2, cosi, cost, NULL, T);
    return 0;
}
