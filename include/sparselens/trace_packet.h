#ifndef SPARSELENS_TRACE_PACKET_H
#define SPARSELENS_TRACE_PACKET_H
/* Sensor-to-object tracing of up to TRACE_LANES rays at once, as SIMD vectors.
 *
 * The sequential trace is a long dependency chain (intersection, square root, division,
 * refraction, per surface), so one ray at a time leaves the CPU waiting on latencies.
 * Tracing several independent rays side by side fills those gaps and lets the
 * arithmetic run as vector instructions. Every lane does exactly the arithmetic a lone
 * ray does, so a ray's result does not depend on its neighbours: trace_to_object and
 * trace_sample are this code with one lane, and trace_batch gives the same bits. */
#include "sparselens/trace.h"

#define TRACE_LANES 8

/* Traces the `count` rays r[] (lens frame, from the sensor side) with per-ray index
 * tables n[l] to the target (last = 0: the front surface, refracted there; last = stop:
 * left at the stop hit, unrefracted). r[l] gets the final ray (the hit where it stopped
 * for rays that did not pass), res[l] the result. With last = 0 and outer non-NULL,
 * outer[4 l ..] gets the ray in the outer-pupil parametrisation of trace.h, computed
 * from the normal the intersection already has (the same as ray_to_outer to rounding). */
void trace_packet_to_object(const lens_t *lens, const double *const *n, int count,
                            lens_ray *r, int last, trace_result *res, double *outer);

/* The same with an explicit kernel width (2, 4 or 8 lanes; the CPU must support it):
 * for tests that check that every width gives the same bits. */
void trace_packet_to_object_w(const lens_t *lens, const double *const *n, int count,
                              lens_ray *r, int last, trace_result *res, double *outer,
                              int width);
int trace_packet_width(void); /* the widest kernel this CPU runs */

/* The output stage of trace_sample: converts a traced ray to the target frame (nan and a
 * flag when it did not pass, or sits on a frame singularity). outer: the kernel's outer
 * coordinates of the ray, or NULL to compute them here. */
trace_result trace_sample_finish(const lens_t *lens, trace_target target, const lens_ray *r,
                                 const double *outer, trace_result res, double out[4]);

#endif
