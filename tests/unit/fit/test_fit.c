/* fit_system end to end: planted sparse polynomials in raw units (input scales 1e4
 * apart), fewer samples than candidates, ill-conditioned clustered samples at degree 13,
 * degenerate input, blocked rays, determinism across thread counts. */
#define _GNU_SOURCE
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sparselens/fit.h"
#include "sparselens/poly.h"

static double urand(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

static const char *IN4[] = {"x", "y", "u", "v"};
static const char *OUT2[] = {"out_x", "out_y"};

/* out_x and out_y of a planted "lens": odd in (x, u), even in (y, v) and the mirror,
 * with x, y in mm (+-100) and u, v in radians (+-0.01): scales 1e4 apart. Terms are
 * given in raw units; ranges are symmetric, so the fit's scaling has no offset and the
 * raw terms are exactly the scaled terms, their coefficients multiplied by the scales'
 * powers. */
typedef struct {
    int e[4];
    double c;
} term;
static const term PX[] = {{{1, 0, 0, 0}, -1.17},  {{0, 0, 1, 0}, 837.0},
                          {{3, 0, 0, 0}, 2.5e-5}, {{1, 2, 0, 0}, 2.4e-5},
                          {{1, 0, 2, 0}, 3.48},   {{0, 2, 1, 0}, 0.05},
                          {{0, 0, 1, 2}, 5.9e5},  {{5, 0, 0, 0}, 1.6e-10}};
static const term PY[] = {{{0, 1, 0, 0}, -1.17}, {{0, 0, 0, 1}, 837.0}, {{0, 3, 0, 0}, 2.5e-5},
                          {{2, 1, 0, 0}, 2.4e-5}, {{0, 1, 0, 2}, 3.48}};

static double eval_terms(const term *t, int n, const double *in)
{
    double s = 0;
    for (int i = 0; i < n; i++) {
        double m = t[i].c;
        for (int v = 0; v < 4; v++)
            m *= pow(in[v], t[i].e[v]);
        s += m;
    }
    return s;
}

static void make_planted(size_t n, uint64_t seed, double **in, double **out)
{
    *in = malloc(n * 4 * sizeof **in);
    *out = malloc(n * 2 * sizeof **out);
    for (size_t i = 0; i < n; i++) {
        double *q = *in + i * 4;
        q[0] = 100 * urand(&seed);
        q[1] = 100 * urand(&seed);
        q[2] = 0.01 * urand(&seed);
        q[3] = 0.01 * urand(&seed);
        (*out)[i * 2] = eval_terms(PX, 8, q);
        (*out)[i * 2 + 1] = eval_terms(PY, 5, q);
    }
}

/* The fitted terms, converted to raw units, must be the planted ones. The size of a
 * term over the domain is |c| * prod(scale^e); every term's error is checked against
 * the sum of those sizes (1e-10 of the polynomial), and its own coefficient to 1e-6. */
static void check_terms(const poly_system *sys, int o, const term *pl, int n)
{
    assert_int_equal(poly_nparts(sys), 1);
    assert_int_equal(poly_nterms(sys, 0, o), n);
    double scale[4], size = 0;
    for (int v = 0; v < 4; v++) {
        double off;
        poly_get_scaling(sys, v, &off, &scale[v]);
        assert_true(off == 0);
    }
    for (int i = 0; i < n; i++) {
        double m = fabs(pl[i].c);
        for (int v = 0; v < 4; v++)
            m *= pow(scale[v], pl[i].e[v]);
        size += m;
    }
    for (int t = 0; t < n; t++) {
        int e[4];
        double c;
        poly_get_term(sys, 0, o, t, e, &c);
        int found = -1;
        for (int i = 0; i < n; i++)
            if (!memcmp(e, pl[i].e, sizeof e))
                found = i;
        assert_true(found >= 0);
        double raw = c;
        for (int v = 0; v < 4; v++)
            raw /= pow(scale[v], e[v]);
        double tsize = 1;
        for (int v = 0; v < 4; v++)
            tsize *= pow(scale[v], e[v]);
        assert_true(fabs(raw - pl[found].c) * tsize <= 1e-10 * size);
        assert_true(fabs(raw - pl[found].c) <= 1e-6 * fabs(pl[found].c));
    }
}

static void test_planted_raw_units(void **state)
{
    (void)state;
    double *in, *out;
    size_t n = 2000;
    make_planted(n, 21, &in, &out);
    fit_options opt;
    fit_options_default(&opt);
    lens_err err;
    poly_system *sys = fit_system("planted", 4, IN4, 2, OUT2, n, in, out, &opt, &err);
    assert_non_null(sys);
    check_terms(sys, 0, PX, 8);
    check_terms(sys, 1, PY, 5);
    /* And evaluation agrees with the planted function at new points. */
    uint64_t sd = 99;
    for (int i = 0; i < 100; i++) {
        double q[4] = {100 * urand(&sd), 100 * urand(&sd), 0.01 * urand(&sd), 0.01 * urand(&sd)};
        double o[2];
        poly_eval(sys, q, o);
        assert_true(fabs(o[0] - eval_terms(PX, 8, q)) <= 1e-9 * 200);
        assert_true(fabs(o[1] - eval_terms(PY, 5, q)) <= 1e-9 * 200);
    }
    poly_free(sys);
    free(in);
    free(out);
}

/* 300 samples and C(15, 4) = 1365 candidates (degree 11 in four inputs): fewer samples
 * than candidates, which sparse selection must handle. */
static void test_fewer_samples_than_candidates(void **state)
{
    (void)state;
    double *in, *out;
    size_t n = 300;
    make_planted(n, 22, &in, &out);
    fit_options opt;
    fit_options_default(&opt);
    opt.max_degree = 11; /* C(15, 4) = 1365 candidates > 300 samples */
    lens_err err;
    poly_system *sys = fit_system("planted", 4, IN4, 2, OUT2, n, in, out, &opt, &err);
    assert_non_null(sys);
    check_terms(sys, 0, PX, 8);
    check_terms(sys, 1, PY, 5);
    poly_free(sys);
    free(in);
    free(out);
}

static char *write_mem(const poly_system *sys, size_t *len)
{
    char *buf = NULL;
    FILE *f = open_memstream(&buf, len);
    assert_int_equal(poly_write(f, sys), 0);
    fclose(f);
    return buf;
}

/* A smooth non-polynomial target on samples clustered in a small ball (80%) with a
 * thin uniform spread: the monomial Gram matrix is badly conditioned. Degree 13
 * candidates include every degree 11 one and the degree caps of 11 are among those of
 * 13, so the held-out error cannot be worse (up to rounding); outputs stay finite. */
static double target(const double *q)
{
    return exp(q[0]) * sin(2 * q[2]) + 1 / (2 + q[3]) + q[1] * q[1] * q[0];
}

static double holdout_rms(const poly_system *sys)
{
    const char *m = poly_get_meta(sys, "fit_out_x");
    assert_non_null(m);
    const char *p = strstr(m, "holdout_rms ");
    assert_non_null(p);
    return atof(p + 12);
}

static void test_clustered_degree13(void **state)
{
    (void)state;
    size_t n = 1500;
    uint64_t sd = 5;
    double *in = malloc(n * 4 * sizeof *in), *out = malloc(n * sizeof *out);
    const double c0[4] = {0.3, -0.2, 0.1, 0.0};
    for (size_t i = 0; i < n; i++) {
        for (int v = 0; v < 4; v++)
            in[i * 4 + v] = i % 5 ? c0[v] + 0.05 * urand(&sd) : urand(&sd);
        out[i] = target(in + i * 4);
    }
    const char *o1[] = {"out_x"};
    fit_options opt;
    fit_options_default(&opt);
    lens_err err;
    double rms[2];
    for (int k = 0; k < 2; k++) {
        opt.max_degree = k ? 13 : 11;
        poly_system *sys = fit_system("clustered", 4, IN4, 1, o1, n, in, out, &opt, &err);
        assert_non_null(sys);
        rms[k] = holdout_rms(sys);
        assert_true(isfinite(rms[k]));
        /* The fit is a good one: far below the target's spread (~0.5). */
        assert_true(rms[k] < 1e-3);
        uint64_t s2 = 77;
        for (int i = 0; i < 200; i++) {
            double q[4], y;
            for (int v = 0; v < 4; v++)
                q[v] = urand(&s2);
            poly_eval(sys, q, &y);
            assert_true(isfinite(y));
        }
        poly_free(sys);
    }
    assert_true(rms[1] <= rms[0] * 1.02);
    free(in);
    free(out);
}

static void test_deterministic_threads(void **state)
{
    (void)state;
    double *in, *out;
    size_t n = 1200;
    make_planted(n, 23, &in, &out);
    /* A non-polynomial output too, so that selection runs the full budget. */
    for (size_t i = 0; i < n; i++)
        out[i * 2 + 1] = sin(in[i * 4] / 50) * cos(in[i * 4 + 2] * 100);
    fit_options opt;
    fit_options_default(&opt);
    opt.max_terms = 20;
    opt.max_degree = 7;
    lens_err err;
    char *text[2];
    size_t len[2];
    for (int t = 0; t < 2; t++) {
        opt.threads = t + 1;
        poly_system *sys = fit_system("det", 4, IN4, 2, OUT2, n, in, out, &opt, &err);
        assert_non_null(sys);
        text[t] = write_mem(sys, &len[t]);
        poly_free(sys);
    }
    assert_int_equal(len[0], len[1]);
    assert_memory_equal(text[0], text[1], len[0]);
    free(text[0]);
    free(text[1]);
    free(in);
    free(out);
}

static void expect_fail(size_t n, const double *in, const double *out, int terms,
                        const char *pattern)
{
    fit_options opt;
    fit_options_default(&opt);
    opt.max_terms = terms;
    opt.max_degree = 5;
    lens_err err = {{0}};
    poly_system *sys = fit_system("bad", 4, IN4, 2, OUT2, n, in, out, &opt, &err);
    assert_null(sys);
    if (!strstr(err.msg, pattern))
        fail_msg("message '%s' does not mention '%s'", err.msg, pattern);
}

static void test_degenerate(void **state)
{
    (void)state;
    double *in, *out;
    size_t n = 200;
    make_planted(n, 24, &in, &out);
    expect_fail(0, in, out, 10, "no samples");
    /* 200 usable, 40 held out: 160 training rows are fewer than 170 terms. */
    expect_fail(n, in, out, 170, "fewer than");
    for (size_t i = 0; i < n; i++)
        in[i * 4 + 3] = 0.25;
    expect_fail(n, in, out, 10, "input v is constant");
    free(in);
    free(out);
    make_planted(n, 24, &in, &out);
    in[17 * 4 + 1] = NAN;
    expect_fail(n, in, out, 10, "sample 18: input y is not finite");
    in[17 * 4 + 1] = 1;
    for (size_t i = 0; i < n; i++)
        out[i * 2] = NAN;
    expect_fail(n, in, out, 10, "every ray is blocked");
    free(in);
    free(out);
}

/* Blocked rays (non-finite outputs) are left out, and the pass circle is the furthest
 * passing hit. */
static void test_blocked_rows_and_pass_circle(void **state)
{
    (void)state;
    double *in, *out;
    size_t n = 1500;
    make_planted(n, 25, &in, &out);
    double rmax = 0;
    for (size_t i = 0; i < n; i++) {
        if (i % 7 == 3) {
            out[i * 2] = NAN; /* blocked, and its out_y is garbage */
            out[i * 2 + 1] = 1e30;
        } else {
            rmax = fmax(rmax, hypot(out[i * 2], out[i * 2 + 1]));
        }
    }
    fit_options opt;
    fit_options_default(&opt);
    lens_err err;
    poly_system *sys = fit_system("blocked", 4, IN4, 2, OUT2, n, in, out, &opt, &err);
    assert_non_null(sys);
    check_terms(sys, 0, PX, 8);
    check_terms(sys, 1, PY, 5);
    assert_int_equal(poly_npass_circles(sys), 1);
    int a, b;
    double r;
    poly_get_pass_circle(sys, 0, &a, &b, &r);
    assert_int_equal(a, 0);
    assert_int_equal(b, 1);
    assert_true(r >= rmax && r <= rmax * (1 + 1e-6));
    poly_free(sys);
    free(in);
    free(out);
}

/* A kink along the circle r = 0.5 (|r - 0.5|^3, whose third derivative jumps there):
 * one polynomial converges slowly, rings split at radius 0.5 fit each side smoothly.
 * With a tolerance no single polynomial meets, lens-fit must take parts, report the
 * jump between them, and do better on held-out rows than with one part. */
static double kink(double x, double y)
{
    double d = hypot(x, y) - 0.5;
    return fabs(d) * d * d + 0.1 * x;
}

static void test_parts(void **state)
{
    (void)state;
    size_t n = 3000;
    uint64_t sd = 31;
    const char *in2[] = {"x", "y"}, *o1[] = {"out_x"};
    double *in = malloc(n * 2 * sizeof *in), *out = malloc(n * sizeof *out);
    for (size_t i = 0; i < n; i++) {
        double r = sqrt(0.5 * (urand(&sd) + 1)), t = M_PI * urand(&sd);
        in[i * 2] = r * cos(t);
        in[i * 2 + 1] = r * sin(t);
        out[i] = kink(in[i * 2], in[i * 2 + 1]);
    }
    fit_options opt;
    fit_options_default(&opt);
    opt.max_terms = 12;
    opt.max_degree = 8;
    lens_err err;
    poly_system *one = fit_system("kink", 2, in2, 1, o1, n, in, out, &opt, &err);
    assert_non_null(one);
    double rms1 = holdout_rms(one);
    opt.tolerance = rms1 / 10;
    opt.max_parts = 3;
    poly_system *parts = fit_system("kink", 2, in2, 1, o1, n, in, out, &opt, &err);
    assert_non_null(parts);
    assert_true(poly_nparts(parts) >= 2);
    assert_true(holdout_rms(parts) < rms1);
    const char *jump = poly_get_meta(parts, "part_jump_out_x");
    assert_non_null(jump);
    assert_true(isfinite(atof(jump)) && atof(jump) >= 0);
    /* Neighbouring parts meet: each part's range starts where the previous ends. */
    for (int p = 1; p < poly_nparts(parts); p++) {
        double a0, a1, b0, b1;
        poly_part_range(parts, p - 1, &a0, &a1);
        poly_part_range(parts, p, &b0, &b1);
        assert_true(a1 == b0);
    }
    poly_free(one);
    poly_free(parts);
    free(in);
    free(out);
}

/* ap_x and ap_y outputs get a pass circle of their own (the stop). */
static void test_stop_circle(void **state)
{
    (void)state;
    double *in, *out;
    size_t n = 600;
    make_planted(n, 26, &in, &out);
    const char *o2[] = {"ap_x", "ap_y"};
    fit_options opt;
    fit_options_default(&opt);
    opt.max_degree = 5;
    lens_err err;
    poly_system *sys = fit_system("stop", 4, IN4, 2, o2, n, in, out, &opt, &err);
    assert_non_null(sys);
    assert_int_equal(poly_npass_circles(sys), 1);
    poly_free(sys);
    free(in);
    free(out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_planted_raw_units),
        cmocka_unit_test(test_fewer_samples_than_candidates),
        cmocka_unit_test(test_clustered_degree13),
        cmocka_unit_test(test_deterministic_threads),
        cmocka_unit_test(test_degenerate),
        cmocka_unit_test(test_blocked_rows_and_pass_circle),
        cmocka_unit_test(test_parts),
        cmocka_unit_test(test_stop_circle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
