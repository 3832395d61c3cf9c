/* Newton through a system, many rays at once (poly_solve_sensor_batch) against the
 * system itself (each solution's outer-pupil image is its target) and against the
 * one-ray solver; with and without the meridional frame, with a pass circle, and with
 * targets no sensor ray reaches. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/poly_solve.h"
#include "splitmix.h"

static const double F = 50.0; /* focal length of the near-ideal system */
static const double R = 20.0; /* its pass circle on the outer pupil */

/* The ideal lens on the front plane (out_x = x + F u, out_u = -x / F, as test_spot's)
 * with cubic terms that make Newton iterate, written in the system's variables: in the
 * meridional frame those are r, u', v' (y is 0 there), and the system is rotationally
 * symmetric by construction. out_eta falls off with the direction. */
static poly_system *cubic_system(int frame)
{
    const char *in[5] = {"x", "y", "u", "v", "lambda"};
    const char *out[5] = {"out_x", "out_y", "out_u", "out_v", "out_eta"};
    poly_system *s = poly_new("cubic", 5, in, 5, out);
    assert_non_null(s);
    int part = poly_add_part(s, 0, INFINITY);
    assert_true(part >= 0);
    /* terms: output, exponents of x y u v lambda, coefficient */
    static const struct {
        int o, e[5];
        double c;
    } t[] = {{0, {1, 0, 0, 0, 0}, 1.0},     {0, {0, 0, 1, 0, 0}, 50.0},
             {0, {3, 0, 0, 0, 0}, 2e-4},    {0, {1, 0, 2, 0, 0}, 3.0},
             {0, {0, 0, 1, 0, 1}, 0.5},     {1, {0, 0, 0, 1, 0}, 50.0},
             {1, {1, 0, 1, 1, 0}, 4.0},     {1, {0, 0, 2, 1, 0}, -20.0},
             {2, {1, 0, 0, 0, 0}, -1 / F},  {2, {3, 0, 0, 0, 0}, 1e-6},
             {2, {0, 0, 3, 0, 0}, 0.2},     {3, {0, 0, 0, 1, 0}, 0.05},
             {3, {1, 0, 1, 1, 0}, 1e-3},    {4, {0, 0, 0, 0, 0}, 0.95},
             {4, {0, 0, 2, 0, 0}, -0.3},    {4, {0, 0, 0, 2, 0}, -0.3},
             /* y: 0 in the frame, the mirror of x outside it */
             {1, {0, 1, 0, 0, 0}, 1.0},     {3, {0, 1, 0, 0, 0}, -1 / F}};
    for (size_t k = 0; k < sizeof t / sizeof t[0]; k++) {
        int e[5];
        memcpy(e, t[k].e, sizeof e);
        assert_int_equal(poly_add_term(s, part, t[k].o, e, t[k].c), 0);
    }
    assert_int_equal(poly_add_pass_circle(s, 0, 1, R), 0);
    if (frame)
        assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
    return s;
}

/* Targets: the images of random sensor rays (so a solution exists), some of them
 * outside the pass circle, and the last three no sensor ray has (an infinite out_x, a
 * nan out_x, an infinite out_u). */
static size_t make_targets(const poly_system *s, size_t n, double *lambda, double *outer,
                           double *truth)
{
    uint64_t st = 12345;
    double out[5];
    for (size_t i = 0; i < n; i++) {
        double in[5] = {-12 + 24 * splitmix_uniform(&st), -12 + 24 * splitmix_uniform(&st),
                        -0.2 + 0.4 * splitmix_uniform(&st), -0.2 + 0.4 * splitmix_uniform(&st),
                        0.45 + 0.2 * splitmix_uniform(&st)};
        if (i == 7)
            in[0] = in[1] = 0; /* on the axis */
        poly_eval(s, in, out);
        memcpy(outer + 4 * i, out, 4 * sizeof(double));
        memcpy(truth + 4 * i, in, 4 * sizeof(double));
        lambda[i] = in[4];
    }
    outer[4 * (n - 3)] = INFINITY; /* would make the tolerance infinite */
    outer[4 * (n - 2)] = NAN;
    outer[4 * (n - 1) + 2] = INFINITY;
    return n;
}

static void batch_matches_the_system_and_the_one_ray_solver(int frame)
{
    poly_system *s = cubic_system(frame);
    enum { N = 300 };
    double lambda[N], outer[4 * N], truth[4 * N], sensor[4 * N], eta[N], seed[4] = {0.3, -0.2, 0, 0};
    int status[N];
    unsigned char pass[N];
    make_targets(s, N, lambda, outer, truth);
    assert_int_equal(poly_solve_sensor_batch(s, N, lambda, outer, seed, 0, 0, sensor, status, pass, eta), 0);
    size_t solved = 0, passed = 0;
    for (size_t i = 0; i < N; i++) {
        double one[4], e1 = -1;
        int p1 = -1;
        int st1 = poly_solve_sensor(s, lambda[i], outer + 4 * i, seed, one, &p1, &e1);
        assert_int_equal(status[i], st1);
        if (i >= N - 3) {
            assert_int_equal(status[i], -1); /* nan and inf targets */
            continue;
        }
        if (status[i] != 0)
            continue;
        solved++;
        /* the solution images onto its target: the system's own values, one ray */
        double in[5] = {sensor[4 * i], sensor[4 * i + 1], sensor[4 * i + 2], sensor[4 * i + 3],
                        lambda[i]},
               out[5];
        int p = poly_eval(s, in, out);
        double tol = 1e-9 * (1 + fmax(fmax(fabs(outer[4 * i]), fabs(outer[4 * i + 1])), 1.0));
        for (int o = 0; o < 4; o++)
            assert_true(fabs(out[o] - outer[4 * i + o]) <= tol);
        /* the map is one-to-one here: the sensor ray the target came from */
        for (int a = 0; a < 4; a++)
            assert_true(fabs(sensor[4 * i + a] - truth[4 * i + a]) < 1e-7);
        for (int a = 0; a < 4; a++)
            assert_true(fabs(sensor[4 * i + a] - one[a]) < 1e-7);
        assert_int_equal(pass[i], p);
        assert_int_equal(pass[i], p1);
        assert_true(fabs(eta[i] - out[4]) < 1e-12);
        assert_true(fabs(eta[i] - e1) < 1e-12);
        /* the pass circle itself: out_x^2 + out_y^2 <= R^2 */
        assert_int_equal(pass[i], hypot(outer[4 * i], outer[4 * i + 1]) <= R);
        passed += pass[i];
    }
    /* most targets are solved, and the circle cuts the set */
    assert_true(solved >= N - 10);
    assert_true(passed > N / 4 && passed < solved);
    /* one seed per ray: the true rays themselves converge at once */
    assert_int_equal(poly_solve_sensor_batch(s, N - 3, lambda, outer, truth, 4, 0, sensor, status, NULL, NULL), 0);
    for (size_t i = 0; i < N - 3; i++) {
        assert_int_equal(status[i], 0);
        for (int a = 0; a < 4; a++)
            assert_true(fabs(sensor[4 * i + a] - truth[4 * i + a]) < 1e-7);
    }
    poly_free(s);
}

static void batch_unframed(void **state)
{
    (void)state;
    batch_matches_the_system_and_the_one_ray_solver(0);
}

static void batch_meridional(void **state)
{
    (void)state;
    batch_matches_the_system_and_the_one_ray_solver(1);
}

static void batch_edges(void **state)
{
    (void)state;
    poly_system *s = cubic_system(1);
    double lambda = 0.55, outer[4] = {1, 2, 0.01, 0.02}, sensor[4];
    int status = 7;
    /* no rays: nothing written */
    assert_int_equal(poly_solve_sensor_batch(s, 0, &lambda, outer, NULL, 0, 0, sensor, &status, NULL, NULL), 0);
    assert_int_equal(status, 7);
    /* a system without out_u: refused */
    const char *in[5] = {"x", "y", "u", "v", "lambda"}, *out[3] = {"out_x", "out_y", "out_v"};
    poly_system *t = poly_new("t", 5, in, 3, out);
    assert_non_null(t);
    assert_int_equal(poly_solve_sensor_batch(t, 1, &lambda, outer, NULL, 0, 0, sensor, &status, NULL, NULL), -1);
    assert_int_equal(status, 7);
    poly_free(t);
    poly_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(batch_unframed),
        cmocka_unit_test(batch_meridional),
        cmocka_unit_test(batch_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
