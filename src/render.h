#ifndef SPARSELENS_RENDER_H
#define SPARSELENS_RENDER_H
/* Rendering through a lens with the camera-ray estimator of the supplement's Eq. 13
 * (the factor-by-factor mapping is written in render.c).
 *
 * The renderer sees the lens as a map from a sensor ray to the ray leaving the front
 * element (exact tracing or a polynomial system: render_lens.c), and the camera-ray
 * directions come from a sampler with a known density in (u, v) (render_sampler.c). */
#include <stddef.h>

#include "diag.h"
#include "lens.h"
#include "pupil_sampler.h"
#include "scene.h"

/* Sensor ray (x, y, u, v, lambda) in the sensor parametrisation of trace.h (lens frame,
 * direction proportional to (u, v, -1)) to the ray where it leaves the front element:
 * org (on the front element) and unit dir, in the LENS frame, and the Fresnel
 * transmittance eta. Returns 1 if the ray passes the lens (the passage function P_a). */
typedef int (*render_map_fn)(void *ctx, const double in[5], double org[3], double dir[3],
                             double *eta);

typedef struct {
    render_map_fn map;
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
/* The same for a lens known only as a map (analytic lenses): probes cam->map at lambda,
 * at nbins + 1 sensor radii over [0, rmax]. */
int render_sampler_pupil(render_sampler *s, const render_camera *cam, double lambda,
                         double rmax, int nbins, lens_err *err);
void render_sampler_free(render_sampler *s);
/* Draws (u, v) at sensor point (x, y) from two uniforms; returns the density p(u, v)
 * (0 when no direction at that point passes: the caller scores zero). */
double render_sampler_sample(const render_sampler *s, double x, double y, double r1, double r2,
                             double *u, double *v);

typedef struct {
    const scene_t *scene;
    const render_camera *cam;
    const render_sampler *sampler;
    int use_eta;  /* weight by the Fresnel transmittance T_r ... */
    double eta_const; /* ... else by this constant (0 means 1) */
    long spp;
    int threads;  /* <= 0: OpenMP default */
    /* called now and then from one thread with the fraction of rows done; may be NULL */
    void (*progress)(void *ctx, double done);
    void *progress_ctx;
} render_job;

typedef struct {
    double camera_rays; /* rays sent into the lens */
    double passed_rays; /* of those, the ones that passed (P_a = 1) */
    double seconds;
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

/* The weight of one camera ray, P_a T_r cos^4(theta_s0) / p(u, v) without L (see
 * render.c): exposed so that tests can check it against an independent derivation. */
double render_ray_weight(double u, double v, double pdf_uv, double eta);

/* Lens frame <-> scene frame (scene.h): a half turn about y. */
void render_lens_to_scene(const double l[3], double s[3]);

#endif
