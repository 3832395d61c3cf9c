/* Tracing many sensor rays at once, OpenMP across rays.
 *
 * Each thread keeps a small direct-mapped cache of index tables keyed by wavelength, so
 * the glass formulas run once per distinct wavelength a thread meets, not per surface
 * and ray. Every row is traced by the same code whatever thread gets it, so the output
 * does not depend on the thread count. */
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/trace.h"
#include "sparselens/trace_packet.h"

enum { CACHE_SLOTS = 16 };

typedef struct {
    double lambda[CACHE_SLOTS];
    int ok[CACHE_SLOTS]; /* 1 valid, -1 out of range, 0 empty */
    double *n;           /* CACHE_SLOTS x nsurf */
} index_cache;

static unsigned slot_of(double lambda)
{
    uint64_t b;
    memcpy(&b, &lambda, sizeof b);
    b ^= b >> 29;
    b *= 0xbf58476d1ce4e5b9ULL;
    return (unsigned)(b >> 60) % CACHE_SLOTS;
}

/* The wavelengths every medium of the lens accepts. */
static void lens_lambda_range(const lens_t *lens, double *lo, double *hi)
{
    *lo = 0;
    *hi = INFINITY;
    for (size_t i = 0; i < lens->nsurf; i++) {
        const glass_t *g = &lens->surf[i].medium;
        *lo = fmax(*lo, g->lambda_min);
        *hi = fmin(*hi, g->lambda_max);
    }
}

/* Index table for lambda, or NULL when it is outside some glass's range. The range was
 * checked for the whole lens at once, so the per-glass formulas run unchecked (with
 * lens_indices' own checks as the fallback for anything odd). */
static const double *cached_indices(const lens_t *lens, index_cache *c, double lambda,
                                    double lo, double hi)
{
    unsigned k = slot_of(lambda);
    double *n = c->n + (size_t)k * lens->nsurf;
    if (c->ok[k] == 0 || c->lambda[k] != lambda) {
        int ok = lambda >= lo && lambda <= hi;
        for (size_t i = 0; ok && i < lens->nsurf; i++) {
            const glass_t *g = &lens->surf[i].medium;
            n[i] = g->kind == GLASS_AIR ? 1.0 : glass_index_unchecked(g, lambda);
            ok = n[i] >= 1.0 && isfinite(n[i]);
        }
        lens_err e;
        c->lambda[k] = lambda;
        c->ok[k] = ok || lens_indices(lens, lambda, n, &e) == 0 ? 1 : -1;
    }
    return c->ok[k] > 0 ? n : NULL;
}

int trace_batch(const lens_t *lens, trace_target target, size_t count, const double *in,
                double *out, trace_result *res, int threads, lens_err *err)
{
    if (count == 0)
        return 0;
    unsigned char *bad = calloc(count, 1);
    if (!bad) {
        lens_errf(err, NULL, 0, "out of memory for %zu rays", count);
        return -1;
    }
    int alloc_failed = 0;
    int nth = threads > 0 ? threads : omp_get_max_threads();
    const double zs = lens_total_track(lens);
    double lam_lo, lam_hi;
    lens_lambda_range(lens, &lam_lo, &lam_hi);
#pragma omp parallel num_threads(nth) reduction(| : alloc_failed)
    {
        index_cache cache;
        memset(&cache, 0, sizeof cache);
        cache.n = malloc(CACHE_SLOTS * lens->nsurf * sizeof *cache.n);
        if (!cache.n)
            alloc_failed = 1;
        double *lane_n = malloc(TRACE_LANES * lens->nsurf * sizeof *lane_n);
        if (!lane_n)
            alloc_failed = 1;
        size_t npk = (count + TRACE_LANES - 1) / TRACE_LANES;
#pragma omp for schedule(static, 32)
        for (size_t pk = 0; pk < npk; pk++) {
            size_t i0 = pk * TRACE_LANES;
            int m = count - i0 < TRACE_LANES ? (int)(count - i0) : TRACE_LANES;
            lens_ray rays[TRACE_LANES];
            trace_result rr[TRACE_LANES];
            const double *nl[TRACE_LANES];
            size_t rows[TRACE_LANES];
            int live = 0;
            for (int l = 0; l < m; l++) {
                size_t i = i0 + l;
                const double *row = in + 5 * i;
                const double *n = NULL;
                if (cache.n && lane_n && isfinite(row[4]))
                    n = cached_indices(lens, &cache, row[4], lam_lo, lam_hi);
                if (!n) {
                    double *o = out + 5 * i;
                    bad[i] = 1;
                    o[0] = o[1] = o[2] = o[3] = o[4] = NAN;
                    if (res)
                        res[i] = (trace_result){TRACE_INVALID, -1, 0.0};
                    continue;
                }
                /* a private copy: the cache slot may be reused by the next lane */
                double *mine = lane_n + (size_t)live * lens->nsurf;
                memcpy(mine, n, lens->nsurf * sizeof *mine);
                nl[live] = mine;
                /* ray_from_sensor, with the sensor plane's z computed once */
                double iu = 1.0 / sqrt(row[2] * row[2] + row[3] * row[3] + 1.0);
                lens_ray *ry = &rays[live];
                ry->o[0] = row[0], ry->o[1] = row[1], ry->o[2] = zs;
                ry->d[0] = row[2] * iu, ry->d[1] = row[3] * iu, ry->d[2] = -iu;
                rows[live++] = i;
            }
            if (!live)
                continue;
            double outer[4 * TRACE_LANES];
            int stop = target == TRACE_TO_STOP;
            trace_packet_to_object(lens, nl, live, rays, stop ? lens->stop : 0, rr,
                                   stop ? NULL : outer);
            for (int l = 0; l < live; l++) {
                double *o = out + 5 * rows[l];
                trace_result r = trace_sample_finish(lens, target, &rays[l],
                                                     stop ? NULL : outer + 4 * l, rr[l], o);
                o[4] = r.status == TRACE_PASSED ? r.transmittance : 0.0;
                if (res)
                    res[rows[l]] = r;
            }
        }
        free(lane_n);
        free(cache.n);
    }
    int rc = 0;
    if (alloc_failed) {
        lens_errf(err, NULL, 0, "out of memory for the index tables");
        rc = -1;
    } else {
        for (size_t i = 0; i < count; i++)
            if (bad[i]) {
                /* The first bad row, whatever the thread count: reproduce its message. */
                double *tmp = malloc(lens->nsurf * sizeof *tmp);
                lens_err e;
                if (tmp && isfinite(in[5 * i + 4]) && lens_indices(lens, in[5 * i + 4], tmp, &e))
                    lens_errf(err, NULL, 0, "ray %zu: %s", i + 1, e.msg);
                else
                    lens_errf(err, NULL, 0, "ray %zu: wavelength %g is not usable", i + 1,
                              in[5 * i + 4]);
                free(tmp);
                rc = -1;
                break;
            }
    }
    free(bad);
    return rc;
}
