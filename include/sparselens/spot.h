#ifndef SPARSELENS_SPOT_H
#define SPARSELENS_SPOT_H
/* Spot diagrams: a bundle of rays from one field point at one wavelength, aimed
 * through sample points of the stop, and where they land on the sensor. */
#include <stddef.h>

#include "sparselens/imaging.h"

typedef enum { PUPIL_HEXAPOLAR, PUPIL_GRID, PUPIL_RANDOM } pupil_pattern;

int pupil_pattern_parse(const char *name, pupil_pattern *p); /* 0, or -1 */
const char *pupil_pattern_name(pupil_pattern p);

/* About `rays` points in the closed unit disc (the stop, normalised):
 *  hexapolar: the centre and rings k = 1..R at radius k/R with 6k points each,
 *             R the smallest with 1 + 3R(R+1) >= rays;
 *  grid:      a square grid whose inscribed points number about rays;
 *  random:    uniform in area, from a seeded generator (reproducible).
 * Returns the number written, at most max; *xy holds 2 doubles per point. */
size_t pupil_points(pupil_pattern p, size_t rays, unsigned long long seed, double *xy, size_t max);

typedef struct {
    double field, lambda;
    size_t rays, passed;  /* launched, reaching the sensor */
    double chief[4];      /* chief-ray sensor ray x y u v (mm, tangents) */
    double centroid[2];   /* mm */
    double rms_chief, max_chief;       /* radii about the chief ray, mm */
    double rms_centroid, max_centroid; /* radii about the centroid, mm */
    double vignetted;     /* fraction of launched rays that do not reach the sensor */
    double airy;          /* Airy disc radius 1.22 lambda N, mm; N = 1 / (2 sin U), U the
                             widest angle of a passing ray about the chief ray */
    double *ray;          /* passed rays, 4 doubles each (x y u v), `passed` of them */
    double *eta;          /* their transmittances */
    int not_imaged;       /* no chief ray reaches the sensor: every figure is nan */
} spot;

/* Traces one spot: the chief ray, then the pupil pattern. Returns 0; 1 with err set
 * when the chief ray fails (a field past what the lens or system can image: sp is then
 * a spot with not_imaged set, no rays and nan figures); -1 with err set on other
 * errors. sp is owned by the caller and released with spot_free. */
int spot_trace(const imaging *im, double field, double lambda, pupil_pattern pat, size_t rays,
               unsigned long long seed, spot *sp, lens_err *err);
void spot_free(spot *sp);
/* Frees the rays and marks the spot as not imaged: every figure nan (field, lambda kept). */
void spot_mark_not_imaged(spot *sp);

/* Recomputes the statistics from the stored rays (after spot_shift). */
void spot_stats(spot *sp);
/* Moves the sensor plane by dz mm along +z for the stored rays and the chief ray. */
void spot_shift(spot *sp, double dz);
/* The plane shift that minimises the summed squared RMS radius about the centroid of
 * the given spots (closed form: each radius is quadratic in the shift). */
double spot_best_shift(const spot *sp, size_t n);

/* Pools spots of one field at several wavelengths into one (rays equally weighted);
 * its chief ray is that of sp[primary]; lambda is NAN. Caller frees with spot_free. */
int spot_pool(const spot *sp, size_t n, size_t primary, spot *total);

/* Pictures of nmodels x nfields x nl spots (the per-wavelength spots of a field as nl
 * consecutive entries, fields of a model consecutive). */
typedef struct {
    int nmodels, nfields, nl;
    const char *const *model_names; /* "lens", "poly" */
    const spot *spots;              /* nmodels * nfields * nl, index (m * nfields + f) * nl + l */
    const char *title;
    int finite;                     /* fields are object heights in mm (else degrees) */
} spot_figure;

/* One panel per field (a row per model), wavelengths in their own colours, a scale bar
 * in um, the Airy disc, labels. Through outfile. */
int spot_write_png(const spot_figure *fig, const char *path, lens_err *err);
/* The same panels as float images, one channel per wavelength "lambda_NNNnm" (rays per
 * square micrometre, per launched ray: a probability density) and their sum "density". */
int spot_write_exr(const spot_figure *fig, const char *path, double *um_per_pixel,
                   int *panel_px, lens_err *err);

#endif
