#ifndef SPARSELENS_RAY_BUNDLE_H
#define SPARSELENS_RAY_BUNDLE_H
/* A bundle: the object-space rays of one field at one wavelength through given points
 * of the stop, aimed once with the exact lens, then imaged through a model (the exact
 * lens, or a fitted system standing in for its tracing). Every designer analysis
 * (ray fans, field curves, MTF, layout) is a bundle of rays read on the sensor, so the
 * same rays go through both models and only the imaging step is timed: what a system
 * costs against the exact tracer for the same work.
 *
 * Conventions: imaging.h (field on +y, stop points in mm, sensor rays x y u v). Stop
 * points here are normalised: (px, py) in the unit disc times the stop's semi-diameter. */
#include <stddef.h>

#include "sparselens/imaging.h"

typedef struct {
    double field, lambda;
    size_t count;
    double *pupil;  /* 2 per ray: normalised stop point px py */
    lens_ray *ray;  /* object-space rays */
    int *aimed;     /* 1 when aiming found the ray */
    double *n;      /* indices of the lens at lambda (nsurf) */
} ray_bundle;

/* Aims count rays of field f at lambda through the normalised stop points pupil[2 i].
 * Points on or past the rim are pulled a hair inside (the rim is grazing for aiming).
 * -1 with err set on a wavelength outside a glass's range or out of memory. */
int bundle_aim(const imaging *im, double field, double lambda, const double *pupil, size_t count,
               ray_bundle *b, lens_err *err);
void bundle_free(ray_bundle *b);

/* Images the bundle through model im: s gets 4 doubles per ray (sensor x y u v on the
 * model's shifted sensor plane), ok[i] 1 when the ray reaches the sensor. A system is
 * solved by Newton on its Jacobian seeded with `seed` (a sensor ray near the bundle's,
 * its chief ray, on the shifted plane; NULL: the axis), never with the exact trace, so
 * the time is the system's own; a ray whose solve fails from the seed is tried again from
 * its nearest solved neighbours in the stop, and counts as vignetted only when those
 * fail too (or the system's passage test says so). Returns
 * the seconds spent imaging (wall clock). */
double bundle_image(const imaging *im, const ray_bundle *b, const double *seed, double *s, int *ok);

/* The sensor ray of the chief ray (stop centre) through model im; 1 with err set when no
 * chief ray reaches the sensor (the model cannot image the field), -1 with err set on
 * other errors. */
int bundle_chief(const imaging *im, double field, double lambda, double s[4], lens_err *err);

/* Seconds on a monotonic clock (for timing models against each other). */
double bundle_clock(void);

#endif
