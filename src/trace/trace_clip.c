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
    lens_err bad_err; /* the first bad wavelength's reason: the glass and its range */
    bad_err.msg[0] = '\0';
#pragma omp parallel num_threads(nth)
    {
        lens_err e;
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
                lam = row[4];
                lam_ok = lens_indices(lens, lam, n, &e) == 0;
            }
            if (!lam_ok) {
#pragma omp critical(trace_clip_bad)
                if (!bad++)
                    bad_err = e;
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
        *err = bad_err;
        return -1;
    }
    return 0;
}
