#ifndef SPARSELENS_PUPIL_SAMPLER_H
#define SPARSELENS_PUPIL_SAMPLER_H
/* Pupil-aware sampling of sensor-side ray directions.
 *
 * For a point (x, y) on the sensor only a small set of directions (u, v) (sensor
 * parametrisation of trace.h) passes the lens: the exit pupil seen from that point,
 * cut by the vignetting of the other apertures. By rotational symmetry that set at
 * (x, y) is the set at (r, 0), r = |(x, y)|, rotated by the point's azimuth. The sampler
 * precomputes it for `radii` radii from 0 to sensor_radius, as an occupancy grid in
 * (u, v) probed by exact traces at five wavelengths spread over the range and
 * dilated by one cell. Between two tabulated radii it samples the equal mixture of the
 * two neighbours' sets, uniform inside each, so its support is their union: every
 * passing direction is covered even though the set moves with r.
 *
 * Use: build once per lens, wavelength range and sensor radius; then, from any thread,
 * sample(x, y, two uniform numbers) -> (u, v, pdf). The pdf is with respect to du dv
 * and is also available for any (u, v) through pupil_sampler_pdf (0 outside). */
#include <stdio.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"

typedef struct {
    double lambda_min, lambda_max; /* um */
    double sensor_radius;          /* mm: the largest |(x, y)| that will be sampled */
    int radii;                     /* tabulated radii (0: 64) */
    int grid;                      /* cells per side of each (u, v) grid (0: 96) */
    int threads;                   /* for building; <= 0: OpenMP default */
} pupil_sampler_options;

typedef struct pupil_sampler pupil_sampler;

pupil_sampler *pupil_sampler_build(const lens_t *lens, const pupil_sampler_options *opt,
                                   lens_err *err);
void pupil_sampler_free(pupil_sampler *ps);

/* The same sampler for a lens known only as a function (an analytic lens in a test, a
 * lens map): fn marks pass[k] = 1 for each sensor ray (r, 0, u[k], v[k]), k < m, that
 * passes at some wavelength the caller cares about (pass[] starts zeroed, and fn must be
 * safe to call from several threads). Every passing ray must cross the plane rear_dist
 * in front of the sensor within rear_radius of the axis (widen it for a curved rear
 * element). opt's wavelengths are checked but only fn uses wavelengths. */
typedef void (*pupil_probe_fn)(void *ctx, double r, int m, const double *u, const double *v,
                               unsigned char *pass);
pupil_sampler *pupil_sampler_build_probe(pupil_probe_fn fn, void *ctx, double rear_dist,
                                         double rear_radius, const pupil_sampler_options *opt,
                                         lens_err *err);

/* A built sampler to a file and back (a cache: binary, this machine's byte order), so
 * that a renderer need not probe the same lens again. 0 / NULL with err on failure. */
int pupil_sampler_write(FILE *f, const pupil_sampler *ps);
pupil_sampler *pupil_sampler_read(FILE *f, lens_err *err);

/* Maps two uniform numbers in [0, 1) to a direction at sensor point (x, y). Returns 0,
 * or -1 when no direction passes from there (or |(x, y)| > sensor_radius): then
 * *pdf = 0 and u, v are nan. */
int pupil_sampler_sample(const pupil_sampler *ps, double x, double y, const double rnd[2],
                         double *u, double *v, double *pdf);

/* The same distribution (and density) by another map from the two numbers: rnd[1]
 * picks the row of cells and the height across it, rnd[0] the place along the row's
 * occupied cells, so that (u, v) moves smoothly with (rnd[0], rnd[1]) over a set whose
 * rows are intervals, and points stratified in the unit square stay stratified over
 * the pupil (pupil_sampler_sample walks the cells in raster order with rnd[0]: only
 * its 1D strata survive). The renderer's camera rays use it. */
int pupil_sampler_sample_rows(const pupil_sampler *ps, double x, double y, const double rnd[2],
                              double *u, double *v, double *pdf);

/* Density (per du dv) with which pupil_sampler_sample produces (u, v) at (x, y). */
double pupil_sampler_pdf(const pupil_sampler *ps, double x, double y, double u, double v);

#endif
