/* Spectral pipeline of lens-render (render_spectrum.h): spectrum -> CIE XYZ -> linear sRGB.
 *
 * The colour-matching functions are the analytic fit of Wyman, Sloan and Shirley,
 * "Simple Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2(2)
 * 2013, multi-lobe version: sums of piecewise Gaussians with a different width on each
 * side of the peak (their Eq. 2-4, lambda in nm), within about 1% of the tabulated CIE
 * 1931 observer. The XYZ -> linear sRGB matrix is IEC 61966-2-1's.
 *
 * The white balance and the band spectra are computed once, by the midpoint rule on
 * NQUAD points over the range; both are smooth enough there for 1e-6. */
#include "sparselens/render_spectrum.h"

#include <math.h>
#include <pthread.h>

#include "sparselens/render.h"

static double lobe(double x, double mu, double s_lo, double s_hi)
{
    double t = (x - mu) / (x < mu ? s_lo : s_hi);
    return exp(-0.5 * t * t);
}

void cie_xyz_bar(double lambda, double xyz[3])
{
    double nm = 1000 * lambda;
    xyz[0] = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7) -
             0.065 * lobe(nm, 501.1, 20.4, 26.2);
    xyz[1] = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
    xyz[2] = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
}

static const double xyz_to_srgb[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                         {-0.9692660, 1.8760108, 0.0415560},
                                         {0.0556434, -0.2040259, 1.0572252}};

static void raw_rgb_bar(double lambda, double rgb[3])
{
    double xyz[3];
    cie_xyz_bar(lambda, xyz);
    for (int c = 0; c < 3; c++)
        rgb[c] = xyz_to_srgb[c][0] * xyz[0] + xyz_to_srgb[c][1] * xyz[1] + xyz_to_srgb[c][2] * xyz[2];
}

#define NQUAD 3000
static const double band_edge[4] = {RENDER_LAMBDA_MIN, 0.49, 0.58, RENDER_LAMBDA_MAX};

/* white[c]: the integral of the raw response over the range; level[b][c]: the band
 * level of spectrum colour c's band b (the inverse of the bands' responses). */
static struct {
    double white[3];
    double level[3][3];
} tab;
static pthread_once_t tab_once = PTHREAD_ONCE_INIT;

static void tab_init(void)
{
    /* resp[b][c]: the white-balanced response of channel c to band b at level 1 */
    double resp[3][3] = {{0}};
    double h = (RENDER_LAMBDA_MAX - RENDER_LAMBDA_MIN) / NQUAD;
    for (int i = 0; i < NQUAD; i++) {
        double lam = RENDER_LAMBDA_MIN + (i + 0.5) * h, r[3];
        raw_rgb_bar(lam, r);
        int b = lam < band_edge[1] ? 0 : lam < band_edge[2] ? 1 : 2;
        for (int c = 0; c < 3; c++) tab.white[c] += r[c] * h, resp[b][c] += r[c] * h;
    }
    for (int b = 0; b < 3; b++)
        for (int c = 0; c < 3; c++) resp[b][c] /= tab.white[c];
    /* rgb_c = sum_b level_b resp[b][c]: level = rgb M^-1 with M = resp (rows b) */
    double m[3][3], det;
    m[0][0] = resp[1][1] * resp[2][2] - resp[1][2] * resp[2][1];
    m[0][1] = resp[0][2] * resp[2][1] - resp[0][1] * resp[2][2];
    m[0][2] = resp[0][1] * resp[1][2] - resp[0][2] * resp[1][1];
    m[1][0] = resp[1][2] * resp[2][0] - resp[1][0] * resp[2][2];
    m[1][1] = resp[0][0] * resp[2][2] - resp[0][2] * resp[2][0];
    m[1][2] = resp[0][2] * resp[1][0] - resp[0][0] * resp[1][2];
    m[2][0] = resp[1][0] * resp[2][1] - resp[1][1] * resp[2][0];
    m[2][1] = resp[0][1] * resp[2][0] - resp[0][0] * resp[2][1];
    m[2][2] = resp[0][0] * resp[1][1] - resp[0][1] * resp[1][0];
    det = resp[0][0] * m[0][0] + resp[0][1] * m[1][0] + resp[0][2] * m[2][0];
    /* level_b = sum_c rgb_c inv[c][b], inv = M^-1 = m / det: store per (b, c) */
    for (int b = 0; b < 3; b++)
        for (int c = 0; c < 3; c++) tab.level[b][c] = m[c][b] / det;
}

void render_rgb_bar(double lambda, double rgb_bar[3])
{
    pthread_once(&tab_once, tab_init);
    if (!(lambda >= RENDER_LAMBDA_MIN && lambda <= RENDER_LAMBDA_MAX)) {
        rgb_bar[0] = rgb_bar[1] = rgb_bar[2] = 0;
        return;
    }
    raw_rgb_bar(lambda, rgb_bar);
    for (int c = 0; c < 3; c++) rgb_bar[c] /= tab.white[c];
}

double render_rgb_spectrum(const double rgb[3], double lambda)
{
    pthread_once(&tab_once, tab_init);
    int b = lambda < band_edge[1] ? 0 : lambda < band_edge[2] ? 1 : 2;
    return rgb[0] * tab.level[b][0] + rgb[1] * tab.level[b][1] + rgb[2] * tab.level[b][2];
}
