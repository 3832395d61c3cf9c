/* Bundles of object-space rays aimed once and imaged through each model (ray_bundle.h). */
#include "sparselens/ray_bundle.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sparselens/poly_solve.h"

/* Newton steps of a retry from a solved neighbour (the first solve from the bundle's seed
 * takes poly_solve_sensor's 60). From a neighbour's solution a solve converges within a
 * few steps or not at all; rays outside the image of the system's domain (a third of an
 * off-axis bundle of fisheye-ii) had crawled through all 60 steps on each of their three
 * tries: lens-mtf through fisheye-ii's default fit 2.28 -> 1.92 s CPU with 16, the same
 * figures. (16 for the first solve too saved 0.1 s more but moved the on-axis MTF of a
 * dgauss.50mm system by up to 6.5e-4: rays near the axis, where a meridional system is
 * discontinuous, converge slowly from the bundle's seed.) */
#define RETRY_NEWTON_STEPS 16

double bundle_clock(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void bundle_free(ray_bundle *b)
{
    free(b->pupil);
    free(b->ray);
    free(b->aimed);
    free(b->n);
    memset(b, 0, sizeof *b);
}

int bundle_aim(const imaging *im, double field, double lambda, const double *pupil, size_t count,
               ray_bundle *b, lens_err *err)
{
    memset(b, 0, sizeof *b);
    const lens_t *lens = im->lens;
    b->field = field, b->lambda = lambda, b->count = count;
    b->pupil = malloc(sizeof(double) * 2 * (count ? count : 1));
    b->ray = malloc(sizeof(lens_ray) * (count ? count : 1));
    b->aimed = calloc(count ? count : 1, sizeof(int));
    b->n = malloc(sizeof(double) * lens->nsurf);
    if (!b->pupil || !b->ray || !b->aimed || !b->n) {
        bundle_free(b);
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    if (imaging_indices(im, lambda, b->n, err) != 0) {
        bundle_free(b);
        return -1;
    }
    memcpy(b->pupil, pupil, sizeof(double) * 2 * count);
    double stop = lens->surf[lens->stop].semi_diameter;
    aim_object_start start;
    int started = imaging_aim_prepare(im, b->n, field, &start) == 0;
#pragma omp parallel for schedule(dynamic, 16) if (count > 512)
    for (size_t i = 0; i < count; i++) {
        double px = pupil[2 * i], py = pupil[2 * i + 1], r = hypot(px, py);
        double k = r > 1 - 1e-9 ? (1 - 1e-9) / r : 1;
        b->aimed[i] = started && aim_object_to(&start, px * k * stop, py * k * stop, &b->ray[i]) == 0;
    }
    return 0;
}

/* One ray through a system without the exact trace: its outer-pupil coordinates, then
 * Newton from the seed. */
static int system_image(const imaging *im, double lambda, const lens_ray *r, const double *seed,
                        double s[4])
{
    double outer[4];
    int pass = 0;
    double eta;
    if (outer_of_object_ray(im->lens, r, outer) != 0 ||
        poly_solve_sensor(im->sys, lambda, outer, seed, s, &pass, &eta) != 0 || !pass)
        return 0;
    return 1;
}

/* Rays whose solve from the bundle's seed failed, tried again from the solutions of their
 * nearest solved neighbours in the stop (up to three, nearest first), sweeping until no
 * ray is gained. A meridional system's frame turns by pi across the axis, and Newton
 * from a seed a hair on the wrong side of it can stall where a seed nearby converges:
 * a ray the system images must not be dropped as vignetted for its seed's sake. The
 * solutions in s are on the file's plane here. Each round of a sweep (every failed
 * ray's k-th neighbour) is one batch solve (imaging_system_batch); one ray at a time it
 * had cost off-axis MTF bundles through fisheye-ii's system, where a third of the aimed
 * rays miss the system's domain, more than their first solve. */
static void retry_from_neighbours(const imaging *im, const ray_bundle *b, double *s, int *ok,
                                  const int *blocked)
{
    size_t n = b->count;
    size_t *near = malloc(sizeof(size_t) * 3 * (n ? n : 1));
    int *cnt = malloc(sizeof(int) * (n ? n : 1)), *use = malloc(sizeof(int) * (n ? n : 1));
    int *got = malloc(sizeof(int) * (n ? n : 1)), *fresh = malloc(sizeof(int) * (n ? n : 1));
    double *seeds = malloc(sizeof(double) * 4 * (n ? n : 1)), *sol = malloc(sizeof(double) * 4 * (n ? n : 1));
    if (!near || !cnt || !use || !got || !fresh || !seeds || !sol)
        goto out;
    for (int gained = 1; gained;) {
        gained = 0;
        /* the neighbours among the rays solved before this sweep */
#pragma omp parallel for schedule(dynamic, 16) if (n > 512)
        for (size_t i = 0; i < n; i++) {
            cnt[i] = 0;
            fresh[i] = 0;
            if (ok[i] || !b->aimed[i] || (blocked && blocked[i]))
                continue;
            double d2[3] = {INFINITY, INFINITY, INFINITY};
            size_t *nr = near + 3 * i;
            for (size_t j = 0; j < n; j++) {
                if (!ok[j])
                    continue;
                double dx = b->pupil[2 * j] - b->pupil[2 * i], dy = b->pupil[2 * j + 1] - b->pupil[2 * i + 1];
                double d = dx * dx + dy * dy;
                for (int k = 0; k < 3; k++)
                    if (d < d2[k]) {
                        for (int m = 2; m > k; m--)
                            d2[m] = d2[m - 1], nr[m] = nr[m - 1];
                        d2[k] = d, nr[k] = j;
                        break;
                    }
            }
            for (int k = 0; k < 3 && isfinite(d2[k]); k++)
                cnt[i] = k + 1;
        }
        for (int k = 0; k < 3; k++) {
            size_t m = 0;
            for (size_t i = 0; i < n; i++) {
                use[i] = cnt[i] > k && !fresh[i];
                if (use[i]) {
                    memcpy(seeds + 4 * i, s + 4 * near[3 * i + k], sizeof(double) * 4);
                    m++;
                }
            }
            if (m == 0 ||
                imaging_system_batch(im, b->lambda, n, b->ray, use, seeds, 4, RETRY_NEWTON_STEPS, sol, NULL, got, NULL) != 0)
                break;
            for (size_t i = 0; i < n; i++)
                if (use[i] && got[i]) {
                    fresh[i] = 1;
                    memcpy(s + 4 * i, sol + 4 * i, sizeof(double) * 4);
                }
        }
        for (size_t i = 0; i < n; i++)
            if (fresh[i] && !ok[i])
                ok[i] = 1, gained = 1;
    }
out:
    free(near);
    free(cnt);
    free(use);
    free(got);
    free(fresh);
    free(seeds);
    free(sol);
}

double bundle_image(const imaging *im, const ray_bundle *b, const double *seed, double *s, int *ok)
{
    double t0 = bundle_clock();
    if (!im->sys) {
#pragma omp parallel for schedule(dynamic, 16) if (b->count > 512)
        for (size_t i = 0; i < b->count; i++) {
            double eta;
            ok[i] = b->aimed[i] && imaging_trace(im, b->n, b->lambda, &b->ray[i], NULL, s + 4 * i, &eta);
        }
        return bundle_clock() - t0;
    }
    /* The system's sensor rays are solved on the file's plane and shifted after, as
     * imaging_trace does. */
    double dz = im->sensor_shift;
    double first[4] = {0, 0, 0, 0};
    if (seed) {
        memcpy(first, seed, sizeof first);
        first[0] += dz * first[2], first[1] += dz * first[3];
    }
    /* all at once (the batch solve); one ray at a time, as before, if memory runs out.
     * A ray the system was solved for and blocks is vignetted, not retried: the retries
     * are for solves that failed, and tried every vignetted ray from three neighbours
     * (most of lens-mtf's time through fisheye-ii's system went there). */
    int *blocked = malloc(sizeof(int) * (b->count ? b->count : 1));
    if (!blocked ||
        imaging_system_batch(im, b->lambda, b->count, b->ray, b->aimed, first, 0, 0, s, NULL, ok,
                             blocked) != 0) {
        free(blocked);
        blocked = NULL;
#pragma omp parallel for schedule(dynamic, 16) if (b->count > 512)
        for (size_t i = 0; i < b->count; i++)
            ok[i] = b->aimed[i] && system_image(im, b->lambda, &b->ray[i], first, s + 4 * i);
    }
    retry_from_neighbours(im, b, s, ok, blocked);
    free(blocked);
    for (size_t i = 0; i < b->count; i++)
        if (ok[i]) {
            s[4 * i] -= dz * s[4 * i + 2];
            s[4 * i + 1] -= dz * s[4 * i + 3];
        }
    return bundle_clock() - t0;
}

int bundle_chief(const imaging *im, double field, double lambda, double s[4], lens_err *err)
{
    double *n = malloc(sizeof(double) * im->lens->nsurf);
    if (!n) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    int rc = imaging_indices(im, lambda, n, err) != 0 ? -1 : imaging_chief(im, n, lambda, field, s, err) != 0;
    free(n);
    return rc;
}
