#ifndef SPARSELENS_RENDER_EFFECTS_H
#define SPARSELENS_RENDER_EFFECTS_H
/* Simulate only the lens effects a scene calls for (render_effects.c): which inputs and
 * outputs the polynomial system needs, over which part of the sensor, to which
 * tolerance; and a cache of fitted systems keyed by the lens and those choices. */
#include <stdio.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/poly.h"
#include "sparselens/render.h"
#include "sparselens/scene.h"

typedef struct {
    int dispersion;       /* lambda is an input: rgb and spectral scenes through a lens
                           * whose glasses disperse */
    int disperses;        /* the lens's indices change over the render's wavelengths */
    int transmittance;    /* out_eta is an output and weights the rays */
    int vignetting;       /* pass circles on the front element as well as the stop */
    double domain_radius; /* sensor radius in use, mm (the fit's domain) */
    double pixel_pitch;   /* mm */
    double tolerance;     /* fit tolerance on the directions: a tenth of a pixel over the efl */
    double efl;           /* mm */
    double focus;         /* mm, INFINITY: the object distance in focus */
    /* why: the measured quantities behind the "auto" choices */
    double vignetting_loss;   /* share of stop-passing rays clipped elsewhere at the field edge */
    double eta_variation;     /* relative change of the mean transmittance centre -> edge */
    double lateral_colour_px; /* chief-ray shift between the band ends at the edge, pixels */
    double eta_centre;        /* mean transmittance on the axis: used when transmittance is off */
} render_effects;

/* 1 when some medium of the lens has different indices at RENDER_LAMBDA_MIN and _MAX. */
int render_lens_disperses(const lens_t *lens);

/* The lens's mean transmittance on the axis at the d line (render_effects' eta_centre),
 * alone: the weight of every ray where the transmittance is not traced ray by ray.
 * 0, or -1 with err set. */
int render_effects_eta_centre(const lens_t *lens, double *eta, lens_err *err);

/* Decides from the scene and a quick exact probe of the lens (at the d line). */
int render_effects_decide(const scene_t *s, const lens_t *lens, double sensor_w,
                          double sensor_h, render_effects *e, lens_err *err);
/* "effects on: ...; off: ..." and the reasons, a few lines. */
void render_effects_print(FILE *f, const render_effects *e);

/* Cache key: a hash of the lens as written (after focus and f-stop are applied) and of
 * the effects; 16 hex digits. */
void render_effects_key(const lens_t *lens, const render_effects *e, char key[17]);

/* The system for lens and e: read from cache_dir/<key>.poly, else fitted (and written
 * there; a cache that cannot be written only costs a refit). log gets what happened and
 * what each effect costs per ray in the system's batch evaluation (no other system is
 * fitted to compare with). */
poly_system *render_effects_system(const lens_t *lens, const render_effects *e,
                                   const char *cache_dir, int threads, FILE *log,
                                   lens_err *err);

/* Fits the system for lens and e (render_fit.c): sensor rays over the domain, traced
 * exactly to the outer pupil and to the stop; *seconds gets the time taken. */
poly_system *render_fit(const lens_t *lens, const render_effects *e, int threads,
                        double *seconds, lens_err *err);

/* The line pupil (render_sampler_lens, or with stop_only render_sampler_stop) for lens over sensor radii [0, rmax] at the
 * wavelengths [lambda_min, lambda_max]: read from cache_dir/<key>.pupil, keyed by the lens
 * as written and those three numbers, else built and written there. */
int render_effects_sampler(const lens_t *lens, double lambda_min, double lambda_max,
                           double rmax, int stop_only, const char *cache_dir, int threads,
                           FILE *log, render_sampler *smp, lens_err *err);

/* $XDG_CACHE_HOME/sparselens, or $HOME/.cache/sparselens; "" when neither is set. */
void render_default_cache_dir(char *buf, size_t len);

#endif
