/* Hard case of the renderer's estimator: the rim of the pupil, where the set of
 * directions that pass shrinks to nothing and the estimator's density (the Jacobian of
 * the map from uniforms to directions) goes to zero or blows up.
 *
 * Lens: lenses/fisheye-aspherical.lens (181 degrees) through the exact tracer, with the
 * line-pupil sampler. At sensor radii from the axis out to the corner of the lens's
 * sensor, where the pupil is a sliver, the expectations are:
 *  - every draw gives a finite density p >= 0, and a finite weight P T cos^4 / p for every
 *    direction that passes (p > 0 there, never a division by zero);
 *  - the estimator is unbiased at the rim: its mean agrees with the naive rear-element
 *    sampler's (independent density, rear_dist^2 / (pi rear_radius^2)) within 5 combined
 *    standard errors plus 2% of the value (the line pupil is built by probing a grid:
 *    a direction it misses would show as a bias), wherever the rear sampler sees any
 *    passing ray;
 *  - the same seed gives the same draws (no hidden state). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "sparselens/lens.h"
#include "sparselens/render.h"
#include "sparselens/render_lens.h"

static double u01(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

/* Mean and standard error of the weight at sensor point (x, 0). */
static void estimate(const render_camera *cam, const render_sampler *smp, double x, int n,
                     uint64_t seed, double *mean, double *se, int *bad)
{
    double s = 0, s2 = 0;
    uint64_t st = seed;
    for (int i = 0; i < n; i++) {
        double u, v, org[3], dir[3], eta = 0;
        double p = render_sampler_sample(smp, x, 0, u01(&st), u01(&st), &u, &v);
        double w = 0;
        if (!isfinite(p) || p < 0) {
            (*bad)++;
            continue;
        }
        if (p > 0) {
            double in[5] = {x, 0, u, v, 0.55};
            if (!isfinite(u) || !isfinite(v)) {
                (*bad)++;
                continue;
            }
            if (cam->map(cam->ctx, in, org, dir, &eta)) {
                w = render_ray_weight(u, v, p, eta);
                if (!isfinite(w) || w < 0)
                    (*bad)++;
            }
        }
        s += w;
        s2 += w * w;
    }
    *mean = s / n;
    *se = sqrt(fmax(0, s2 / n - *mean * *mean) / n);
}

static void test_pupil_rim(void **state)
{
    (void)state;
    lens_t L;
    lens_err err;
    if (lens_load("lenses/fisheye-aspherical.lens", NULL, &L, &err) != 0)
        fail_msg("%s", err.msg);
    render_camera cam;
    render_lens_ctx *ctx = render_lens_exact(&L, L.sensor_w, L.sensor_h, &cam, &err);
    assert_non_null(ctx);
    double rmax = hypot(L.sensor_w, L.sensor_h) / 2;
    render_sampler pupil, rear;
    assert_int_equal(render_sampler_pupil(&pupil, &cam, 0.55, rmax, 16, &err), 0);
    render_sampler_rear(&rear, &cam);
    int san = getenv("SANITIZE") && *getenv("SANITIZE");
    int n = san ? 2000 : 10000, bad = 0, compared = 0;
    double worst_rel = 0;
    const double frac[] = {0, 0.5, 0.9, 0.97, 0.995, 1.0};
    for (size_t k = 0; k < sizeof frac / sizeof *frac; k++) {
        double x = rmax * frac[k], mp, sp, mr, sr;
        estimate(&cam, &pupil, x, n, 11 + k, &mp, &sp, &bad);
        estimate(&cam, &rear, x, 4 * n, 101 + k, &mr, &sr, &bad);
        printf("hard-metric fisheye-aspherical pupil_rim_r%.3f pupil %.5g+-%.2g rear %.5g+-%.2g\n",
               frac[k], mp, sp, mr, sr);
        assert_true(isfinite(mp) && isfinite(mr));
        if (mr > 0) {
            double tol = 5 * hypot(sp, sr) + 0.02 * mr;
            assert_true(fabs(mp - mr) <= tol);
            worst_rel = fmax(worst_rel, fabs(mp - mr) / mr);
            compared++;
        }
    }
    assert_int_equal(bad, 0);
    assert_true(compared >= 4);
    printf("hard-metric fisheye-aspherical pupil_vs_rear_rel_diff %.3g\n", worst_rel);
    /* same seed, same numbers */
    double a, b, sa, sb;
    estimate(&cam, &pupil, rmax * 0.99, 1000, 5, &a, &sa, &bad);
    estimate(&cam, &pupil, rmax * 0.99, 1000, 5, &b, &sb, &bad);
    assert_memory_equal(&a, &b, sizeof a);
    render_sampler_free(&pupil);
    render_sampler_free(&rear);
    render_lens_free(ctx);
    lens_free(&L);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_pupil_rim)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
