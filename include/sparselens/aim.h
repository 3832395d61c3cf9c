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

/* The same in two steps, for many stop points of one object direction or point: the
 * search for the ray through the stop centre (a scan and a Newton solve, most of the
 * cost of one aimed ray) is done once by aim_object_prepare; aim_object_to then follows
 * the target out from it. Each ray is the one aim_from_object finds, bit for bit.
 * lens and n must outlive the start. */
typedef struct {
    const lens_t *lens;
    double o[3], e1[3], e2[3], d[3]; /* dir: origin plane; point: o is the point */
    int finite;
    double dist; /* how far back to start a ray from infinity */
} aim_object_ctx;

typedef struct {
    aim_object_ctx ctx;
    const double *n;
    double a, b; /* the start parameters of the ray through the stop centre */
} aim_object_start;

int aim_object_prepare(const lens_t *lens, const double *n, const double *dir,
                       const double *point, aim_object_start *st);
int aim_object_to(const aim_object_start *st, double sx, double sy, lens_ray *r);
/* aim_object_to with its own bound on the traces it may take (<= 0: none). A stop point
 * no ray reaches is given up after the bound; aim_object_to's bound (aim.c) lies far
 * above what any reachable point of the shipped lenses needs (test_aim). */
int aim_object_to_within(const aim_object_start *st, double sx, double sy, long max_traces,
                         lens_ray *r);

#endif
