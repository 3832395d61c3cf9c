#ifndef SPARSELENS_SAMPLING_H
#define SPARSELENS_SAMPLING_H
/* Generation of sample rays (lens-trace): sensor points uniform over a sensor rectangle
 * centred on the axis, wavelengths uniform over a range, and sensor-side directions
 * (u, v) (trace.h) by one of two strategies:
 *  - rear:  towards a uniform point of the rear element's clear disc (the disc of its
 *           semi-diameter in its vertex plane): the usual way, kept as the baseline;
 *  - pupil: from the pupil sampler (pupil_sampler.h), which knows which directions
 *           pass from each sensor radius; one ray in 16 (every sixteenth index) from a
 *           sensor point uniform within a tenth of the half diagonal from the axis,
 *           where a meridional fit's data end (sampling.c);
 *  - full:  uniform in (u, v) over a disc in the rear vertex plane that holds every
 *           direction that can pass (full_disc_radius): the whole ray space a system
 *           serves, for finding what limits the beam and for measuring passage as a
 *           share of the light (uniform in u, v: each ray weighs cos^4 theta T).
 * Ray i is made from the random stream (seed, i) alone (rng.h), so any range of rays
 * can be generated on its own, by any number of threads, with the same result. */
#include <stddef.h>
#include <stdint.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/pupil_sampler.h"

typedef enum { SAMPLING_PUPIL = 0, SAMPLING_REAR, SAMPLING_FULL } sampling_strategy;

typedef struct {
    sampling_strategy strategy;
    double sensor_w, sensor_h;     /* mm; NAN: the lens's sensor_w, sensor_h */
    double lambda_min, lambda_max; /* um; equal for one wavelength */
    uint64_t seed;
    int pupil_radii, pupil_grid;   /* pupil sampler resolution (0: its defaults) */
    int threads;                   /* <= 0: OpenMP default */
} sampling_options;

sampling_options sampling_defaults(void); /* pupil, lens sensor, 0.4..0.7 um, seed 1 */

/* "pupil" / "rear" / "full" <-> strategy; parse returns -1 for an unknown name. */
int sampling_strategy_parse(const char *name, sampling_strategy *s);
const char *sampling_strategy_name(sampling_strategy s);

/* The rear strategy at one sensor point: rnd in [0,1)^2 -> (u, v) and its pdf per du dv. */
void rear_sample(const lens_t *lens, double x, double y, const double rnd[2], double *u,
                 double *v, double *pdf);
double rear_pdf(const lens_t *lens, double x, double y, double u, double v);

/* The full strategy: the radius of the disc in the rear vertex plane that every passing
 * ray from a sensor point within sensor_radius of the axis crosses, and a uniform draw
 * of (u, v) through it (pdf per du dv). */
double full_disc_radius(const lens_t *lens, double sensor_radius);
void full_sample(const lens_t *lens, double disc, double x, double y, const double rnd[2],
                 double *u, double *v, double *pdf);

typedef struct ray_generator ray_generator;

/* Checks the options (sensor size known, wavelengths inside every glass's range) and
 * builds the pupil sampler when needed. NULL with err set on failure. */
ray_generator *ray_generator_new(const lens_t *lens, const sampling_options *opt,
                                 lens_err *err);
/* Rays first .. first+count-1 as rows (x, y, u, v, lambda). A sensor point from which no
 * direction passes is drawn again from the same stream (up to 64 times; then the ray is
 * aimed at the rear element), so pupil-sampled points are uniform over the part of the
 * sensor the lens can reach (but for the axis's share above). */
int ray_generator_fill(const ray_generator *g, size_t first, size_t count, double *rows,
                       lens_err *err);
/* The pupil sampler in use (NULL for the rear strategy). */
const pupil_sampler *ray_generator_sampler(const ray_generator *g);
void ray_generator_free(ray_generator *g);

#endif
