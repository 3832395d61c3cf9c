#ifndef SPARSELENS_TRACE_CORE_H
#define SPARSELENS_TRACE_CORE_H
/* The scalar tracer, for any direction and with optional clipping: object-to-sensor
 * traces (trace_to_sensor) and ray aiming (aim.c) use it. Sensor-to-object traces go
 * through the SIMD packet kernel (trace_packet.h), which does the same physics. */
#include "sparselens/trace.h"

/* Traces r surface by surface from `first` to `last` (first > last: towards the
 * object, else towards the sensor), refracting at each surface, at `last` only when
 * refract_last is non-zero. clip = 0 extends every surface beyond its semi-diameter
 * (ray aiming needs a smooth function of the start ray; vignetting is checked after).
 * On return r holds the last hit, or the hit where the ray stopped. */
trace_result trace_path(const lens_t *lens, const double *n, lens_ray *r, int first, int last,
                        int refract_last, int clip);

#endif
