/* The pupil sampler built from a probe function (pupil_sampler_build_probe) and its
 * cache file (pupil_sampler_write / _read), on an analytic lens: a bare circular
 * aperture of radius R at distance h from the sensor. From the sensor point (x, y) the
 * passing directions are the disk |(x, y) + h (u, v)| <= R, of area pi R^2 / h^2 in
 * (u, v): the closed form the sampler's density must integrate to. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sparselens/pupil_sampler.h"

typedef struct {
    double h, R;
} aperture;

static int passes(const aperture *a, double x, double y, double u, double v)
{
    double px = x + a->h * u, py = y + a->h * v;
    return px * px + py * py <= a->R * a->R;
}

static void probe(void *ctx, double r, int m, const double *u, const double *v,
                  unsigned char *pass)
{
    for (int k = 0; k < m; k++) pass[k] = pass[k] || passes(ctx, r, 0, u[k], v[k]);
}

static double u01(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static pupil_sampler *build(aperture *a)
{
    pupil_sampler_options po = {.lambda_min = 0.55, .lambda_max = 0.55, .sensor_radius = 10,
                                .radii = 16, .grid = 48};
    lens_err err = {{0}};
    pupil_sampler *ps = pupil_sampler_build_probe(probe, a, a->h, a->R, &po, &err);
    if (!ps) print_error("%s\n", err.msg);
    assert_non_null(ps);
    return ps;
}

/* E[pass / pdf] is the area of the passing set: pi R^2 / h^2, within three standard
 * errors, at points on the axis, between tabulated radii and at the edge; and most
 * draws pass (the set is a disk, the grid hugs it). */
typedef int (*draw_fn)(const pupil_sampler *, double, double, const double[2], double *, double *,
                       double *);

static void probe_density(draw_fn draw)
{
    aperture a = {20, 6};
    pupil_sampler *ps = build(&a);
    double area = M_PI * a.R * a.R / (a.h * a.h);
    const double pts[][2] = {{0, 0}, {3.1, 0}, {-2.2, 4.7}, {0, -10}};
    uint64_t st = 1;
    for (size_t k = 0; k < sizeof pts / sizeof *pts; k++) {
        int n = 20000, passed = 0;
        double s = 0, s2 = 0;
        for (int i = 0; i < n; i++) {
            double rnd[2] = {u01(&st), u01(&st)}, u, v, pdf;
            assert_int_equal(draw(ps, pts[k][0], pts[k][1], rnd, &u, &v, &pdf), 0);
            assert_true(pdf > 0);
            /* the density query knows the drawn direction */
            assert_true(pupil_sampler_pdf(ps, pts[k][0], pts[k][1], u, v) > 0);
            double w = passes(&a, pts[k][0], pts[k][1], u, v) / pdf;
            passed += w > 0;
            s += w, s2 += w * w;
        }
        double mean = s / n, se = sqrt((s2 / n - mean * mean) / n);
        print_message("point %zu: area %.5f +- %.5f, closed form %.5f, %.1f%% pass\n", k, mean, se,
                      area, 100.0 * passed / n);
        assert_true(fabs(mean - area) < 3 * se + 1e-9);
        assert_true(passed > 0.8 * n);
    }
    pupil_sampler_free(ps);
}

static void test_probe_density(void **state)
{
    (void)state;
    probe_density(pupil_sampler_sample);
    probe_density(pupil_sampler_sample_rows); /* the same distribution by another map */
}

/* The share of the passing disk on the far side of the chord u > u_c, estimated with a
 * jittered 32 x 32 grid of (rnd[0], rnd[1]) through draw: RMS error over 20 grids. */
static double chord_rms(const pupil_sampler *ps, draw_fn draw)
{
    aperture a = {20, 6};
    double x = 3.1, y = 0, uc = (-x + 0.3 * a.R) / a.h; /* the disk's centre u is -x / h */
    double d = 0.3, share = (acos(d) - d * sqrt(1 - d * d)) / M_PI, se = 0;
    uint64_t st = 5;
    for (int rep = 0; rep < 20; rep++) {
        double sum = 0;
        for (int i = 0; i < 32; i++)
            for (int j = 0; j < 32; j++) {
                double rnd[2] = {(i + u01(&st)) / 32, (j + u01(&st)) / 32}, u, v, pdf;
                assert_int_equal(draw(ps, x, y, rnd, &u, &v, &pdf), 0);
                sum += passes(&a, x, y, u, v) * (u > uc) / pdf;
            }
        double e = sum / 1024 / (M_PI * a.R * a.R / (a.h * a.h)) - share;
        se += e * e;
    }
    return sqrt(se / 20);
}

/* Stratified numbers stay stratified over the pupil through pupil_sampler_sample_rows
 * (smooth in both numbers), not through the raster walk of pupil_sampler_sample: the
 * share of a chord's segment, far less error from the same grids. */
static void test_rows_keep_strata(void **state)
{
    (void)state;
    aperture a = {20, 6};
    pupil_sampler *ps = build(&a);
    double rows = chord_rms(ps, pupil_sampler_sample_rows), raster = chord_rms(ps, pupil_sampler_sample);
    print_message("segment share from 32 x 32 jittered grids, RMS error: rows %.2g, raster %.2g\n",
                  rows, raster);
    assert_true(rows < 0.3 * raster);
    pupil_sampler_free(ps);
}

/* Written and read back, the sampler draws the same directions with the same densities;
 * a truncated or foreign file is refused. */
static void test_cache_round_trip(void **state)
{
    (void)state;
    aperture a = {20, 6};
    pupil_sampler *ps = build(&a);
    FILE *f = tmpfile();
    assert_non_null(f);
    assert_int_equal(pupil_sampler_write(f, ps), 0);
    long size = ftell(f);
    rewind(f);
    lens_err err = {{0}};
    pupil_sampler *back = pupil_sampler_read(f, &err);
    assert_non_null(back);
    uint64_t st = 7;
    for (int i = 0; i < 2000; i++) {
        double x = 14 * u01(&st) - 7, y = 14 * u01(&st) - 7, rnd[2] = {u01(&st), u01(&st)};
        double u1, v1, p1, u2, v2, p2;
        int r1 = pupil_sampler_sample(ps, x, y, rnd, &u1, &v1, &p1);
        int r2 = pupil_sampler_sample(back, x, y, rnd, &u2, &v2, &p2);
        assert_int_equal(r1, r2);
        if (r1 == 0) {
            assert_true(u1 == u2 && v1 == v2 && p1 == p2);
        }
    }
    /* truncated */
    rewind(f);
    char *buf = malloc((size_t)size);
    assert_int_equal(fread(buf, 1, (size_t)size, f), (size_t)size);
    FILE *g = tmpfile();
    fwrite(buf, 1, (size_t)size / 2, g);
    rewind(g);
    assert_null(pupil_sampler_read(g, &err));
    fclose(g);
    /* foreign */
    g = tmpfile();
    fputs("lens-poly 1\n", g);
    rewind(g);
    assert_null(pupil_sampler_read(g, &err));
    assert_non_null(strstr(err.msg, "pupil sampler"));
    fclose(g);
    free(buf);
    fclose(f);
    pupil_sampler_free(back);
    pupil_sampler_free(ps);
}

static void test_probe_bad_arguments(void **state)
{
    (void)state;
    aperture a = {20, 6};
    pupil_sampler_options po = {.lambda_min = 0.55, .lambda_max = 0.55, .sensor_radius = 10};
    lens_err err = {{0}};
    assert_null(pupil_sampler_build_probe(probe, &a, 0, 6, &po, &err));
    assert_null(pupil_sampler_build_probe(NULL, &a, 20, 6, &po, &err));
    po.sensor_radius = -1;
    assert_null(pupil_sampler_build_probe(probe, &a, 20, 6, &po, &err));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_probe_density),
        cmocka_unit_test(test_rows_keep_strata),
        cmocka_unit_test(test_cache_round_trip),
        cmocka_unit_test(test_probe_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
