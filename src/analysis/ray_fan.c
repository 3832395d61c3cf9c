/* Ray fans (ray_fan.h): two bundles of npts rays across the stop, read on the sensor. */
#include "sparselens/ray_fan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/ray_bundle.h"

void ray_fan_free(ray_fan *fan)
{
    free(fan->pupil);
    free(fan->ex);
    free(fan->ey);
    memset(fan, 0, sizeof *fan);
}

/* The fan's arrays, its pupil coordinates, every error nan. */
static int fan_alloc(ray_fan *fan, int npts, lens_err *err)
{
    memset(fan, 0, sizeof *fan);
    size_t n = (size_t)npts;
    fan->npts = npts;
    fan->pupil = malloc(sizeof(double) * n);
    fan->ex = malloc(sizeof(double) * 2 * n);
    fan->ey = malloc(sizeof(double) * 2 * n);
    if (npts < 2 || !fan->pupil || !fan->ex || !fan->ey) {
        lens_errf(err, NULL, 0, npts < 2 ? "a fan needs at least 2 points" : "out of memory");
        ray_fan_free(fan);
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        fan->pupil[i] = -1 + 2.0 * (double)i / (double)(n - 1);
    for (size_t i = 0; i < 2 * n; i++)
        fan->ex[i] = fan->ey[i] = NAN;
    return 0;
}

int ray_fan_not_imaged(int npts, ray_fan *fan, lens_err *err)
{
    return fan_alloc(fan, npts, err);
}

int ray_fan_trace(const imaging *im, double field, double lambda, const double ref[2],
                  const double seed[4], int npts, ray_fan *fan, lens_err *err)
{
    if (fan_alloc(fan, npts, err) != 0)
        return -1;
    size_t n = (size_t)npts;
    double *xy = malloc(sizeof(double) * 4 * n), *s = malloc(sizeof(double) * 8 * n);
    int *ok = malloc(sizeof(int) * 2 * n);
    int rc = -1;
    if (!xy || !s || !ok) {
        lens_errf(err, NULL, 0, "out of memory");
        goto out;
    }
    for (size_t i = 0; i < n; i++) {
        double p = fan->pupil[i];
        xy[2 * i] = 0, xy[2 * i + 1] = p;             /* tangential */
        xy[2 * (n + i)] = p, xy[2 * (n + i) + 1] = 0; /* sagittal */
    }
    ray_bundle b;
    if (bundle_aim(im, field, lambda, xy, 2 * n, &b, err) != 0)
        goto out;
    fan->seconds = bundle_image(im, &b, seed, s, ok);
    bundle_free(&b);
    for (size_t i = 0; i < 2 * n; i++) {
        fan->ex[i] = ok[i] ? s[4 * i] - ref[0] : NAN;
        fan->ey[i] = ok[i] ? s[4 * i + 1] - ref[1] : NAN;
    }
    rc = 0;
out:
    free(xy);
    free(s);
    free(ok);
    if (rc != 0)
        ray_fan_free(fan);
    return rc;
}
