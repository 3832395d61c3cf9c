#ifndef SPARSELENS_AIM_H
#define SPARSELENS_AIM_H
/* Ray aiming (aim.c): the ray from a sensor point, or from an object direction or point,
 * that crosses the stop surface at a given point. n: the indices (lens_indices). */
#include "sparselens/ray_frames.h"

/* Finds the sensor direction (u, v) from sensor point (x, y) whose ray
 * passes through the point (sx, sy) on the stop surface; 0 on success. */
int aim_from_sensor(const lens_t *lens, const double *n, double x, double y, double sx,
                    double sy, double *u, double *v);
/* Finds an object-space ray with the given direction (object at infinity) or from the
 * given point (finite object) through (sx, sy) on the stop. Exactly one of dir/point is
 * non-NULL. On success r is the ray in front of the first surface. */
int aim_from_object(const lens_t *lens, const double *n, const double *dir, const double *point,
                    double sx, double sy, lens_ray *r);

#endif
