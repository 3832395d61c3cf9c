#ifndef SPARSELENS_RAY_FAN_H
#define SPARSELENS_RAY_FAN_H
/* Ray fans: the transverse ray error on the sensor against the normalised pupil
 * coordinate, for a fan of rays in the meridional plane (tangential: stop points
 * (0, p)) and one across it (sagittal: (p, 0)), p from -1 to 1.
 *
 * Errors are measured from a reference point on the sensor, normally the chief ray of
 * the primary wavelength (so lateral colour shows as an offset of the other
 * wavelengths' fans). The tangential fan's error is along y (ey), the sagittal fan's
 * along x (ex); the sagittal fan's ey (sagittal coma) is kept too. */
#include "sparselens/imaging.h"

enum { FAN_TANGENTIAL = 0, FAN_SAGITTAL = 1 };

typedef struct {
    int npts;
    double *pupil;      /* npts normalised pupil coordinates, -1 .. 1 */
    double *ex, *ey;    /* [fan * npts + i], mm from the reference; NAN when vignetted */
    double seconds;     /* spent imaging the rays through the model */
} ray_fan;

/* Traces both fans of field f at lambda through model im, errors from ref (sensor x y);
 * seed is a sensor ray near the fans' (the chief ray) for a system's Newton solves.
 * -1 with err set on failure. */
int ray_fan_trace(const imaging *im, double field, double lambda, const double ref[2],
                  const double seed[4], int npts, ray_fan *fan, lens_err *err);
void ray_fan_free(ray_fan *fan);

/* The fans of a field the model cannot image: npts pupil points, every error nan. */
int ray_fan_not_imaged(int npts, ray_fan *fan, lens_err *err);

/* Picture: a row of two panels (tangential ey, sagittal ex, in um) per field, one scale
 * for all; wavelengths in their colours, the first model as lines and a second one as
 * dots over them. fans[(m * nfields + f) * nl + l]. */
typedef struct {
    int nmodels, nfields, nl;
    const char *const *model_names;
    const ray_fan *fans;
    const double *field, *lambda;
    const char *title;
    int finite;                 /* fields are object heights in mm */
} ray_fan_figure;
int ray_fan_write_png(const ray_fan_figure *fig, const char *path, lens_err *err);

#endif
