/* Camera-ray direction samplers with known densities (render.h): the rear element's
 * disk, and the line pupil found by probing the lens.
 *
 * Why the line pupil is unbiased: it samples uniformly inside a box that holds every
 * direction that passes the lens at that sensor radius, so the estimator's support
 * (P_a = 1) lies inside the sampler's; directions in the box that do not pass score 0.
 * The box is found by probing a grid, so it is grown by two grid cells (and probed at
 * several radii per ring) to keep directions between probes inside it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render.h"

#define PROBE_GRID 64  /* directions per axis probed per radius */
#define PROBE_RADII 5  /* radii probed per ring */
#define PROBE_MARGIN 2 /* grid cells added around the passing directions */

void render_sampler_rear(render_sampler *s, const render_camera *cam)
{
    memset(s, 0, sizeof *s);
    s->kind = RENDER_SAMPLE_REAR;
    s->rear_dist = cam->rear_dist;
    s->rear_radius = cam->rear_radius;
}

void render_sampler_free(render_sampler *s)
{
    free(s->box);
    s->box = NULL;
}

/* Bounding box of the passing directions at sensor point (r, 0), within the probe
 * window [uc - w, uc + w] x [-w, w]; grows box (u0 u1 v1). */
static void probe(const render_camera *cam, double lambda, double r, double *box)
{
    double h = cam->rear_dist, R = cam->rear_radius;
    /* every passing ray crosses the rear element's plane within about its disk; the
     * window is that cone widened by half, since the rear surface is curved */
    double w = 1.5 * R / h, uc = -r / h;
    double cell = 2 * w / (PROBE_GRID - 1);
    for (int i = 0; i < PROBE_GRID; i++) {
        for (int j = 0; j < PROBE_GRID / 2; j++) { /* v >= 0: the set is symmetric in v */
            double u = uc - w + i * cell, v = j * cell;
            double in[5] = {r, 0, u, v, lambda}, o[3], d[3], eta;
            if (!cam->map(cam->ctx, in, o, d, &eta)) continue;
            box[0] = fmin(box[0], u - PROBE_MARGIN * cell);
            box[1] = fmax(box[1], u + PROBE_MARGIN * cell);
            box[2] = fmax(box[2], v + PROBE_MARGIN * cell);
        }
    }
}

int render_sampler_pupil(render_sampler *s, const render_camera *cam, double lambda,
                         double rmax, int nbins, lens_err *err)
{
    memset(s, 0, sizeof *s);
    if (nbins < 1 || !(rmax > 0) || !(cam->rear_dist > 0) || !(cam->rear_radius > 0)) {
        lens_errf(err, NULL, 0, "pupil sampler: bad rings (%d over %g mm) or rear element", nbins,
                  rmax);
        return -1;
    }
    s->kind = RENDER_SAMPLE_PUPIL;
    s->rear_dist = cam->rear_dist;
    s->rear_radius = cam->rear_radius;
    s->nbins = nbins;
    s->rmax = rmax;
    s->box = malloc(3 * (size_t)nbins * sizeof *s->box);
    if (!s->box) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    for (int b = 0; b < nbins; b++) {
        double *box = s->box + 3 * b;
        box[0] = INFINITY, box[1] = -INFINITY, box[2] = 0;
        for (int k = 0; k < PROBE_RADII; k++) {
            double r = rmax * (b + (double)k / (PROBE_RADII - 1)) / nbins;
            probe(cam, lambda, r, box);
        }
    }
    return 0;
}

double render_sampler_sample(const render_sampler *s, double x, double y, double r1, double r2,
                             double *u, double *v)
{
    if (s->kind == RENDER_SAMPLE_REAR) {
        /* uniform point q on the disk at distance h: (u, v) = (q - s0) / h, so
         * p(u, v) = p_A(q) h^2 */
        double rad = s->rear_radius * sqrt(r1), phi = 2 * M_PI * r2, h = s->rear_dist;
        *u = (rad * cos(phi) - x) / h;
        *v = (rad * sin(phi) - y) / h;
        return h * h / (M_PI * s->rear_radius * s->rear_radius);
    }
    double r = hypot(x, y);
    int b = (int)(r / s->rmax * s->nbins);
    if (b >= s->nbins) return 0; /* outside the probed sensor area */
    const double *box = s->box + 3 * b;
    if (!(box[1] > box[0]) || !(box[2] > 0)) return 0;
    double up = box[0] + r1 * (box[1] - box[0]), vp = box[2] * (2 * r2 - 1);
    /* turn from the frame of point (r, 0) to the point's azimuth; a rotation keeps du dv */
    double c = r > 0 ? x / r : 1, sn = r > 0 ? y / r : 0;
    *u = c * up - sn * vp;
    *v = sn * up + c * vp;
    return 1 / ((box[1] - box[0]) * 2 * box[2]);
}
