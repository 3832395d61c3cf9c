/* Diffraction and geometric MTF (mtf.h). */
#include "sparselens/mtf.h"

#include <math.h>
#include <stdlib.h>

#include "sparselens/fft.h"

double mtf_diffraction_limit(double v)
{
    v = fabs(v);
    return v >= 1 ? 0 : 2 / M_PI * (acos(v) - v * sqrt(1 - v * v));
}

double *mtf_otf(const wavefront *wf, int *m_out)
{
    int n = wf->n;
    size_t m = fft_size((size_t)(2 * n));
    double *z = calloc(2 * m * m, sizeof *z);
    if (!z)
        return NULL;
    double k = 2 * M_PI / (wf->lambda * 1e-3); /* OPD in mm, lambda in um */
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            size_t c = (size_t)j * n + i, at = 2 * ((size_t)j * m + i);
            double a = wf->amp[c], ph = k * wf->opd[c];
            if (a > 0)
                z[at] = a * cos(ph), z[at + 1] = a * sin(ph);
        }
    fft_2d(z, m, -1);
    for (size_t p = 0; p < m * m; p++) { /* the PSF */
        z[2 * p] = z[2 * p] * z[2 * p] + z[2 * p + 1] * z[2 * p + 1];
        z[2 * p + 1] = 0;
    }
    fft_2d(z, m, +1);
    /* Normalised by the pupil's area (the cells' coverages) rather than by the value at
     * zero shift (the sum of squared coverages): the coverage-weighted rim is the hard
     * rim blurred by a cell, whose autocorrelation agrees with the hard rim's beyond a
     * cell's shift but loses its cusp at zero; dividing by that smoothed peak would
     * lift the whole curve by about 0.4 / n. The zero shift itself is 1 by definition. */
    double area = 0;
    for (size_t c = 0; c < (size_t)n * n; c++)
        area += wf->amp[c] > 0 ? wf->amp[c] : 0;
    double norm = (double)m * (double)m * area;
    for (size_t p = 0; p < 2 * m * m; p++)
        z[p] = norm > 0 ? z[p] / norm : 0;
    z[0] = 1, z[1] = 0;
    *m_out = (int)m;
    return z;
}

void mtf_otf_at(const wavefront *wf, const double *otf, int m, int dir, double nu, double z[2])
{
    /* shift in cells for this frequency: a shift dL in direction cosine is the
     * frequency dL / (lambda / n'), the wavelength inside the image space's medium */
    double s = fabs(nu) * wf->lambda * 1e-3 * wf->n / (2 * fabs(wf->scale[dir]) * wf->n_image);
    z[0] = z[1] = 0;
    /* tested before the cast: a shift of nan (no pupil scale) must not reach (int) */
    if (!(s < m / 2 - 1))
        return;
    int k = (int)floor(s);
    double f = s - k;
    /* modulus and phase interpolated apart: a wavefront tilted by lateral colour turns
     * the OTF's phase quickly, and a chord between complex values would cut the modulus;
     * but where the phase jumps by more than a quarter turn between two cells the OTF
     * passes near a zero, which the chord follows and the moduli overshoot */
    size_t a = dir == 0 ? (size_t)k : (size_t)k * (size_t)m, b = dir == 0 ? a + 1 : a + (size_t)m;
    double ma = hypot(otf[2 * a], otf[2 * a + 1]), mb = hypot(otf[2 * b], otf[2 * b + 1]);
    double pa = atan2(otf[2 * a + 1], otf[2 * a]), pb = atan2(otf[2 * b + 1], otf[2 * b]);
    pb = pa + remainder(pb - pa, 2 * M_PI);
    if (fabs(pb - pa) > M_PI / 2) {
        z[0] = (1 - f) * otf[2 * a] + f * otf[2 * b], z[1] = (1 - f) * otf[2 * a + 1] + f * otf[2 * b + 1];
        return;
    }
    double mod = (1 - f) * ma + f * mb, ph = (1 - f) * pa + f * pb;
    z[0] = mod * cos(ph), z[1] = mod * sin(ph);
}

double mtf_strehl(const wavefront *wf)
{
    double k = 2 * M_PI / (wf->lambda * 1e-3), re = 0, im = 0, sa = 0;
    for (size_t c = 0; c < (size_t)wf->n * wf->n; c++)
        if (wf->amp[c] > 0)
            re += wf->amp[c] * cos(k * wf->opd[c]), im += wf->amp[c] * sin(k * wf->opd[c]), sa += wf->amp[c];
    return sa > 0 ? (re * re + im * im) / (sa * sa) : 0;
}

double mtf_geometric(const wavefront *const *wf, int nwf, int dir, double nu, double dz)
{
    double re = 0, im = 0, sw = 0;
    for (int q = 0; q < nwf; q++) {
        const wavefront *w = wf[q];
        double ref = w->ref_chief[dir] - dz * w->ref_chief[2 + dir], tw = 0, tr = 0, ti = 0;
        for (size_t k = 0; k < (size_t)w->n * w->n; k++) {
            if (w->amp[k] <= 0)
                continue;
            const double *s = w->sensor + 4 * k;
            double ph = -2 * M_PI * nu * (s[dir] - dz * s[2 + dir] - ref);
            tw += w->amp[k], tr += w->amp[k] * cos(ph), ti += w->amp[k] * sin(ph);
        }
        /* each wavelength weighs the same whatever share of its rays passes */
        if (tw > 0)
            re += tr / tw, im += ti / tw, sw += 1;
    }
    return sw > 0 ? hypot(re, im) / sw : 0;
}
