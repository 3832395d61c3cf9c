/* fit_drop_circles (lens-fit's circles that decide nothing), on a system of known
 * circles: every hit is the sensor point (x, y) itself, so which circle blocks which
 * row is plain geometry, and the lens's verdict is set row by row. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit/fit_internal.h"
#include "sparselens/fit.h"
#include "sparselens/poly.h"

enum { N = 61 * 61 };

/* out_x (unless passage_only) and pairs s1 .. s{ncirc} of hits (x, y), circle radii
 * radius[k]. */
static poly_system *circles(int ncirc, const double *radius, int passage_only)
{
    static const char *const in[2] = {"x", "y"};
    char names[8][8];
    const char *out[9];
    int nout = 0;
    if (!passage_only)
        out[nout++] = "out_x";
    for (int k = 0; k < ncirc; k++)
        for (int a = 0; a < 2; a++) {
            snprintf(names[2 * k + a], sizeof names[0], "s%d_%c", k + 1, "xy"[a]);
            out[nout++] = names[2 * k + a];
        }
    poly_system *s = poly_new("circles", 2, in, nout, out);
    assert_non_null(s);
    int p = poly_add_part(s, 0, INFINITY);
    const int ex[2] = {1, 0}, ey[2] = {0, 1};
    for (int o = 0; o < nout; o++)
        assert_int_equal(poly_add_term(s, p, o, o == 0 && !passage_only ? ex : (o - !passage_only) % 2 ? ey : ex, 1), 0);
    for (int k = 0; k < ncirc; k++)
        assert_int_equal(poly_add_pass_circle(s, !passage_only + 2 * k, !passage_only + 2 * k + 1,
                                              radius[k]), 0);
    return s;
}

/* A grid over [-1.5, 1.5]^2; the lens passes a row when r <= rlens. */
static void rows(double *in, unsigned char *pass, double rlens)
{
    for (int i = 0; i < N; i++) {
        in[2 * i] = -1.5 + 3.0 * (i % 61) / 60;
        in[2 * i + 1] = -1.5 + 3.0 * (i / 61) / 60;
        pass[i] = hypot(in[2 * i], in[2 * i + 1]) <= rlens;
    }
}

/* fit_drop_circles on circles(ncirc, radius, passage_only) with the lens passing
 * r <= rlens; *orig gets the system it was given (the result, or freed by it). */
static poly_system *drop(int ncirc, const double *radius, int passage_only, double rlens,
                         poly_system **orig)
{
    poly_system *s = circles(ncirc, radius, passage_only);
    double in[2 * N];
    unsigned char pass[N];
    rows(in, pass, rlens);
    *orig = s;
    poly_system *d = fit_drop_circles(s, N, in, pass);
    assert_non_null(d);
    return d;
}

static int has_output(const poly_system *s, const char *name)
{
    return poly_output_index(s, name) >= 0;
}

/* The lens blocks beyond r = 1. s1 and s2 (radius 1) do each other's work: one goes,
 * not both (they are counted again after the first); s3 (radius 2) blocks nothing the
 * others do not; s4 (radius 0.8) alone blocks nothing (s1, s2 block the same rows
 * beyond 1), and only rows the lens passes: it goes first. */
static void test_drops_idle(void **st)
{
    (void)st;
    const double radius[4] = {1, 1, 2, 0.8};
    poly_system *s, *d = drop(4, radius, 0, 1, &s);
    assert_true(d != s);
    assert_int_equal(poly_noutputs(d), 3);
    assert_int_equal(poly_npass_circles(d), 1);
    assert_true(has_output(d, "out_x"));
    assert_true(has_output(d, "s1_x") != has_output(d, "s2_x"));
    assert_false(has_output(d, "s3_x"));
    assert_false(has_output(d, "s4_x"));
    const char *m = poly_get_meta(d, "fit_dropped_circles");
    assert_non_null(m);
    assert_true(strncmp(m, "s4 ", 3) == 0); /* it blocked rows the lens passes: first */
    poly_free(d);
}

/* A circle that alone blocks rows the lens blocks stays, with however many rows the
 * lens passes it blocks too (here the lens blocks beyond 0.8, the circle at 1). */
static void test_keeps_needed(void **st)
{
    (void)st;
    const double radius[1] = {1};
    poly_system *s, *d = drop(1, radius, 0, 0.8, &s);
    assert_ptr_equal(d, s);
    assert_int_equal(poly_npass_circles(d), 1);
    poly_free(d);
}

/* A circle that alone blocks rows the lens blocks stays even when it alone blocks more
 * rows the lens passes: the lens blocks beyond 1; s1 (0.9) alone blocks the rows from 1
 * to 1.05 and, wrongly, those from 0.9 to 1; s2 (1.05) blocks nothing s1 does not. s2
 * goes, s1 stays (a rule of "no more rightly than wrongly" dropped s1, and a coarse
 * passage lost the rows it alone blocked). */
static void test_keeps_rightful(void **st)
{
    (void)st;
    const double radius[2] = {0.9, 1.05};
    poly_system *s, *d = drop(2, radius, 0, 1, &s);
    assert_true(has_output(d, "s1_x"));
    assert_false(has_output(d, "s2_x"));
    poly_free(d);
}

/* Nothing to judge by: no row blocked, or no output a blocked ray would lack (every
 * output a passage hit). The system comes back as it was. */
static void test_nothing_to_judge(void **st)
{
    (void)st;
    const double radius[2] = {1, 2};
    poly_system *s, *d = drop(2, radius, 0, 10, &s);
    assert_ptr_equal(d, s);
    assert_int_equal(poly_npass_circles(d), 2);
    poly_free(d);
    d = drop(2, radius, 1, 1, &s);
    assert_ptr_equal(d, s);
    assert_int_equal(poly_noutputs(d), 4);
    poly_free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_drops_idle),
        cmocka_unit_test(test_keeps_needed),
        cmocka_unit_test(test_keeps_rightful),
        cmocka_unit_test(test_nothing_to_judge),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
