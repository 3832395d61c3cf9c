#ifndef SPARSELENS_WAVEFRONT_H
#define SPARSELENS_WAVEFRONT_H
/* The wavefront of one field at one wavelength over a square grid of the pupil: the
 * optical path difference (OPD) to a reference sphere, two ways.
 *
 *  - WAVEFRONT_PATH (the exact lens): optical path lengths surface by surface, from a
 *    plane normal to the incoming beam (object at infinity) or from the object point,
 *    to the reference sphere: centred on the reference point on the sensor, through
 *    the point where the reference chief ray crosses the paraxial exit pupil plane.
 *  - WAVEFRONT_RAYS (any model, the only way for a fitted system, which knows ray
 *    directions but not path lengths): the OPD whose gradient matches the transverse
 *    ray errors, dW/dL = -n' ex and dW/dM = -n' ey (L, M the ray's direction cosines in
 *    image space, ex, ey its error on the sensor from the reference point: exact for
 *    the path to the foot of the perpendicular from that point on the ray), fitted by
 *    least squares as a polynomial of degree WAVEFRONT_DEGREE in L and M, then moved
 *    to the same reference sphere (+ n' (R - sqrt(R^2 - rho^2)), rho the ray's distance
 *    from the reference point). On a real lens the two agree to 1e-3 waves.
 *
 * Grid: n x n cells over the normalised stop square [-1, 1]^2, rays through the cell
 * centres (a centre just outside the rim is pulled onto it); a cell's amplitude is the
 * share of its area inside the stop's disc (so the rim is smooth), 0 when its ray is
 * vignetted. Transmittance does not apodise the pupil. W is in mm of optical path,
 * piston removed; the reference point is given (the chief ray of the primary
 * wavelength, so lateral colour is a tilt of the other wavelengths' wavefronts).
 *
 * The pupil is taken as linear in direction cosines: L ~ Lc + a px, M ~ Mc + b py
 * (a, b the secants between the outermost passing cells of the central rows and
 * columns, the marginal rays' slope); diffraction needs this scale (frequency = shift
 * in pupil x a n' / lambda, the wavelength inside the image space's medium). */
#include "sparselens/imaging.h"

#define WAVEFRONT_DEGREE 10

typedef enum { WAVEFRONT_PATH, WAVEFRONT_RAYS } wavefront_method;

typedef struct {
    int n;                  /* cells across */
    double lambda;          /* um */
    wavefront_method method;
    double n_image;         /* index of image space */
    double *amp;            /* n * n, row-major, y (tangential) rows, x columns */
    double *opd;            /* n * n, mm; 0 where amp is 0 */
    double *sensor;         /* n * n * 4: sensor rays x y u v at the model's plane; NAN if vignetted */
    double *path;           /* PATH: n * n * 7: last-surface hit, direction, optical path there */
    double chief[4];        /* this wavelength's chief ray on the sensor */
    double ref_chief[4];    /* the reference chief ray (primary wavelength) on the sensor */
    double exit_z;          /* z of the paraxial exit pupil (reference sphere) */
    double sensor_z;        /* z of the model's sensor plane */
    double scale[2];        /* a (x, sagittal) and b (y, tangential): direction cosine per
                               unit of normalised pupil */
    double seconds;         /* imaging through the model (and, for PATH, the path lengths) */
    int passed;             /* cells with amplitude */
} wavefront;

/* Traces the grid of field f at lambda through model im; ref_chief is the reference
 * chief ray (sensor ray on im's plane), normally the primary wavelength's. PATH needs
 * the exact lens (im->sys NULL). -1 with err set. */
int wavefront_trace(const imaging *im, double field, double lambda, int n, wavefront_method method,
                    const double ref_chief[4], wavefront *wf, lens_err *err);
void wavefront_free(wavefront *wf);

/* Recomputes wf->opd for the sensor plane moved by dz mm along +z from where it was
 * traced (the reference point moves with the chief ray). -1 when the fit fails. */
int wavefront_refocus(wavefront *wf, double dz);

/* RMS of the OPD over the pupil (amplitude-weighted), mm. */
double wavefront_rms(const wavefront *wf);

#endif
