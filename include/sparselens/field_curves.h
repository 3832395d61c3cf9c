#ifndef SPARSELENS_FIELD_CURVES_H
#define SPARSELENS_FIELD_CURVES_H
/* Field curves from real rays: where the tangential and the sagittal foci of a field
 * lie, by finite differences of rays close to its chief ray.
 *
 * Two rays through the stop at (0, +-d) (tangential) and two at (+-d, 0) (sagittal),
 * d a small fraction of the stop radius, are imaged and read on the sensor as lines
 * (x, y, u, v: trace.h). The tangential focus is where the two meridional rays cross;
 * the sagittal focus is where a sagittal ray crosses the meridional plane (both of the
 * symmetric pair cross it at the same point). Symmetric pairs cancel the first-order
 * error in d, so the result is the Coddington focus up to O(d^2).
 *
 * Focus positions are longitudinal: mm along +z (towards the sensor) from the model's
 * sensor plane. In third order, with T = tangential and S = sagittal, the Petzval
 * focus is (3 S - T) / 2 and the astigmatic difference is T - S. */
#include "sparselens/imaging.h"

typedef struct {
    double field, lambda;
    double chief[4];      /* the chief ray on the sensor (x y u v) */
    double z_tan, z_sag;  /* foci, mm along +z from the sensor plane; NAN when a ray fails */
    double seconds;       /* spent imaging through the model */
} field_focus;

/* delta: the half separation of each pair as a fraction of the stop radius (0.01 is a
 * good default). seed: the chief ray when known (NULL: traced first). */
int field_focus_trace(const imaging *im, double field, double lambda, double delta,
                      field_focus *ff, lens_err *err);

/* One row of the field table. */
typedef struct {
    field_focus focus;
    double distortion_pct; /* chief-ray height against the paraxial one at the primary
                              wavelength: f tan(theta), or magnification x height */
    double lateral_um;     /* chief-ray height minus the primary wavelength's, um */
} field_row;

/* Pictures. Field curves: three panels against field (vertical): the tangential (lines)
 * and sagittal (thin lines) foci in mm, distortion in %, lateral colour in um;
 * wavelengths in their colours, a second model as dots. rows[(m * nfields + f) * nl + l]. */
typedef struct {
    int nmodels, nfields, nl;
    const char *const *model_names;
    const field_row *rows;
    const double *field, *lambda;
    int primary;
    const char *title;
    int finite;
} field_figure;
int field_write_png(const field_figure *fig, const char *path, lens_err *err);

/* Focal shift (um) against wavelength, shift[m * n + i]. */
typedef struct {
    int nmodels;
    const char *const *model_names;
    int n;
    const double *lambda, *shift; /* shift in mm */
    const char *title;
} field_shift_figure;
int field_shift_write_png(const field_shift_figure *fig, const char *path, lens_err *err);

#endif
