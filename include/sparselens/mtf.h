#ifndef SPARSELENS_MTF_H
#define SPARSELENS_MTF_H
/* Modulation transfer functions of one field, tangential (frequencies along y, the
 * field's direction) and sagittal (along x).
 *
 *  - Diffraction: the pupil function A exp(2 pi i W / lambda) on the wavefront grid,
 *    zero-padded to twice its size, the PSF as |FFT|^2, and the OTF as the inverse FFT
 *    of the PSF (the pupil's autocorrelation, exact on the grid). A shift of k cells is
 *    the frequency k (2 / n) a / lambda (wavefront.h: a, b the pupil scales); values
 *    between cells are interpolated linearly. Several wavelengths add as incoherent
 *    PSFs: their OTFs (complex, each wavefront referred to the same point) summed with
 *    equal weights.
 *  - Geometric: the Fourier transform of the spot (the grid's rays where they land on
 *    the sensor, weighted by the cells' amplitudes), |sum w exp(-2 pi i nu y)| / sum w.
 *
 * Frequencies in cycles per mm. The diffraction limit of a circular pupil (closed form)
 * is 2/pi (acos v - v sqrt(1 - v^2)), v = nu / nu_c, nu_c = 2 NA / lambda. */
#include "sparselens/wavefront.h"

/* The complex OTF of a wavefront: otf[2 (j m + i)] for shifts (i, j) of an m x m grid
 * (m = fft_size(2 n)), normalised to 1 at 0. Caller frees. NULL when out of memory. */
double *mtf_otf(const wavefront *wf, int *m);

/* The OTF at frequency nu (cycles/mm) along x (dir 0: sagittal) or y (dir 1:
 * tangential), complex (re, im); 0 past the grid. */
void mtf_otf_at(const wavefront *wf, const double *otf, int m, int dir, double nu, double z[2]);

/* Geometric MTF of the wavefront's rays on the sensor plane moved dz along +z, about
 * the reference point; several wavefronts (wavelengths) pooled with equal weight. */
double mtf_geometric(const wavefront *const *wf, int nwf, int dir, double nu, double dz);

/* Strehl ratio: |sum A exp(i k W)|^2 / (sum A)^2 (the PSF's peak against a perfect
 * wavefront's over the same pupil). */
double mtf_strehl(const wavefront *wf);

/* The diffraction limit of a circular pupil at v = nu / nu_c (0 for v >= 1). */
double mtf_diffraction_limit(double v);

/* One value row: tangential and sagittal, diffraction and geometric. */
typedef struct {
    int model, field, lambda;    /* lambda == the number of wavelengths: all wavelengths */
    double x;                    /* frequency (cycles/mm) or focus shift (mm) */
    double diff[2], geo[2];      /* [0] tangential, [1] sagittal */
} mtf_row;

/* Picture of the rows: a panel per field, tangential lines thick, sagittal thin,
 * diffraction in colour, geometric in grey, the diffraction limit nu_c (cycles/mm, 0:
 * none) dotted; only the all-wavelength rows when there are several wavelengths;
 * a second model as dots. */
typedef struct {
    int nmodels;
    const char *const *model_names;
    int nfields, nl;
    const double *field, *lambda;
    const mtf_row *rows;
    size_t nrows;
    double through_focus;  /* > 0: rows are against focus at this frequency */
    double nu_c;
    const char *title;
    int finite;
} mtf_figure;
int mtf_write_png(const mtf_figure *fig, const char *path, lens_err *err);

#endif
