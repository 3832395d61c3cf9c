/* Camera-ray direction samplers with known densities (render.h): the rear element's
 * disk, and the line pupil found by probing the lens.
 *
 * Why the line pupil is unbiased: it samples uniformly over grid cells that together
 * hold every direction that passes the lens at that sensor radius, so the estimator's
 * support (P_a = 1) lies inside the sampler's; directions in those cells that do not
 * pass score 0. The cells are found by probing their centres at several radii per ring,
 * then grown by one cell on every side, so that the edge of the passing set, which
 * moves with the radius and lies between probes, stays inside. By rotational symmetry
 * the set at (x, y) is the set at (r, 0) turned by the point's azimuth, and it is
 * symmetric in v. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render.h"

#define COARSE_GRID 16 /* cells per side of the first, wide probe of a ring */
#define PROBE_GRID 64  /* cells per side of a ring's (u, v) window */
#define PROBE_RADII 3  /* radii probed per ring: its ends and middle */

void render_sampler_rear(render_sampler *s, const render_camera *cam)
{
    memset(s, 0, sizeof *s);
    s->kind = RENDER_SAMPLE_REAR;
    s->rear_dist = cam->rear_dist;
    s->rear_radius = cam->rear_radius;
}

void render_sampler_free(render_sampler *s)
{
    free(s->win);
    free(s->start);
    free(s->cells);
    s->win = NULL;
    s->start = s->cells = NULL;
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
    const int G = PROBE_GRID;
    s->kind = RENDER_SAMPLE_PUPIL;
    s->rear_dist = cam->rear_dist;
    s->rear_radius = cam->rear_radius;
    s->nbins = nbins;
    s->rmax = rmax;
    s->grid = G;
    s->win = malloc(4 * (size_t)nbins * sizeof *s->win);
    s->start = malloc(((size_t)nbins + 1) * sizeof *s->start);
    s->cells = malloc((size_t)nbins * G * G * sizeof *s->cells);
    unsigned char *hit = malloc((size_t)G * G), *grown = malloc((size_t)G * G);
    if (!s->win || !s->start || !s->cells || !hit || !grown) {
        free(hit);
        free(grown);
        render_sampler_free(s);
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    double h = cam->rear_dist;
    /* every passing ray crosses the rear element's vertex plane within about its disk;
     * the wide window is that cone widened by half, since the rear surface is curved */
    double w = 1.5 * cam->rear_radius / h;
    int total = 0;
    for (int b = 0; b < nbins; b++) {
        double rlo = rmax * b / nbins, rhi = rmax * (b + 1) / nbins;
        /* coarse: where in the wide window do rays pass at all? */
        double cu0 = -rhi / h - w, cdu = (-rlo / h + w - cu0) / COARSE_GRID,
               cdv = 2 * w / COARSE_GRID;
        double lo_u = INFINITY, hi_u = -INFINITY, hi_v = 0;
        for (int k = 0; k < PROBE_RADII; k++) {
            double r = rlo + (rhi - rlo) * k / (PROBE_RADII - 1);
            for (int i = 0; i <= COARSE_GRID; i++)
                for (int j = 0; j <= COARSE_GRID / 2; j++) {
                    double u = cu0 + i * cdu, v = j * cdv;
                    double in[5] = {r, 0, u, v, lambda}, o[3], d[3], eta;
                    if (!cam->map(cam->ctx, in, o, d, &eta)) continue;
                    lo_u = fmin(lo_u, u), hi_u = fmax(hi_u, u), hi_v = fmax(hi_v, v);
                }
        }
        double *win = s->win + 4 * b;
        if (!(hi_u >= lo_u)) { /* nothing passes in this ring */
            win[0] = win[1] = 0, win[2] = win[3] = 1;
            s->start[b] = total;
            continue;
        }
        /* fine: the window of the passing directions, one coarse cell wider all round */
        double u0 = lo_u - cdu, u1 = hi_u + cdu, v1 = hi_v + cdv;
        win[0] = u0, win[1] = -v1, win[2] = (u1 - u0) / G, win[3] = 2 * v1 / G;
        memset(hit, 0, (size_t)G * G);
        for (int k = 0; k < PROBE_RADII; k++) {
            double r = rlo + (rhi - rlo) * k / (PROBE_RADII - 1);
            for (int i = 0; i < G; i++)
                for (int j = G / 2; j < G; j++) { /* v >= 0; mirrored below */
                    if (hit[i * G + j]) continue;
                    double u = u0 + (i + 0.5) * win[2], v = win[1] + (j + 0.5) * win[3];
                    double in[5] = {r, 0, u, v, lambda}, o[3], d[3], eta;
                    if (cam->map(cam->ctx, in, o, d, &eta)) hit[i * G + j] = hit[i * G + G - 1 - j] = 1;
                }
        }
        memset(grown, 0, (size_t)G * G);
        for (int i = 0; i < G; i++)
            for (int j = 0; j < G; j++) {
                if (!hit[i * G + j]) continue;
                for (int di = -1; di <= 1; di++)
                    for (int dj = -1; dj <= 1; dj++) {
                        int a = i + di, c = j + dj;
                        if (a >= 0 && a < G && c >= 0 && c < G) grown[a * G + c] = 1;
                    }
            }
        s->start[b] = total;
        for (int c = 0; c < G * G; c++)
            if (grown[c]) s->cells[total++] = c;
    }
    s->start[nbins] = total;
    free(hit);
    free(grown);
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
    if (b >= s->nbins && !(r <= s->rmax)) return 0; /* outside the probed sensor area */
    if (b >= s->nbins) b = s->nbins - 1; /* r == rmax: the outer edge of the last ring */
    int n = s->start[b + 1] - s->start[b];
    if (n == 0) return 0;
    /* r1 picks the cell and, rescaled, the position across it */
    double f = r1 * n;
    int k = (int)f;
    if (k >= n) k = n - 1;
    double fu = f - k;
    int c = s->cells[s->start[b] + k];
    const double *win = s->win + 4 * b;
    double up = win[0] + (c / s->grid + fu) * win[2], vp = win[1] + (c % s->grid + r2) * win[3];
    /* turn from the frame of point (r, 0) to the point's azimuth; a rotation keeps du dv */
    double cs = r > 0 ? x / r : 1, sn = r > 0 ? y / r : 0;
    *u = cs * up - sn * vp;
    *v = sn * up + cs * vp;
    return 1 / (n * win[2] * win[3]);
}
