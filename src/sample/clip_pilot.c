/* The pilot trace that picks the surfaces a system models for its passage (see
 * clip_pilot.h): rays over the whole ray space, their census (weight, pass, the surfaces
 * that block each), and a greedy cover. The hits themselves are trace_clip.c's. */
#include "sparselens/clip_pilot.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/rng.h"
#include "sparselens/trace.h"
#include "sparselens/trace_clip.h"

/* The census of the pilot rays: per ray its weight (cos^4 theta times the Fresnel
 * transmittance: its share of the irradiance, the rays being uniform in u, v), whether
 * the lens passes it, and the surfaces that would block it (outside the rim, or where
 * the trace ends). */
typedef struct {
    size_t count, nsurf;
    double *w;
    unsigned char *pass, *blocks; /* count; count x nsurf */
    unsigned char *zone;          /* count: the ring of sensor radius (ZONES rings) */
} census;

/* A surface that limits the beam only near the axis, say, blocks little of all the
 * light but much of some ring's: the cover also looks at ZONES rings of equal width in
 * sensor radius, holding a surface to ZONE_FACTOR times min_share of the ring's light
 * (rings with fewer than ZONE_MIN_RAYS passing rays are too noisy to judge). */
#define ZONES 16
#define ZONE_FACTOR 4
#define ZONE_MIN_RAYS 200

static int take_census(const lens_t *lens, size_t count, const double *in, const double *rw,
                       int threads, census *c, lens_err *err)
{
    c->count = count;
    c->nsurf = lens->nsurf;
    c->w = malloc((count ? count : 1) * sizeof *c->w);
    c->pass = malloc(count ? count : 1);
    c->blocks = calloc((count ? count : 1) * lens->nsurf, 1);
    c->zone = malloc(count ? count : 1);
    if (!c->w || !c->pass || !c->blocks || !c->zone) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    int nth = threads > 0 ? threads : omp_get_max_threads(), bad = 0;
#pragma omp parallel num_threads(nth)
    {
        double *n = malloc(lens->nsurf * sizeof *n), *h = malloc(lens->nsurf * 2 * sizeof *h);
        double lam = NAN;
        int lam_ok = 0;
#pragma omp for schedule(static, 256)
        for (size_t i = 0; i < count; i++) {
            const double *row = in + 5 * i;
            unsigned char *b = c->blocks + i * lens->nsurf;
            c->w[i] = 0;
            c->pass[i] = 0;
            if (!n || !h)
                continue;
            if (row[4] != lam) {
                lens_err e;
                lam = row[4];
                lam_ok = lens_indices(lens, lam, n, &e) == 0;
            }
            if (!lam_ok) {
#pragma omp atomic write
                bad = 1;
                continue;
            }
            double eta, q = 1 + row[2] * row[2] + row[3] * row[3];
            int end = trace_unclipped(lens, n, row, 0, h, b, &eta);
            int pass = end < 0;
            /* Total reflection at a surface: that surface's hit exists, its circle stands
             * in. A miss: the ray left the surface it came from (nearer the sensor) where
             * the next one does not reach, as where an element's two surfaces cross
             * inside their semi-diameters (fisheye-ii's 15-16): a circle on that one,
             * of the passing rays' furthest radius, blocks it. */
            if (end >= 0)
                b[isfinite(h[2 * end]) || end + 1 == (int)lens->nsurf ? end : end + 1] = 1;
            for (size_t s = 0; pass && s < lens->nsurf; s++)
                pass = !b[s];
            c->pass[i] = (unsigned char)pass;
            c->w[i] = (end < 0 ? eta : 1) / (q * q) * rw[i];

        }
        if (!n || !h) {
#pragma omp atomic write
            bad = 2;
        }
        free(n);
        free(h);
    }
    if (bad == 1) {
        /* Name the wavelength, the glass and its range (lens_indices says them). */
        double *n = malloc(lens->nsurf * sizeof *n);
        lens_err e = {""};
        for (size_t i = 0; n && i < count && !e.msg[0]; i++)
            if (lens_indices(lens, in[5 * i + 4], n, &e) != 0)
                lens_errf(err, NULL, 0, "pilot rays of the lens: %s", e.msg);
        free(n);
        if (!e.msg[0])
            lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    if (bad) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    /* rings up to the furthest sensor point the lens lights */
    double rmax = 1e-300;
    for (size_t i = 0; i < count; i++)
        if (c->pass[i])
            rmax = fmax(rmax, hypot(in[5 * i], in[5 * i + 1]));
    for (size_t i = 0; i < count; i++)
        c->zone[i] = (unsigned char)fmin(ZONES - 1, floor(ZONES * hypot(in[5 * i], in[5 * i + 1]) / rmax));
    return 0;
}

static void census_free(census *c)
{
    free(c->w);
    free(c->pass);
    free(c->blocks);
    free(c->zone);
}

/* Greedy cover: the modelled set starts with the stop (and the front); then, while
 * some surface would still block >= min_share of the light among the blocked rays no
 * chosen surface blocks (light a system without it lets through), or ZONE_FACTOR times
 * that of some ring's light, the one that blocks most (as a share, the ring's scaled
 * down by ZONE_FACTOR) is added. share[s]: for the stop and the front, the light they
 * block; for a chosen surface what it added; for the others what still leaks past the
 * choice there (shares of all the light). */
static int choose_cover(const census *c, const lens_t *lens, double min_share, int skip_front,
                        int max_surf, double *share, int *surf, double *leak)
{
    size_t ns = c->nsurf;
    unsigned char *chosen = calloc(ns, 1);
    double *gain = malloc(ns * (ZONES + 1) * sizeof *gain);
    if (!chosen || !gain) {
        free(chosen);
        free(gain);
        return -1;
    }
    double light = 0, zlight[ZONES] = {0};
    size_t zrays[ZONES] = {0};
    for (size_t i = 0; i < c->count; i++)
        if (c->pass[i]) {
            light += c->w[i];
            zlight[c->zone[i]] += c->w[i];
            zrays[c->zone[i]]++;
        }
    if (!(light > 0))
        light = 1;
    for (size_t s = 0; s < ns; s++)
        share[s] = 0;
    for (size_t i = 0; i < c->count; i++)
        for (size_t s = 0; !c->pass[i] && s < ns; s++)
            share[s] += c->blocks[i * ns + s] ? c->w[i] / light : 0;
    chosen[lens->stop] = 1;
    if (skip_front)
        chosen[0] = 1;
    int k = 0;
    for (;;) {
        for (size_t s = 0; s < ns * (ZONES + 1); s++)
            gain[s] = 0;
        double open = 0;
        for (size_t i = 0; i < c->count; i++) {
            const unsigned char *b = c->blocks + i * ns;
            int covered = c->pass[i];
            for (size_t s = 0; s < ns && !covered; s++)
                covered = b[s] && chosen[s];
            if (covered)
                continue;
            open += c->w[i];
            for (size_t s = 0; s < ns; s++)
                if (b[s]) {
                    gain[s * (ZONES + 1)] += c->w[i];
                    gain[s * (ZONES + 1) + 1 + c->zone[i]] += c->w[i];
                }
        }
        *leak = open / light;
        size_t best = ns;
        double best_score = 0;
        for (size_t s = 0; s < ns; s++) {
            if (chosen[s])
                continue;
            double score = gain[s * (ZONES + 1)] / light;
            for (int z = 0; z < ZONES; z++)
                if (zrays[z] >= ZONE_MIN_RAYS)
                    score = fmax(score, gain[s * (ZONES + 1) + 1 + z] / zlight[z] / ZONE_FACTOR);
            if (best == ns || score > best_score)
                best = s, best_score = score;
        }
        if (best == ns || best_score < min_share || k >= max_surf) {
            for (size_t s = 0; s < ns; s++)
                if (!chosen[s])
                    share[s] = gain[s * (ZONES + 1)] / light;
            break;
        }
        share[best] = gain[best * (ZONES + 1)] / light;
        chosen[best] = 1;
        surf[k++] = (int)best;
    }
    /* increasing surface order, as the columns are written */
    for (int a = 1; a < k; a++)
        for (int b = a; b > 0 && surf[b] < surf[b - 1]; b--) {
            int t = surf[b];
            surf[b] = surf[b - 1];
            surf[b - 1] = t;
        }
    free(chosen);
    free(gain);
    return k;
}

/* The pilot's rays: sensor points uniform in radius (up to the half diagonal) and in
 * azimuth, kept inside the sensor, so that every ring of the cover holds as many rays
 * as the next and the axis is seen as well as the edge; rw gets each ray's weight, its
 * radius, which makes the points stand for a uniform density over the sensor. The
 * directions are the full strategy's (sampling.h), ray i from the stream (seed, i). */
static int pilot_rays(const lens_t *lens, const sampling_options *so, size_t rays, double *in,
                      double *rw, lens_err *err)
{
    double w = isnan(so->sensor_w) ? lens->sensor_w : so->sensor_w;
    double h = isnan(so->sensor_h) ? lens->sensor_h : so->sensor_h;
    if (!(w > 0 && h > 0 && isfinite(w) && isfinite(h))) {
        lens_errf(err, lens->path[0] ? lens->path : NULL, 0,
                  "no sensor size (give one, or a '# sensor: WxH' header)");
        return -1;
    }
    double R = 0.5 * hypot(w, h), disc = full_disc_radius(lens, R);
    for (size_t i = 0; i < rays; i++) {
        rng_t g = rng_stream(so->seed, i);
        double x = 0, y = 0, r = 0, pdf;
        for (int tries = 0; tries < 64; tries++) {
            double a = 2 * M_PI * rng_uniform(&g);
            r = R * rng_uniform(&g);
            x = r * cos(a), y = r * sin(a);
            if (fabs(x) <= 0.5 * w && fabs(y) <= 0.5 * h)
                break;
        }
        double rnd[2] = {rng_uniform(&g), rng_uniform(&g)}, *row = in + 5 * i;
        full_sample(lens, disc, x, y, rnd, &row[2], &row[3], &pdf);
        row[0] = x, row[1] = y;
        row[4] = so->lambda_min + rng_uniform(&g) * (so->lambda_max - so->lambda_min);
        rw[i] = r;
    }
    return 0;
}

int trace_clip_pilot(const lens_t *lens, const sampling_options *so, size_t rays,
                     double min_share, int skip_front, int max_surf, double *share, int *surf,
                     double *leak, lens_err *err)
{
    double *in = malloc((rays ? rays : 1) * 5 * sizeof *in);
    double *rw = malloc((rays ? rays : 1) * sizeof *rw);
    census c = {0};
    int k = -1;
    if (!in || !rw)
        lens_errf(err, NULL, 0, "out of memory");
    else if (pilot_rays(lens, so, rays, in, rw, err) == 0 &&
             take_census(lens, rays, in, rw, so->threads, &c, err) == 0) {
        k = choose_cover(&c, lens, min_share, skip_front, max_surf, share, surf, leak);
        if (k < 0)
            lens_errf(err, NULL, 0, "out of memory");
    }
    census_free(&c);
    free(in);
    free(rw);
    return k;
}
