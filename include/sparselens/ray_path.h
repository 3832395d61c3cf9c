#ifndef SPARSELENS_RAY_PATH_H
#define SPARSELENS_RAY_PATH_H
/* An object-space ray through the exact lens surface by surface, keeping what the
 * sensor-side parametrisation forgets: where it meets each surface and the optical
 * path it has travelled (the layout draws the first, the wavefront needs the second). */
#include "sparselens/trace.h"

/* Traces r (in front of the first surface) through every surface. pts (may be NULL)
 * gets 3 doubles per surface reached: the hit points, in order. The optical path is
 * accumulated onto *opl (may be NULL) from r's origin. Returns the number of surfaces
 * passed (lens->nsurf when the ray passes them all; r is then on the last surface with
 * its image-space direction); a ray clipped by surface i returns i with pts[i] its hit
 * on the surface's extension, when it meets it at all (*clip_hit 1, else 0). */
int ray_path(const lens_t *lens, const double *n, lens_ray *r, double *pts, double *opl, int *clip_hit);

#endif
