/* Passage surfaces and the hits on them (see trace_clip.h).
 *
 * Hits are taken from a trace with every rim extended: a fitted system must tell a ray
 * just inside a rim from one just outside it, so its training rays need the hit on both
 * sides, and a smooth function of the ray (a hit that turns nan at the rim is neither).
 * The clipped tracer decides passage by the same test (hit radius <= semi-diameter on
 * each surface), so "passes" is exactly "inside every rim, no miss, no TIR". */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/intersect.h"
#include "sparselens/refract.h"
#include "sparselens/trace.h"
#include "sparselens/trace_clip.h"

int trace_unclipped(const lens_t *lens, const double *n, const double in[4], int last,
                    double *hit, unsigned char *outside, double *eta)
{
    int ns = (int)lens->nsurf;
    for (int i = 0; i < ns; i++) {
        hit[2 * i] = hit[2 * i + 1] = NAN;
        if (outside)
            outside[i] = 0;
    }
    *eta = 0;
    lens_ray r;
    ray_from_sensor(lens, in, &r);
    if (!isfinite(r.o[0]) || !isfinite(r.o[1]) || !isfinite(r.d[0]) || !isfinite(r.d[1]))
        return ns - 1;
    double T = 1;
    for (int i = ns - 1; i >= last; i--) {
        const lens_surface *s = &lens->surf[i];
        double t, p[3], nrm[3];
        if (intersect_surface(s, lens->vertex_z[i], r.o, r.d, INFINITY, &t, p, nrm) != ISECT_HIT)
            return i;
        memcpy(r.o, p, sizeof p);
        hit[2 * i] = p[0];
        hit[2 * i + 1] = p[1];
        if (outside)
            outside[i] = p[0] * p[0] + p[1] * p[1] > s->semi_diameter * s->semi_diameter;
        /* towards the object: from the medium after surface i into the one before it */
        double n1 = n[i], n2 = i > 0 ? n[i - 1] : 1.0, Ti = 1;
        if (n1 != n2 && refract(r.d, nrm, n1, n2, r.d, &Ti))
            return i;
        T *= Ti;
    }
    *eta = T;
    return -1;
}

int trace_surface_hit(const lens_t *lens, int surf, const double *n, const double in[4],
                      double hit[2])
{
    double *h = malloc(lens->nsurf * 2 * sizeof *h), eta;
    if (!h) {
        hit[0] = hit[1] = NAN;
        return 0;
    }
    trace_unclipped(lens, n, in, surf, h, NULL, &eta);
    hit[0] = h[2 * surf];
    hit[1] = h[2 * surf + 1];
    free(h);
    return isfinite(hit[0]) && isfinite(hit[1]);
}

int trace_surfaces_batch(const lens_t *lens, int nsel, const int *surf, size_t count,
                         const double *in, double *hit, int threads, lens_err *err)
{
    int last = (int)lens->nsurf - 1, bad = 0, oom = 0;
    for (int k = 0; k < nsel; k++)
        last = surf[k] < last ? surf[k] : last;
    int nth = threads > 0 ? threads : omp_get_max_threads();
    double bad_lambda = NAN;
#pragma omp parallel num_threads(nth)
    {
        double *n = malloc(lens->nsurf * sizeof *n), *h = malloc(lens->nsurf * 2 * sizeof *h);
        double lam = NAN, eta;
        int lam_ok = 0;
        if (!n || !h) {
#pragma omp atomic write
            oom = 1;
        }
#pragma omp for schedule(static, 256)
        for (size_t i = 0; i < count; i++) {
            const double *row = in + 5 * i;
            double *out = hit + 2 * (size_t)nsel * i;
            for (int k = 0; k < 2 * nsel; k++)
                out[k] = NAN;
            if (!n || !h)
                continue;
            if (row[4] != lam) {
                lens_err e;
                lam = row[4];
                lam_ok = lens_indices(lens, lam, n, &e) == 0;
            }
            if (!lam_ok) {
#pragma omp critical(trace_clip_bad)
                if (!bad++)
                    bad_lambda = lam;
                continue;
            }
            trace_unclipped(lens, n, row, last, h, NULL, &eta);
            for (int k = 0; k < nsel; k++) {
                out[2 * k] = h[2 * surf[k]];
                out[2 * k + 1] = h[2 * surf[k] + 1];
            }
        }
        free(n);
        free(h);
    }
    if (oom) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    if (bad) {
        lens_errf(err, NULL, 0, "wavelength %g um is outside the range of a glass of the lens",
                  bad_lambda);
        return -1;
    }
    return 0;
}

/* The census of the pilot rays: per ray its weight (cos^4 theta times the Fresnel
 * transmittance: its share of the irradiance, the rays being uniform in u, v), whether
 * the lens passes it, and the surfaces that would block it (outside the rim, or where
 * the trace ends). */
typedef struct {
    size_t count, nsurf;
    double *w;
    unsigned char *pass, *blocks; /* count; count x nsurf */
} census;

static int take_census(const lens_t *lens, size_t count, const double *in, int threads,
                       census *c, lens_err *err)
{
    c->count = count;
    c->nsurf = lens->nsurf;
    c->w = malloc((count ? count : 1) * sizeof *c->w);
    c->pass = malloc(count ? count : 1);
    c->blocks = calloc((count ? count : 1) * lens->nsurf, 1);
    if (!c->w || !c->pass || !c->blocks) {
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
            if (end >= 0)
                b[end] = 1;
            for (size_t s = 0; pass && s < lens->nsurf; s++)
                pass = !b[s];
            c->pass[i] = (unsigned char)pass;
            c->w[i] = (end < 0 ? eta : 1) / (q * q);
        }
        if (!n || !h) {
#pragma omp atomic write
            bad = 2;
        }
        free(n);
        free(h);
    }
    if (bad) {
        lens_errf(err, NULL, 0, bad == 2 ? "out of memory" : "a pilot wavelength is outside "
                                                             "the range of a glass of the lens");
        return -1;
    }
    return 0;
}

static void census_free(census *c)
{
    free(c->w);
    free(c->pass);
    free(c->blocks);
}

/* Greedy cover: the modelled set starts with the stop (and the front); then, while
 * some surface would still block >= min_share of the light among the blocked rays no
 * chosen surface blocks (light a system without it lets through), the one that blocks
 * most is added. share[s]: for the stop and the front, the light they block; for a
 * chosen surface what it added; for the others what still leaks past the choice there. */
static int choose_cover(const census *c, const lens_t *lens, double min_share, int skip_front,
                        int max_surf, double *share, int *surf, double *leak)
{
    size_t ns = c->nsurf;
    unsigned char *chosen = calloc(ns, 1);
    double *gain = malloc(ns * sizeof *gain);
    if (!chosen || !gain) {
        free(chosen);
        free(gain);
        return -1;
    }
    double light = 0;
    for (size_t i = 0; i < c->count; i++)
        light += c->pass[i] ? c->w[i] : 0;
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
        for (size_t s = 0; s < ns; s++)
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
                gain[s] += b[s] ? c->w[i] : 0;
        }
        *leak = open / light;
        size_t best = ns;
        for (size_t s = 0; s < ns; s++)
            if (!chosen[s] && (best == ns || gain[s] > gain[best]))
                best = s;
        if (best == ns || gain[best] < min_share * light || k >= max_surf) {
            for (size_t s = 0; s < ns; s++)
                if (!chosen[s])
                    share[s] = gain[s] / light;
            break;
        }
        share[best] = gain[best] / light;
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

int trace_clip_pilot(const lens_t *lens, const sampling_options *so, size_t rays,
                     double min_share, int skip_front, int max_surf, double *share, int *surf,
                     double *leak, lens_err *err)
{
    double *in = malloc((rays ? rays : 1) * 5 * sizeof *in);
    if (!in) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    sampling_options full = *so;
    full.strategy = SAMPLING_FULL;
    ray_generator *g = ray_generator_new(lens, &full, err);
    census c = {0};
    int k = -1;
    if (g && ray_generator_fill(g, 0, rays, in, err) == 0 &&
        take_census(lens, rays, in, so->threads, &c, err) == 0) {
        k = choose_cover(&c, lens, min_share, skip_front, max_surf, share, surf, leak);
        if (k < 0)
            lens_errf(err, NULL, 0, "out of memory");
    }
    census_free(&c);
    if (g)
        ray_generator_free(g);
    free(in);
    return k;
}
