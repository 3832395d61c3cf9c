#ifndef SPARSELENS_TRACE_H
#define SPARSELENS_TRACE_H
/* Exact sequential ray tracing through a lens_t (frame: see lens.h; z towards sensor),
 * in the ray parametrisations of ray_frames.h (sensor, outer pupil, stop). eta, a
 * ray's transmittance: the product over all surfaces of the unpolarised Fresnel
 * transmittance. */
#include <stddef.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/ray_frames.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    TRACE_PASSED = 0,
    TRACE_MISSED,  /* no intersection with a surface */
    TRACE_CLIPPED, /* hit outside a surface's semi-diameter */
    TRACE_STOPPED, /* blocked by the aperture stop */
    TRACE_TIR,     /* total internal reflection */
    TRACE_INVALID  /* non-finite input */
} trace_status;

typedef struct {
    trace_status status;
    int surface;          /* surface where the ray ended (-1 if it passed) */
    double transmittance; /* Fresnel product so far (0 when not passed) */
} trace_result;

typedef enum { TRACE_TO_OUTER, TRACE_TO_STOP } trace_target;

const char *trace_status_name(trace_status s); /* "passed", "missed", "clipped", ... */

/* Traces from the sensor side towards the object through surfaces nsurf-1 .. last
 * (last = 0 for the whole lens; last = lens->stop to end on the stop). r is updated to
 * the hit on surface `last` with the direction after refraction there (when last == 0)
 * or before refraction (when last > 0, the ray is left at the stop hit). */
trace_result trace_to_object(const lens_t *lens, const double *n, lens_ray *r, int last);

/* Traces an object-space ray (travelling towards +z) through the whole lens to the
 * sensor plane; r ends on the sensor plane. */
trace_result trace_to_sensor(const lens_t *lens, const double *n, lens_ray *r);

/* One sample: sensor (x, y, u, v) at the wavelength whose indices are n, to the target
 * frame. out gets out_x out_y out_u out_v (nan when not passed). */
trace_result trace_sample(const lens_t *lens, const double *n, trace_target target,
                          const double in[4], double out[4]);

/* Many samples: in is count rows of (x, y, u, v, lambda), out count rows of
 * (out_x, out_y, out_u, out_v, out_eta); res may be NULL. Indices are computed once per
 * distinct wavelength. threads <= 0: OpenMP default. 0, or -1 with err set for a
 * wavelength out of range (its row is nan; the others are traced). */
int trace_batch(const lens_t *lens, trace_target target, size_t count, const double *in,
                double *out, trace_result *res, int threads, lens_err *err);

#ifdef __cplusplus
}
#endif

#endif
