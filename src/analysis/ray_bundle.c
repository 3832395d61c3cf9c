/* Bundles of object-space rays aimed once and imaged through each model (ray_bundle.h). */
#include "sparselens/ray_bundle.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sparselens/poly_solve.h"

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
 * solutions in s are on the file's plane here. */
static void retry_from_neighbours(const imaging *im, const ray_bundle *b, double *s, int *ok)
{
    size_t n = b->count;
    /* a sweep reads the rays solved before it and marks its own in fresh, so no ray is
     * read while another thread writes it */
    int *fresh = calloc(n ? n : 1, sizeof *fresh);
    if (!fresh)
        return;
    for (int gained = 1; gained;) {
        gained = 0;
#pragma omp parallel for schedule(dynamic, 16) reduction(| : gained) if (n > 512)
        for (size_t i = 0; i < n; i++) {
            if (ok[i] || !b->aimed[i])
                continue;
            size_t near[3] = {0, 0, 0};
            double d2[3] = {INFINITY, INFINITY, INFINITY};
            for (size_t j = 0; j < n; j++) {
                if (!ok[j])
                    continue;
                double dx = b->pupil[2 * j] - b->pupil[2 * i], dy = b->pupil[2 * j + 1] - b->pupil[2 * i + 1];
                double d = dx * dx + dy * dy;
                for (int k = 0; k < 3; k++)
                    if (d < d2[k]) {
                        for (int m = 2; m > k; m--)
                            d2[m] = d2[m - 1], near[m] = near[m - 1];
                        d2[k] = d, near[k] = j;
                        break;
                    }
            }
            for (int k = 0; k < 3 && isfinite(d2[k]) && !fresh[i]; k++)
                fresh[i] = system_image(im, b->lambda, &b->ray[i], s + 4 * near[k], s + 4 * i);
            gained |= fresh[i];
        }
        for (size_t i = 0; i < n; i++)
            ok[i] |= fresh[i];
    }
    free(fresh);
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
#pragma omp parallel for schedule(dynamic, 16) if (b->count > 512)
    for (size_t i = 0; i < b->count; i++)
        ok[i] = b->aimed[i] && system_image(im, b->lambda, &b->ray[i], first, s + 4 * i);
    retry_from_neighbours(im, b, s, ok);
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
