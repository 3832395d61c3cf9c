#ifndef SPARSELENS_TRACE_H
#define SPARSELENS_TRACE_H
/* Exact sequential ray tracing through a lens_t (frame: see lens.h; z towards sensor).
 *
 * Ray parametrisations (design.md):
 *  - sensor:  position (x, y) on the sensor plane z = lens_total_track(); direction
 *             towards the lens proportional to (u, v, -1) in the lens frame, i.e.
 *             u = dx/d(-z), v = dy/d(-z). A ray arriving at the sensor with direction d
 *             is described by the reversed direction, so a round trip is the identity.
 *  - outer:   the hit (x, y) on the first surface; direction components (u, v) of the
 *             outgoing unit direction d along the tangent frame at the hit:
 *               n  = unit surface normal pointing to object space ((0,0,-1) at the vertex)
 *               ex = normalize(-n.z, 0, n.x),  ey = ex x n
 *             so out_u = d.ex, out_v = d.ey and d.n = sqrt(1 - u^2 - v^2) > 0. This
 *             stays valid for rays past 90 degrees from the axis; it is singular only
 *             where n = (0, +-1, 0) (the rim of a full hemisphere).
 *  - stop:    the hit (x, y) on the stop surface; direction as on the sensor side
 *             (tangents towards the object: d proportional to (u, v, -1)).
 *  - eta:     product over all surfaces of the unpolarised Fresnel transmittance. */
#include <stddef.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"

typedef struct {
    double o[3]; /* origin, mm, lens frame */
    double d[3]; /* unit direction */
} lens_ray;

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

/* Refractive index after each surface (n[i], i < nsurf) at lambda; object space is air.
 * 0 on success, -1 (err set) for a wavelength outside some glass's range. */
int lens_indices(const lens_t *lens, double lambda_um, double *n, lens_err *err);

/* Traces from the sensor side towards the object through surfaces nsurf-1 .. last
 * (last = 0 for the whole lens; last = lens->stop to end on the stop). r is updated to
 * the hit on surface `last` with the direction after refraction there (when last == 0)
 * or before refraction (when last > 0, the ray is left at the stop hit). */
trace_result trace_to_object(const lens_t *lens, const double *n, lens_ray *r, int last);

/* Traces an object-space ray (travelling towards +z) through the whole lens to the
 * sensor plane; r ends on the sensor plane. */
trace_result trace_to_sensor(const lens_t *lens, const double *n, lens_ray *r);

/* Conversions between parametrisations and lens-frame rays. */
void ray_from_sensor(const lens_t *lens, const double xyuv[4], lens_ray *r);
void ray_to_sensor(const lens_t *lens, const lens_ray *r, double xyuv[4]);
void ray_to_outer(const lens_t *lens, const lens_ray *r, double xyuv[4]);
int ray_from_outer(const lens_t *lens, const double xyuv[4], lens_ray *r); /* -1 if off the surface */
void ray_to_stop(const lens_t *lens, const lens_ray *r, double xyuv[4]);

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

/* Ray aiming. Finds the sensor direction (u, v) from sensor point (x, y) whose ray
 * passes through the point (sx, sy) on the stop surface; 0 on success. */
int aim_from_sensor(const lens_t *lens, const double *n, double x, double y, double sx,
                    double sy, double *u, double *v);
/* Finds an object-space ray with the given direction (object at infinity) or from the
 * given point (finite object) through (sx, sy) on the stop. Exactly one of dir/point is
 * non-NULL. On success r is the ray in front of the first surface. */
int aim_from_object(const lens_t *lens, const double *n, const double *dir, const double *point,
                    double sx, double sy, lens_ray *r);

#endif
