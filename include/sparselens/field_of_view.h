#ifndef SPARSELENS_FIELD_OF_VIEW_H
#define SPARSELENS_FIELD_OF_VIEW_H
/* Field of view from real chief rays (not paraxial), so that fisheyes past 180 degrees
 * come out right. */
#include "sparselens/lens.h"

/* Full field angle (degrees) of the chief ray that lands at sensor radius r_sensor.
 * When no chief ray reaches that radius (a sensor corner outside the image circle),
 * *r_used is the largest radius that a chief ray does reach and the angle is for it.
 * Returns 0, or -1 with err set (no chief ray passes at all). */
int lens_field_of_view(const lens_t *lens, double lambda_um, double r_sensor, double *fov_deg,
                       double *r_used, lens_err *err);

/* Object-space angle from the axis (degrees, may exceed 90) of the chief ray from sensor
 * point (r, 0); -1 if no chief ray through the stop centre passes there. */
int lens_chief_angle(const lens_t *lens, const double *n, double r, double *angle_deg);

#endif
