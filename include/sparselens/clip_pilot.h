#ifndef SPARSELENS_CLIP_PILOT_H
#define SPARSELENS_CLIP_PILOT_H
/* Which surfaces a system must model for its passage (trace_clip.h): found by a pilot
 * trace over the whole ray space a system serves, the directions of sampling.h's full
 * strategy, weighted by light (clip_pilot.c). In the sample stage, as it draws rays. */
#include <stddef.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/sampling.h"

/* The pilot: `rays` rays of the full strategy (the sensor, wavelengths, seed and
 * threads of *so; its strategy is ignored), each weighted by its share of the light
 * (cos^4 theta times its transmittance). The stop, and with skip_front the front
 * element (the outer frame's out_x out_y test it), are always modelled; then surfaces
 * are added, the one that blocks most of the still unblocked light first, while one
 * blocks >= min_share of the light the lens passes, at most max_surf of them. surf
 * (room for nsurf) gets them in increasing order; share[nsurf] the light each blocks
 * (see trace_clip.c); *leak the light that no modelled surface blocks (what a system
 * would let through falsely with perfect fits). Returns their count, or -1 with err. */
int trace_clip_pilot(const lens_t *lens, const sampling_options *so, size_t rays,
                     double min_share, int skip_front, int max_surf, double *share, int *surf,
                     double *leak, lens_err *err);

#endif
