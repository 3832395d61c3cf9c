#ifndef SPARSELENS_RAY_FRAMES_H
#define SPARSELENS_RAY_FRAMES_H
/* Rays in the lens frame (lens.h: z towards the sensor) and the parametrisations the
 * tracer and the sample files use (ray_frames.c). Ray parametrisations (design.md):
 *  - sensor:  position (x, y) on the sensor plane z = lens_total_track(); direction
 *             towards the lens proportional to (u, v, -1) in the lens frame, i.e.
 *             u = dx/d(-z), v = dy/d(-z). A ray arriving at the sensor with direction d
 *             is described by the reversed direction, so a round trip is the identity.
 *  - outer:   the hit (x, y) on the first surface; direction components (u, v) of the
 *             outgoing unit direction d along the tangent frame at the hit:
 *               n  = unit surface normal pointing to object space ((0,0,-1) at the vertex)
 *               ex = (1 - k n.x^2, -k n.x n.y, n.x), ey = (-k n.x n.y, 1 - k n.y^2, n.y),
 *               k = 1 / (1 - n.z): the x and y axes turned by the smallest rotation
 *               that takes -z to n
 *             so out_u = d.ex, out_v = d.ey and d.n = sqrt(1 - u^2 - v^2) > 0. This
 *             stays valid for rays past 90 degrees from the axis and is singular
 *             nowhere on a front surface (n.z < 0); turning a ray about the axis turns
 *             (u, v) with it, as it does (x, y).
 *  - stop:    the hit (x, y) on the stop surface; direction as on the sensor side
 *             (tangents towards the object: d proportional to (u, v, -1)).
 *  - eta:     product over all surfaces of the unpolarised Fresnel transmittance. */
#include "sparselens/lens.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    double o[3]; /* origin, mm, lens frame */
    double d[3]; /* unit direction */
} lens_ray;

/* Tangent frame at the unit normal n (n.z < 0, towards the object): the images of the
 * x and y axes under the smallest rotation that takes -z to n,
 *   ex = (1 - k n.x^2, -k n.x n.y, n.x),  ey = (-k n.x n.y, 1 - k n.y^2, n.y),
 *   k = 1 / (1 - n.z).
 * Turning the lens's point and ray about the axis turns this frame with them, so the
 * outer pupil's (u, v) turn like any direction, and a fit in the meridional frame
 * models them too (lens-fit --frame). Defined wherever n.z < 1: every front surface;
 * -1 elsewhere. Inline: the renderer's polynomial path makes one a camera ray. */
static inline int lens_outer_frame(const double n[3], double ex[3], double ey[3])
{
    double q = 1 - n[2];
    if (!(q > 1e-300))
        return -1;
    double k = 1 / q;
    ex[0] = 1 - k * n[0] * n[0];
    ex[1] = -k * n[0] * n[1];
    ex[2] = n[0];
    ey[0] = ex[1];
    ey[1] = 1 - k * n[1] * n[1];
    ey[2] = n[1];
    return 0;
}

/* Conversions between parametrisations and lens-frame rays. */
void ray_from_sensor(const lens_t *lens, const double xyuv[4], lens_ray *r);
void ray_to_sensor(const lens_t *lens, const lens_ray *r, double xyuv[4]);
void ray_to_outer(const lens_t *lens, const lens_ray *r, double xyuv[4]);
int ray_from_outer(const lens_t *lens, const double xyuv[4], lens_ray *r); /* -1 if off the surface */
void ray_to_stop(const lens_t *lens, const lens_ray *r, double xyuv[4]);

/* Outer-pupil coordinates of an object-space ray travelling into the lens: its hit on
 * the front surface and the reversed direction there. -1 if it misses. */
int outer_of_object_ray(const lens_t *lens, const lens_ray *r, double outer[4]);

#ifdef __cplusplus
}
#endif

#endif
