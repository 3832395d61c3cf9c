/* Camera-ray direction samplers with known densities (render.h): the rear element's
 * disk, and the line pupil, which is the tracer's pupil sampler (pupil_sampler.h) built
 * either from the exact lens or, for lenses known only as a map, by probing the map.
 *
 * Why the line pupil is unbiased: it samples a mixture of uniform densities over grid
 * cells that together hold every direction that passes the lens at that sensor radius
 * (probed, then grown by one cell; see pupil_sampler.h), so the estimator's support
 * (P_a = 1) lies inside the sampler's, and it returns the mixture's exact density;
 * directions in those cells that do not pass score 0. */
#include <math.h>
#include <string.h>

#include "sparselens/render.h"
#include "sparselens/trace.h"

void render_sampler_rear(render_sampler *s, const render_camera *cam)
{
    memset(s, 0, sizeof *s);
    s->kind = RENDER_SAMPLE_REAR;
    s->rear_dist = cam->rear_dist;
    s->rear_radius = cam->rear_radius;
}

void render_sampler_free(render_sampler *s)
{
    pupil_sampler_free(s->ps);
    s->ps = NULL;
}

int render_sampler_lens(render_sampler *s, const lens_t *lens, double lambda_min,
                        double lambda_max, double rmax, int threads, lens_err *err)
{
    memset(s, 0, sizeof *s);
    pupil_sampler_options po = {.lambda_min = lambda_min, .lambda_max = lambda_max,
                                .sensor_radius = rmax, .threads = threads};
    s->kind = RENDER_SAMPLE_PUPIL;
    s->ps = pupil_sampler_build(lens, &po, err);
    return s->ps ? 0 : -1;
}

typedef struct {
    const render_camera *cam;
    double lambda;
} map_probe;

static void probe_map(void *ctx, double r, int m, const double *u, const double *v,
                      unsigned char *pass)
{
    const map_probe *p = ctx;
    for (int k = 0; k < m; k++) {
        double in[5] = {r, 0, u[k], v[k], p->lambda}, o[3], d[3], eta;
        pass[k] = pass[k] || p->cam->map(p->cam->ctx, in, o, d, &eta);
    }
}

int render_sampler_pupil(render_sampler *s, const render_camera *cam, double lambda,
                         double rmax, int nbins, lens_err *err)
{
    memset(s, 0, sizeof *s);
    map_probe p = {cam, lambda};
    pupil_sampler_options po = {.lambda_min = lambda, .lambda_max = lambda,
                                .sensor_radius = rmax, .radii = nbins + 1};
    /* every passing ray crosses the rear element's vertex plane within about its disk;
     * widened by half, since a real rear surface is curved */
    s->kind = RENDER_SAMPLE_PUPIL;
    s->ps = pupil_sampler_build_probe(probe_map, &p, cam->rear_dist, 1.5 * cam->rear_radius, &po,
                                      err);
    return s->ps ? 0 : -1;
}

typedef struct {
    const lens_t *lens;
    double *n; /* STOP_WAVES x nsurf indices */
} stop_probe;

#define STOP_WAVES 3
static void probe_stop(void *ctx, double r, int m, const double *u, const double *v,
                       unsigned char *pass)
{
    const stop_probe *p = ctx;
    for (int k = 0; k < m; k++)
        for (int w = 0; w < STOP_WAVES && !pass[k]; w++) {
            double in[4] = {r, 0, u[k], v[k]}, out[4];
            trace_result t = trace_sample(p->lens, p->n + (size_t)w * p->lens->nsurf, TRACE_TO_STOP,
                                          in, out);
            pass[k] = t.status == TRACE_PASSED;
        }
}

int render_sampler_stop(render_sampler *s, const lens_t *lens, double lambda_min,
                        double lambda_max, double rmax, lens_err *err)
{
    memset(s, 0, sizeof *s);
    size_t ns = lens->nsurf;
    double n[STOP_WAVES * ns];
    for (int w = 0; w < STOP_WAVES; w++)
        if (lens_indices(lens, lambda_min + (lambda_max - lambda_min) * w / (STOP_WAVES - 1),
                         n + w * ns, err))
            return -1;
    stop_probe p = {lens, n};
    const lens_surface *rear = &lens->surf[ns - 1];
    pupil_sampler_options po = {.lambda_min = lambda_min, .lambda_max = lambda_max,
                                .sensor_radius = rmax};
    s->kind = RENDER_SAMPLE_PUPIL;
    s->ps = pupil_sampler_build_probe(probe_stop, &p, rear->thickness, 1.5 * rear->semi_diameter,
                                      &po, err);
    return s->ps ? 0 : -1;
}

/* REAR: a uniform point q on the disk at distance h: (u, v) = (q - s0) / h, so
 * p(u, v) = p_A(q) h^2 */
static double sample_rear(const render_sampler *s, double x, double y, double r1, double r2,
                          double *u, double *v)
{
    double rad = s->rear_radius * sqrt(r1), phi = 2 * M_PI * r2, h = s->rear_dist;
    *u = (rad * cos(phi) - x) / h;
    *v = (rad * sin(phi) - y) / h;
    return h * h / (M_PI * s->rear_radius * s->rear_radius);
}

double render_sampler_sample(const render_sampler *s, double x, double y, double r1, double r2,
                             double *u, double *v)
{
    if (s->kind == RENDER_SAMPLE_REAR) return sample_rear(s, x, y, r1, r2, u, v);
    double rnd[2] = {r1, r2}, pdf;
    if (pupil_sampler_sample(s->ps, x, y, rnd, u, v, &pdf)) return 0;
    return pdf;
}

double render_sampler_sample_2d(const render_sampler *s, double x, double y, double r1,
                                double r2, double *u, double *v)
{
    if (s->kind == RENDER_SAMPLE_REAR) return sample_rear(s, x, y, r1, r2, u, v);
    double rnd[2] = {r1, r2}, pdf;
    if (pupil_sampler_sample_rows(s->ps, x, y, rnd, u, v, &pdf)) return 0;
    return pdf;
}
