#ifndef SPARSELENS_TRACE_CLIP_H
#define SPARSELENS_TRACE_CLIP_H
/* Passage surfaces and the hits on them (lens-trace's ap_x ap_y and sN_x sN_y columns).
 *
 * A fitted system decides passage by pass circles on its outputs: the ray passes when
 * its hit on each modelled surface lies within that surface's rim. Which surfaces must
 * be modelled is found over the whole ray space a system serves (every sensor point,
 * every direction that can pass: sampling.h's full strategy), weighted by light. The
 * hits are those of the ray traced with every rim extended, so they are defined (and
 * smooth) on both sides of a rim: a fit sees rays just inside and just outside. */
#include <stddef.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/sampling.h"

/* The sensor ray in[4] = (x, y, u, v) (trace.h) at the wavelength whose indices are n,
 * traced towards the object from the rear surface down to surface `last` with every
 * rim extended: hit[2 s], hit[2 s + 1] get (x, y) of its hit on surface s (mm, lens
 * frame; nan where it does not get), outside[s] (may be NULL) whether that hit lies
 * outside the semi-diameter, *eta the Fresnel transmittance (0 unless it got through).
 * Returns the surface where the ray missed or was totally reflected, or -1. The
 * clipped tracer passes the ray exactly when this returns -1 (with last 0) and no
 * hit is outside. */
int trace_unclipped(const lens_t *lens, const double *n, const double in[4], int last,
                    double *hit, unsigned char *outside, double *eta);

/* One ray's hit on surface `surf` (0-based) as above; 1 when finite. */
int trace_surface_hit(const lens_t *lens, int surf, const double *n, const double in[4],
                      double hit[2]);

/* count rays (rows x y u v lambda): hit gets count rows of nsel (x, y) pairs, the hits
 * on surfaces surf[0..nsel-1]. threads <= 0: OpenMP default. 0, or -1 with err set
 * (a wavelength out of range: its rows are nan; out of memory). */
int trace_surfaces_batch(const lens_t *lens, int nsel, const int *surf, size_t count,
                         const double *in, double *hit, int threads, lens_err *err);

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
