#ifndef SPARSELENS_TRACE_STOP_H
#define SPARSELENS_TRACE_STOP_H
/* The hit of a sensor ray on the aperture-stop surface (lens-trace --stop-columns).
 * A fitted system decides passage only by pass circles on its outputs; with the stop
 * hit among them it also learns the stop, which the front-element hit alone misses. */
#include <stddef.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"

/* Sensor ray in[4] = (x, y, u, v) (trace.h convention) at the wavelength whose indices
 * are n: ap gets (x, y) of its hit on surface lens->stop, in mm of the lens frame, or
 * (nan, nan) when the ray is clipped, missed or blocked before or at the stop.
 * Returns 1 when the hit is finite, 0 otherwise. */
int trace_stop_hit(const lens_t *lens, const double *n, const double in[4], double ap[2]);

/* Many rays: in is count rows of (x, y, u, v, lambda), ap count rows of (ap_x, ap_y).
 * threads <= 0: OpenMP default. 0, or -1 with err set for a wavelength out of range
 * (its row is nan; the others are traced). */
int trace_stop_batch(const lens_t *lens, size_t count, const double *in, double *ap,
                     int threads, lens_err *err);

#endif
