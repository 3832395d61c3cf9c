#ifndef SPARSELENS_RENDER_H
#define SPARSELENS_RENDER_H
/* Rendering through a lens with the camera-ray estimator of the supplement's Eq. 13
 * (the factor-by-factor mapping is written in render.c).
 *
 * The renderer sees the lens as a map from a sensor ray to the ray leaving the front
 * element (exact tracing or a polynomial system: render_lens.c), and the camera-ray
 * directions come from a sampler with a known density in (u, v) (render_sampler.c). */
#include <stddef.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/pupil_sampler.h"
#include "sparselens/scene.h"

/* Sensor ray (x, y, u, v, lambda) in the sensor parametrisation of trace.h (lens frame,
 * direction proportional to (u, v, -1)) to the ray where it leaves the front element:
 * org (on the front element) and unit dir, in the LENS frame, and the Fresnel
 * transmittance eta. Returns 1 if the ray passes the lens (the passage function P_a). */
typedef int (*render_map_fn)(void *ctx, const double in[5], double org[3], double dir[3],
                             double *eta);

/* The same sensor ray to the outer pupil's coordinates o = (out_x, out_y, out_u, out_v)
 * (trace.h) and, if jac is not NULL, their Jacobian jac[4 k + i] = d o_k / d in_i over
 * in = (x, y, u, v) (NAN when unknown). Returns P_a as map does, for the same ray:
 * ray_from_outer(lens, o) is the ray map gives. For the full estimator only. */
typedef int (*render_outer_fn)(void *ctx, const double in[5], double o[4], double jac[16],
                               double *eta);

/* The same for n rays at once (rows of in: n x 5; org, dir: n x 3; eta, pass: n): what a
 * polynomial system evaluates in vector blocks. NULL: the renderer calls map per ray. */
typedef void (*render_map_batch_fn)(void *ctx, size_t n, const double *in, double *org,
                                    double *dir, double *eta, unsigned char *pass);

/* outer for n rays at once (rows: in n x 5, o n x 4, jac n x 16, eta and pass n). */
typedef void (*render_outer_batch_fn)(void *ctx, size_t n, const double *in, double *o,
                                      double *jac, double *eta, unsigned char *pass);

typedef struct {
    render_map_fn map;
    render_map_batch_fn map_batch; /* may be NULL */
    render_outer_batch_fn outer_batch; /* may be NULL: outer per ray */
    render_outer_fn outer; /* NULL: no full estimator (analytic lenses) */
    const lens_t *lens;    /* the lens whose front element o lies on (with outer) */
    void *ctx;
    double sensor_w, sensor_h; /* mm, centred on the axis */
    double rear_dist;          /* sensor plane to the rear element's vertex, mm */
    double rear_radius;        /* rear element's semi-diameter, mm */
} render_camera;

/* Camera-ray directions at a sensor point, with their density p(u, v) in du dv
 * (render_sampler.c).
 *  REAR:  a uniform point on the rear element's disk (the plane of its vertex), the
 *         naive sampler; p = rear_dist^2 / (pi rear_radius^2).
 *  PUPIL: the "line pupil": the tracer's pupil sampler (pupil_sampler.h), an occupancy
 *         grid of the passing directions per tabulated sensor radius, turned to the
 *         point's azimuth; p is the exact density of its mixture. */
typedef enum { RENDER_SAMPLE_REAR, RENDER_SAMPLE_PUPIL } render_sampling;

typedef struct {
    render_sampling kind;
    double rear_dist, rear_radius; /* REAR */
    pupil_sampler *ps;             /* PUPIL, owned */
} render_sampler;

void render_sampler_rear(render_sampler *s, const render_camera *cam);
/* The line pupil of an exact lens, probed by the packet tracer at wavelengths spread
 * over [lambda_min, lambda_max], for sensor radii up to rmax. */
int render_sampler_lens(render_sampler *s, const lens_t *lens, double lambda_min,
                        double lambda_max, double rmax, int threads, lens_err *err);
/* The line pupil of the stop alone: directions that pass the rear element and the stop
 * (the lens without the clipping of the front group: vignetting off). */
int render_sampler_stop(render_sampler *s, const lens_t *lens, double lambda_min,
                        double lambda_max, double rmax, lens_err *err);
/* The same for a lens known only as a map (analytic lenses): probes cam->map at lambda,
 * at nbins + 1 sensor radii over [0, rmax]. */
int render_sampler_pupil(render_sampler *s, const render_camera *cam, double lambda,
                         double rmax, int nbins, lens_err *err);
void render_sampler_free(render_sampler *s);
/* Draws (u, v) at sensor point (x, y) from two uniforms; returns the density p(u, v)
 * (0 when no direction at that point passes: the caller scores zero). */
double render_sampler_sample(const render_sampler *s, double x, double y, double r1, double r2,
                             double *u, double *v);
/* The same directions with the same density, smooth in (r1, r2) (the line pupil by
 * pupil_sampler_sample_rows): what camera rays use, so that the stratification of the
 * pixel's (r1, r2) points carries over to the pupil. */
double render_sampler_sample_2d(const render_sampler *s, double x, double y, double r1,
                                double r2, double *u, double *v);

/* Eq. 13 (the default), or the unsimplified estimator: Eq. 3 with G-bar (Eq. 12) and
 * p_A(s1) (Eq. 8) each evaluated from its own terms, from the lens's Jacobian
 * (render_full.c). */
typedef enum { RENDER_ESTIMATOR_EQ13, RENDER_ESTIMATOR_FULL } render_estimator;

/* The factors of the full estimator for one camera ray (render_full_weight). */
typedef struct {
    /* Eq. 8, the sensor point s0 fixed */
    double A;        /* |det d(out_x, out_y) / d(u, v)|: line pupil -> front element */
    double J_all;    /* area on the front element per d out_x d out_y (frames) */
    double ds1_dsf;  /* area at s1 per area on the front element */
    double cos_s0, cos_s0p; /* at the sensor point and at the line-pupil point */
    double pA_s1;    /* Eq. 8: density of s1 per area of the scene surface */
    /* Eq. 12, the scene point s1 fixed */
    double A_s1;     /* |det d(out_x, out_y) / d(x, y)| along the rays through s1 */
    double cos_sf, cos_s1; /* the ray against the front element's and s1's normals */
    double dist_f1;  /* |s_f - s1|, mm */
    double G;        /* Eq. 12 without P_a T_r: cos(theta_s1) dw_s1 / dA(s0) =
                      * J_all A_s1 cos_sf cos_s1 / dist_f1^2 */
    double weight;   /* T_r G / p_A(s1) (W_e / p_A(s0) = 1): the ray's weight before L */
} render_full_terms;

/* Evaluates the factors at the sensor ray in (x, y, u, v, lambda) drawn with density pdf
 * (per du dv), whose outer-pupil coordinates o and Jacobian jac come from cam->outer,
 * with transmittance eta, reaching the scene at s1 with unit normal n1 (scene frame).
 * 0, or -1 when a factor is not finite and positive (|A| = 0, a blocked difference
 * step, a grazing or exactly focused hit): the caller falls back to Eq. 13. */
int render_full_weight(const lens_t *lens, const double in[5], const double o[4],
                       const double jac[16], double pdf, double eta, const double s1[3],
                       const double n1[3], render_full_terms *t);

/* The pixel's reconstruction filter, sampled by importance (the sample offset is drawn
 * from the filter itself, every sample weighs 1): BOX is the pixel's own area (the mean
 * irradiance over it: what the tests compare with closed forms); TENT has radius
 * filter_radius pixels on each axis (separable), trading a little sharpness for noise. */
typedef enum { RENDER_FILTER_BOX, RENDER_FILTER_TENT } render_filter;

/* Wavelengths per camera sample in spectral mode (hero wavelength plus evenly rotated
 * companions, Wilkie et al. 2014). */
#define RENDER_HERO 4

typedef struct {
    const scene_t *scene;
    const render_camera *cam;
    /* 1: every wavelength of a sample shares one camera ray (the lens does not disperse,
     * or dispersion is off): one lens evaluation and one scene path per sample carry all
     * channels / hero wavelengths. 0: one ray per wavelength (the lens sees lambda). */
    int achromatic;
    render_filter filter;
    double filter_radius; /* TENT: pixels (0 means 1) */
    render_estimator estimator;
    const render_sampler *sampler;
    int use_eta;  /* weight by the Fresnel transmittance T_r ... */
    double eta_const; /* ... else by this constant (0 means 1) */
    long spp;
    int threads;  /* <= 0: OpenMP default */
    /* pixels rendered: [x0, x1) x [y0, y1); x1 == 0: the whole image. The others are 0
     * (a crop: a test looks at one bokeh at a time). Samples do not depend on it. */
    int x0, y0, x1, y1;
    /* called now and then from one thread with the fraction of rows done; may be NULL */
    void (*progress)(void *ctx, double done);
    void *progress_ctx;
} render_job;

typedef struct {
    double camera_rays; /* rays sent into the lens */
    double passed_rays; /* of those, the ones that passed (P_a = 1) */
    double full_rays;   /* full estimator: rays weighted by it (they hit the scene) */
    double full_fallback; /* ... and rays where it could not be evaluated (Eq. 13 used) */
    double seconds;
    double cpu_seconds; /* processor time of the whole process over the render: with one
                         * thread, the render's own time, whatever else runs */
} render_stats;

/* The wavelength bands of the rgb and spectral modes, um: blue [0.40, 0.49), green
 * [0.49, 0.58), red [0.58, 0.70]; rgb mode traces each band at one wavelength. */
#define RENDER_LAMBDA_MIN 0.40
#define RENDER_LAMBDA_MAX 0.70
double render_channel_lambda(int c); /* 0 r, 1 g, 2 b */

/* Renders width x height pixels into rgb (3 floats per pixel, row 0 at the top: the
 * mean irradiance over the pixel, in the scene's radiance units times sr). var, if not
 * NULL, gets the variance of each pixel's estimate (sample variance / spp), per channel.
 * 0 on success. */
int render_image(const render_job *job, float *rgb, float *var, render_stats *st,
                 lens_err *err);

/* The noise figure of two renders a and b of the same scene with different seeds (3
 * floats per pixel): per pixel and lit channel, the variance of one render's estimate,
 * (a - b)^2 / 2, over the squared mean of the two; averaged over the lit channels and
 * over the 3x3 neighbourhood (a single pair is a one-degree-of-freedom estimate); the
 * median over lit pixels. From independent renders, it holds for any sampler (a sample
 * variance within a pixel does not, once samples are stratified). Times render time, it
 * is what equal-time comparisons divide (variance falls as 1/spp). NAN if nothing is lit. */
double render_noise(int width, int height, const float *a, const float *b);

/* The weight of one camera ray, P_a T_r cos^4(theta_s0) / p(u, v) without L (see
 * render.c): exposed so that tests can check it against an independent derivation. */
double render_ray_weight(double u, double v, double pdf_uv, double eta);

/* Lens frame <-> scene frame (scene.h): a half turn about y. */
void render_lens_to_scene(const double l[3], double s[3]);

#endif
