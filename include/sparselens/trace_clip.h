#ifndef SPARSELENS_TRACE_CLIP_H
#define SPARSELENS_TRACE_CLIP_H
/* Vignetting surfaces and the hits on them (lens-trace --clip-columns).
 *
 * A fitted system decides passage only by pass circles on its outputs. The front hit
 * (out_x, out_y) and the stop hit (ap_x, ap_y, trace_stop.h) catch rays blocked there;
 * rays clipped by an inner element's rim pass both. Recording the hit on every surface
 * that really clips (sN_x, sN_y) gives lens-fit a circle for each of them. */
#include <stddef.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/sampling.h"

/* Share of rays, per surface, that end blocked there (outside its semi-diameter, the
 * stop included): in is count rows of (x, y, u, v, lambda), share[nsurf] gets the
 * fractions. threads <= 0: OpenMP default. 0, or -1 with err set (out of memory, a
 * wavelength out of range). */
int trace_clip_census(const lens_t *lens, size_t count, const double *in, double *share,
                      int threads, lens_err *err);

/* The surfaces (0-based, increasing) whose share >= min_share, leaving out the stop
 * (it has its own columns) and, when skip_front, surface 0 (the front hit is already an
 * output of the outer frame). surf needs room for nsurf entries; returns their count. */
int trace_clip_choose(const lens_t *lens, const double *share, double min_share,
                      int skip_front, int *surf);

/* The pilot: census of `rays` rays generated with *so (its seed included), then the
 * choice above. share[nsurf] gets the shares, surf the surfaces; returns their count,
 * or -1 with err set. */
int trace_clip_pilot(const lens_t *lens, const sampling_options *so, size_t rays,
                     double min_share, int skip_front, double *share, int *surf,
                     lens_err *err);

/* Hits on surface `surf` (0-based) of count rays: hit gets count rows of (x, y), in mm
 * of the lens frame, or (nan, nan) when the ray does not reach the surface within its
 * semi-diameter (blocked before or at it). The same trace as trace_stop_batch, ended
 * at `surf` instead of the stop. Return as trace_stop_batch. */
int trace_surface_batch(const lens_t *lens, int surf, size_t count, const double *in,
                        double *hit, int threads, lens_err *err);

/* One ray (in[4] = x, y, u, v at the indices n): its hit on surface `surf` as above;
 * 1 when finite, 0 otherwise. */
int trace_surface_hit(const lens_t *lens, int surf, const double *n, const double in[4],
                      double hit[2]);

#endif
