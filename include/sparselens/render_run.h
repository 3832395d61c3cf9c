#ifndef SPARSELENS_RENDER_RUN_H
#define SPARSELENS_RENDER_RUN_H
/* The whole of lens-render as a library call: scene -> camera (exact lens, a given
 * .poly, or a system fitted for the scene's effects) -> image -> EXR (+ PNG). */
#include <stdio.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/render.h"

typedef struct {
    const char *scene;      /* scene file */
    const lens_load_options *load; /* glass catalogs and fallback for the lens; NULL: defaults */
    const char *exr;        /* output image (required) */
    const char *png;        /* preview, or NULL */
    const char *cache_dir;  /* fitted systems; NULL: $XDG_CACHE_HOME/sparselens or ~/.cache/sparselens */
    int exact;              /* trace exactly instead of a polynomial system */
    int rear_sampling;      /* sample the rear element instead of the line pupil */
    render_estimator estimator; /* Eq. 13 (default) or the full one */
    long spp;               /* 0: the scene's */
    int threads;            /* <= 0: OpenMP default */
    const char *reference;  /* an EXR to compare with (RMS error printed to log), or NULL */
    const char *noise_against; /* a render of the same scene with another seed: the noise
                                * figure (render_noise) printed to log, or NULL */
    unsigned long seed;     /* 0: the scene's */
    /* The scene's camera overridden (lens-render --focus, --fstop, --blades): */
    double focus;           /* mm in front of the front vertex, INFINITY; 0: the scene's */
    double fstop;           /* 0: the scene's */
    int blades;             /* 0: the scene's; RENDER_BLADES_ROUND: the stop's circle;
                               3 .. 16: that polygon (the scene's rotation) */
    const char *emit_camera; /* write the camera module (camera.h) here instead of rendering */
    const char *camera_name; /* the prefix of the module's symbols; NULL: lens_camera */
    FILE *log;              /* decisions and figures (stderr in lens-render); may be NULL */
    FILE *figures;          /* the figures asked for (--reference, --noise-against), also
                               with -q; NULL: log */
    void (*progress)(void *ctx, double done);
    void *progress_ctx;
} render_options;

#define RENDER_BLADES_ROUND (-1)

int render_run(const render_options *opt, render_stats *st, lens_err *err);

/* RMS difference of rgb (width x height, as render_image fills it) from the R, G, B
 * channels of the EXR file ref, and that over ref's mean. 0 on success. */
int render_compare(const char *ref, int width, int height, const float *rgb, double *rms,
                   double *rel, lens_err *err);

/* Reads the R, G, B channels of an EXR file of width x height pixels into *rgb (3 floats
 * per pixel, malloc'ed). 0 on success. */
int render_read_rgb(const char *path, int width, int height, float **rgb, lens_err *err);

/* Writes the preview: exposure so that the 99th percentile of the luminance maps to
 * white, then the sRGB curve. rgb as render_image fills it. */
int render_write_png(const char *path, int width, int height, const float *rgb, lens_err *err);

#endif
