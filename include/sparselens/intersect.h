#ifndef SPARSELENS_INTERSECT_H
#define SPARSELENS_INTERSECT_H
/* Ray-surface intersection for the exact tracer (frame and sag: lens.h).
 *
 * Planes, spheres and conics are solved in closed form from the implicit surface in
 * vertex-relative coordinates, c (x^2 + y^2 + (1 + k) z^2) - 2 z = 0, with the stable
 * form of the quadratic, so a nearly flat surface (|R| = 1e6 mm) loses no digits. Of
 * its roots only the vertex branch, (1 + k) c z <= 1, is the lens surface. Even
 * aspheres are solved by Newton's method inside a sign-change bracket, falling back to
 * bisection, so a result is always a verified root or a flagged failure. */
#include "sparselens/lens.h"

typedef enum {
    ISECT_HIT = 0,
    ISECT_MISS,    /* the ray does not meet the surface (or its vertex branch) */
    ISECT_OUTSIDE  /* the first meeting is beyond the clip radius */
} isect_status;

/* Rays may start this far (mm) behind a surface and still hit it: a ray that starts on
 * the surface itself (a reversed outer-pupil ray) must find it at t ~ 0. */
#define ISECT_T_MIN (-1e-7)

/* Intersects the ray o + t d (d unit) with surface s whose vertex is at z = vz.
 * clip_r2: squared radius beyond which a hit is ISECT_OUTSIDE (INFINITY: no clip; an
 * asphere is then searched out to 1.5 semi-diameters). On ISECT_HIT, *t is the ray
 * parameter, p the hit point and nrm the unit normal at p pointing to object space
 * ((0, 0, -1) at the vertex). p and nrm are left alone otherwise. */
isect_status intersect_surface(const lens_surface *s, double vz, const double o[3],
                               const double d[3], double clip_r2, double *t, double p[3],
                               double nrm[3]);

/* Unit normal (object-space side) of s at the vertex-relative point (x, y) on it. */
void surface_normal(const lens_surface *s, double x, double y, double nrm[3]);

#endif
