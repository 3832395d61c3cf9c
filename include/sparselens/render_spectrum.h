#ifndef SPARSELENS_RENDER_SPECTRUM_H
#define SPARSELENS_RENDER_SPECTRUM_H
/* Spectra for lens-render's spectral mode (render_spectrum.c): the CIE 1931 colour-matching
 * functions, the pixel's linear sRGB response to a wavelength, and the spectrum that a
 * scene's r g b colour stands for.
 *
 * Convention: wavelengths in um over [RENDER_LAMBDA_MIN, RENDER_LAMBDA_MAX] (render.h);
 * outside it the response is 0. The response is white-balanced to an equal-energy
 * spectrum: a flat spectrum of 1 over the range gives r = g = b = 1, and the spectrum of
 * a colour (r, g, b) gives back (r, g, b). */

/* The CIE 1931 2-degree observer xbar, ybar, zbar at lambda (um), by the multi-lobe
 * piecewise-Gaussian fit of Wyman, Sloan and Shirley (JCGT 2(2), 2013). */
void cie_xyz_bar(double lambda, double xyz[3]);

/* The linear sRGB (D65 primaries) response per um at lambda, white-balanced as above:
 * a pixel's channel c is the integral of L(lambda) rgb_bar_c(lambda) dlambda. */
void render_rgb_bar(double lambda, double rgb_bar[3]);

/* The spectrum of colour rgb at lambda: piecewise constant over the blue, green and red
 * bands of render.h, with band levels chosen so that render_rgb_bar integrates it back to
 * rgb exactly (a grey stays flat). */
double render_rgb_spectrum(const double rgb[3], double lambda);

#endif
