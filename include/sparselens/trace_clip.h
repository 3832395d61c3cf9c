#ifndef SPARSELENS_TRACE_CLIP_H
#define SPARSELENS_TRACE_CLIP_H
/* Passage surfaces and the hits on them (lens-trace's ap_x ap_y and sN_x sN_y columns).
 *
 * A fitted system decides passage by pass circles on its outputs: the ray passes when
 * its hit on each modelled surface lies within that surface's rim. Which surfaces must
 * be modelled is found over the whole ray space a system serves (every sensor point,
 * every direction that can pass), weighted by light: the pilot of clip_pilot.h. The
 * hits are those of the ray traced with every rim extended, so they are defined (and
 * smooth) on both sides of a rim: a fit sees rays just inside and just outside. */
#include <stddef.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"

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

#endif
