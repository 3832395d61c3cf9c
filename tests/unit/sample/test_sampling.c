/* Sample-ray generation: the counter-based RNG, the rear and pupil strategies. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "fixture_lenses.h"
#include "sparselens/rng.h"
#include "sparselens/sampling.h"
#include "sparselens/trace.h"

static int sanitized(void) { return getenv("SANITIZE") && *getenv("SANITIZE"); }

static void test_rng(void **state)
{
    (void)state;
    rng_t a = rng_stream(7, 123), b = rng_stream(7, 123), c = rng_stream(7, 124),
          d = rng_stream(8, 123);
    for (int i = 0; i < 100; i++) {
        uint64_t x = rng_u64(&a);
        assert_true(x == rng_u64(&b));
        assert_true(x != rng_u64(&c) || x != rng_u64(&d));
    }
    /* mean and variance of U(0,1): 1/2 and 1/12, to 5 standard errors */
    enum { N = 200000 };
    double s = 0, s2 = 0;
    for (int i = 0; i < N; i++) {
        rng_t r = rng_stream(1, (uint64_t)i); /* first number of many streams */
        double u = rng_uniform(&r);
        assert_true(u >= 0 && u < 1);
        s += u;
        s2 += u * u;
    }
    double mean = s / N, var = s2 / N - mean * mean;
    assert_true(fabs(mean - 0.5) < 5 * sqrt(1.0 / 12 / N));
    assert_true(fabs(var - 1.0 / 12) < 5 * sqrt(1.0 / 180 / N));
}

static sampling_options fisheye_opts(sampling_strategy st)
{
    sampling_options o = sampling_defaults();
    o.strategy = st;
    o.sensor_w = 23.6; /* APS-C, the format the Nikkor 10.5 mm fisheye covers */
    o.sensor_h = 15.7;
    if (sanitized())
        o.pupil_radii = 24, o.pupil_grid = 64;
    return o;
}

/* Ray i depends on (seed, i) only: 1 or 2 threads, whole or partial ranges. */
static void test_generator_deterministic(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    for (int st = 0; st < 2; st++) {
        sampling_options o = fisheye_opts(st ? SAMPLING_REAR : SAMPLING_PUPIL);
        enum { N = 3000 };
        static double a[N * 5], b[N * 5];
        lens_err e;
        o.threads = 1;
        ray_generator *g1 = ray_generator_new(&L, &o, &e);
        assert_non_null(g1);
        assert_int_equal(ray_generator_fill(g1, 0, N, a, &e), 0);
        o.threads = 2;
        ray_generator *g2 = ray_generator_new(&L, &o, &e);
        assert_non_null(g2);
        assert_int_equal(ray_generator_fill(g2, 0, N, b, &e), 0);
        assert_memory_equal(a, b, sizeof a);
        assert_int_equal(ray_generator_fill(g2, 1000, 500, b, &e), 0);
        assert_memory_equal(a + 5 * 1000, b, 500 * 5 * sizeof *b);
        for (int i = 0; i < N; i++) {
            assert_true(fabs(a[5 * i]) <= 11.8 && fabs(a[5 * i + 1]) <= 7.85);
            assert_true(a[5 * i + 4] >= 0.4 && a[5 * i + 4] <= 0.7);
        }
        ray_generator_free(g1);
        ray_generator_free(g2);
    }
    lens_free(&L);
}

/* The rear strategy aims at the rear vertex-plane disc and its pdf is 1 / that disc's
 * area in (u, v). */
static void test_rear(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_dgauss50(&L), 0);
    double D = lens_total_track(&L) - L.vertex_z[L.nsurf - 1], sd = L.surf[L.nsurf - 1].semi_diameter;
    rng_t r = rng_stream(3, 0);
    for (int i = 0; i < 1000; i++) {
        double x = 10 * rng_uniform(&r), y = -5 * rng_uniform(&r);
        double rnd[2] = {rng_uniform(&r), rng_uniform(&r)}, u, v, pdf;
        rear_sample(&L, x, y, rnd, &u, &v, &pdf);
        assert_true(hypot(x + u * D, y + v * D) <= sd * (1 + 1e-12));
        assert_true(fabs(pdf - 1 / (M_PI * sd * sd / (D * D))) < 1e-12 * pdf);
        assert_true(rear_pdf(&L, x, y, u, v) == pdf);
    }
    assert_true(rear_pdf(&L, 0, 0, 2 * sd / D, 0) == 0);
    lens_free(&L);
}

/* Pass fraction of the rays of generator g, traced to the outer pupil. */
static double pass_fraction(const lens_t *L, const ray_generator *g, size_t N, double *in,
                            double *out)
{
    lens_err e;
    assert_int_equal(ray_generator_fill(g, 0, N, in, &e), 0);
    assert_int_equal(trace_batch(L, TRACE_TO_OUTER, N, in, out, NULL, 0, &e), 0);
    size_t p = 0;
    for (size_t i = 0; i < N; i++)
        p += out[5 * i + 4] > 0;
    return (double)p / N;
}

/* The pupil strategy on fisheye-ii and the double Gauss: at least 90% of its rays pass,
 * and every passing ray of a dense rear-sampled set lies in its support. */
static void check_pupil(const lens_t *L, sampling_options o)
{
    size_t N = sanitized() ? 20000 : 60000;
    double *in = malloc(N * 5 * sizeof *in), *out = malloc(N * 5 * sizeof *out);
    lens_err e;
    ray_generator *g = ray_generator_new(L, &o, &e), *gr;
    assert_non_null(g);
    double pupil = pass_fraction(L, g, N, in, out);
    sampling_options rear = o;
    rear.strategy = SAMPLING_REAR;
    rear.seed = 12345;
    gr = ray_generator_new(L, &rear, &e);
    assert_non_null(gr);
    double rp = pass_fraction(L, gr, N, in, out);
    ray_generator_free(gr);
    assert_true(pupil >= 0.90);
    assert_true(pupil > rp);
    const pupil_sampler *ps = ray_generator_sampler(g);
    size_t passing = 0;
    for (size_t i = 0; i < N; i++) {
        const double *row = in + 5 * i;
        if (out[5 * i + 4] > 0) {
            passing++;
            assert_true(pupil_sampler_pdf(ps, row[0], row[1], row[2], row[3]) > 0);
        }
    }
    assert_true(passing > N / 4);
    ray_generator_free(g);
    free(in);
    free(out);
}

static void test_pupil_fisheye(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    check_pupil(&L, fisheye_opts(SAMPLING_PUPIL));
    lens_free(&L);
}

static void test_pupil_dgauss(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_dgauss50(&L), 0);
    sampling_options o = sampling_defaults();
    o.sensor_w = 36, o.sensor_h = 24;
    if (sanitized())
        o.pupil_radii = 24, o.pupil_grid = 64;
    check_pupil(&L, o);
    lens_free(&L);
}

/* The pdf: what sample() reports is what pdf() says there, it integrates to 1 over
 * (u, v), it is invariant under rotation about the axis, and it is 0 off the sensor. */
static void test_pupil_pdf(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    pupil_sampler_options po = {0.4, 0.7, 14.2, 24, 64, 0};
    lens_err e;
    pupil_sampler *ps = pupil_sampler_build(&L, &po, &e);
    assert_non_null(ps);
    rng_t r = rng_stream(5, 0);
    const double pts[][2] = {{0, 0}, {3, 4}, {-9, 2}, {0, -12}, {10, 9.5}};
    for (int k = 0; k < 5; k++) {
        double x = pts[k][0], y = pts[k][1];
        int agree = 0, n = 2000;
        double box[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
        for (int i = 0; i < n; i++) {
            double rnd[2] = {rng_uniform(&r), rng_uniform(&r)}, u, v, pdf;
            assert_int_equal(pupil_sampler_sample(ps, x, y, rnd, &u, &v, &pdf), 0);
            assert_true(pdf > 0);
            agree += pupil_sampler_pdf(ps, x, y, u, v) == pdf; /* cell edges may differ */
            box[0] = fmin(box[0], u), box[1] = fmax(box[1], u);
            box[2] = fmin(box[2], v), box[3] = fmax(box[3], v);
        }
        assert_true(agree > 0.99 * n);
        /* integral over the samples' bounding box grown by half its size (which holds
         * the whole support): Monte Carlo, uniform in the box */
        double wu = box[1] - box[0], wv = box[3] - box[2];
        box[0] -= 0.25 * wu, box[1] += 0.25 * wu, box[2] -= 0.25 * wv, box[3] += 0.25 * wv;
        double sum = 0;
        int m = sanitized() ? 50000 : 200000;
        for (int i = 0; i < m; i++) {
            double u = box[0] + (box[1] - box[0]) * rng_uniform(&r);
            double v = box[2] + (box[3] - box[2]) * rng_uniform(&r);
            sum += pupil_sampler_pdf(ps, x, y, u, v);
        }
        double integral = sum / m * (box[1] - box[0]) * (box[3] - box[2]);
        assert_true(fabs(integral - 1) < 0.02);
        /* rotation (off the axis: on it the grid itself is not rotation invariant) */
        if (k == 0)
            continue;
        double phi = 1.1, c = cos(phi), s = sin(phi);
        int same = 0;
        for (int i = 0; i < n; i++) {
            double rnd[2] = {rng_uniform(&r), rng_uniform(&r)}, u, v, pdf;
            pupil_sampler_sample(ps, x, y, rnd, &u, &v, &pdf);
            same += pupil_sampler_pdf(ps, c * x - s * y, s * x + c * y, c * u - s * v,
                                      s * u + c * v) == pdf;
        }
        assert_true(same > 0.99 * n);
    }
    double rnd[2] = {0.5, 0.5}, u, v, pdf;
    assert_int_equal(pupil_sampler_sample(ps, 20, 0, rnd, &u, &v, &pdf), -1);
    assert_true(pdf == 0 && isnan(u) && isnan(v));
    assert_true(pupil_sampler_pdf(ps, 20, 0, 0, 0) == 0);
    assert_true(pupil_sampler_pdf(ps, 0, 0, NAN, 0) == 0);
    pupil_sampler_free(ps);
    lens_free(&L);
}

/* Every shipped single-system lens (lenses/, loaded from its file): the pupil sampler's
 * rays pass at least 85% of the time (at the coarse resolution used here), its support
 * holds every passing rear-sampled ray, and no passing ray has a nan output. */
static void test_pupil_shipped_lenses(void **state)
{
    (void)state;
    const char *names[] = {"fisheye-aspherical", "fisheye", "wide", "wideangle-ii", "fisheye-iii",
                           "dgauss.50mm", "telephoto.250mm", "kreitzer-tele", "petzval",
                           "fisheye.10mm", "nikon-zoom", "brendel-tessar"};
    int nl = sanitized() ? 3 : (int)(sizeof names / sizeof names[0]), tested = 0;
    size_t N = sanitized() ? 4000 : 12000;
    double *in = malloc(N * 5 * sizeof *in), *out = malloc(N * 5 * sizeof *out);
    for (int k = 0; k < nl; k++) {
        char path[256];
        snprintf(path, sizeof path, "lenses/%s.lens", names[k]);
        lens_t L;
        lens_err e;
        if (lens_load(path, NULL, &L, &e))
            continue; /* not shipped (yet) */
        tested++;
        sampling_options o = sampling_defaults();
        o.pupil_radii = 24, o.pupil_grid = 64;
        ray_generator *g = ray_generator_new(&L, &o, &e);
        assert_non_null(g);
        double pass = pass_fraction(&L, g, N, in, out);
        for (size_t i = 0; i < N; i++)
            if (out[5 * i + 4] > 0)
                for (int c = 0; c < 4; c++)
                    assert_true(isfinite(out[5 * i + c]));
        if (pass < 0.85)
            fail_msg("%s: pupil pass fraction %.3f", names[k], pass);
        sampling_options r = o;
        r.strategy = SAMPLING_REAR;
        ray_generator *gr = ray_generator_new(&L, &r, &e);
        assert_non_null(gr);
        pass_fraction(&L, gr, N, in, out);
        ray_generator_free(gr);
        const pupil_sampler *ps = ray_generator_sampler(g);
        for (size_t i = 0; i < N; i++)
            if (out[5 * i + 4] > 0 &&
                !(pupil_sampler_pdf(ps, in[5 * i], in[5 * i + 1], in[5 * i + 2], in[5 * i + 3]) > 0))
                fail_msg("%s: passing ray %zu outside the pupil sampler's support", names[k], i);
        ray_generator_free(g);
        lens_free(&L);
    }
    free(in);
    free(out);
    if (!tested)
        skip();
}

static void test_bad_options(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    lens_err e;
    sampling_options o = fisheye_opts(SAMPLING_REAR);
    o.lambda_min = 0.2;
    assert_null(ray_generator_new(&L, &o, &e));
    assert_non_null(strstr(e.msg, "0.2"));
    o = fisheye_opts(SAMPLING_REAR);
    o.sensor_w = NAN; /* and the lens has no sensor size either */
    assert_null(ray_generator_new(&L, &o, &e));
    assert_non_null(strstr(e.msg, "sensor"));
    sampling_strategy s;
    assert_int_equal(sampling_strategy_parse("pupil", &s), 0);
    assert_int_equal(s, SAMPLING_PUPIL);
    assert_int_equal(sampling_strategy_parse("rear", &s), 0);
    assert_int_equal(s, SAMPLING_REAR);
    assert_int_equal(sampling_strategy_parse("Pupil", &s), -1);
    assert_string_equal(sampling_strategy_name(SAMPLING_REAR), "rear");
    pupil_sampler_options po = {0.4, 0.7, -1, 0, 0, 0};
    assert_null(pupil_sampler_build(&L, &po, &e));
    lens_free(&L);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rng),         cmocka_unit_test(test_generator_deterministic),
        cmocka_unit_test(test_rear),        cmocka_unit_test(test_pupil_fisheye),
        cmocka_unit_test(test_pupil_dgauss), cmocka_unit_test(test_pupil_pdf),
        cmocka_unit_test(test_pupil_shipped_lenses), cmocka_unit_test(test_bad_options),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
