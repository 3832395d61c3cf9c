/* poly_copy_outputs: a system with some of its outputs (lens-fit's dropped circles). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/poly.h"
#include "poly_fixture.h"

/* One ray's value (poly_fast: another order of additions, fused multiply-adds) against
 * the batch's, to 1e-12 relative to the larger of the value and scale. */
static void agree(double one, double batch, double scale, int r, int o)
{
    if ((isnan(one) && isnan(batch)) || one == batch)
        return;
    if (!(fabs(one - batch) <= 1e-12 * fmax(fabs(batch), scale)))
        fail_msg("ray %d output %d: poly_eval %.17g, batch %.17g", r, o, one, batch);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* poly_copy_outputs (lens-fit's dropped circles): the outputs kept give the original's
 * bits in the batch, frame, transform, parts and domain included, and one ray at a time
 * the batch's values to rounding (poly_fast orders a copy's terms by its own outputs'
 * variables); a circle on a dropped output goes with it (the rays only it blocked pass),
 * the others stay; so do the meta lines but those of the dropped outputs. */
static void test_copy_outputs(void **st)
{
    (void)st;
    enum { N = 203 };
    poly_system *s = fixture_system(30, 9, 2, 77);
    assert_non_null(s);
    assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
    assert_int_equal(poly_set_output_plain(s, 2, 1), 0);
    assert_int_equal(poly_set_output_plain(s, 3, 1), 0);
    assert_int_equal(poly_set_transform(s, 4, POLY_XFORM_INVERSE_SQUARE), 0);
    poly_set_scaling(s, 4, 4.25, 2.0);
    poly_set_domain(s, 0, -3, 3);
    poly_set_lens_path(s, "lenses/x.lens");
    poly_set_meta(s, "fit_out_u", "terms 30");
    poly_set_meta(s, "part_jump_out_v", "0.1");
    poly_set_meta(s, "fit_out_x", "terms 30");
    double *in = malloc(N * 5 * sizeof *in), *o5 = malloc(N * 5 * sizeof *o5);
    double *o3 = malloc(N * 3 * sizeof *o3);
    unsigned char p5[N], p3[N];
    assert_non_null(in);
    assert_non_null(o5);
    assert_non_null(o3);
    fixture_rng g = {5};
    for (int r = 0; r < N; r++)
        fixture_ray(&g, in + r * 5);
    poly_eval_batch(s, N, in, o5, p5);
    /* circles: out_x out_y around every ray's value, out_u out_v around half of them */
    double rxy = 0, ruv[N];
    for (int r = 0; r < N; r++) {
        rxy = fmax(rxy, hypot(o5[r * 5], o5[r * 5 + 1]));
        ruv[r] = hypot(o5[r * 5 + 2], o5[r * 5 + 3]);
    }
    qsort(ruv, N, sizeof *ruv, cmp_double);
    assert_int_equal(poly_add_pass_circle(s, 0, 1, 2 * rxy), 0);
    assert_int_equal(poly_add_pass_circle(s, 2, 3, ruv[N / 2]), 0);
    poly_eval_batch(s, N, in, o5, p5);
    const unsigned char keep[5] = {1, 1, 0, 0, 1};
    poly_system *c = poly_copy_outputs(s, keep);
    assert_non_null(c);
    assert_int_equal(poly_noutputs(c), 3);
    assert_string_equal(poly_output_name(c, 2), "out_eta");
    assert_int_equal(poly_npass_circles(c), 1);
    assert_string_equal(poly_lens_path(c), "lenses/x.lens");
    assert_null(poly_get_meta(c, "fit_out_u"));
    assert_null(poly_get_meta(c, "part_jump_out_v"));
    assert_string_equal(poly_get_meta(c, "fit_out_x"), "terms 30");
    double lo, hi;
    poly_get_domain(c, 0, &lo, &hi);
    assert_true(lo == -3 && hi == 3);
    poly_eval_batch(c, N, in, o3, p3);
    double range[3] = {0};
    for (int r = 0; r < N * 3; r++)
        range[r % 3] = isfinite(o3[r]) ? fmax(range[r % 3], fabs(o3[r])) : range[r % 3];
    int blocked_uv = 0;
    for (int r = 0; r < N; r++) {
        static const int from[3] = {0, 1, 4};
        double one[3];
        for (int k = 0; k < 3; k++)
            assert_memory_equal(&o3[r * 3 + k], &o5[r * 5 + from[k]], sizeof *o3);
        assert_int_equal(p3[r], 1); /* out_x out_y's circle holds them all */
        blocked_uv += !p5[r];
        poly_eval(c, in + r * 5, one);
        for (int k = 0; k < 3; k++)
            agree(one[k], o3[r * 3 + k], range[k], r, k);
    }
    assert_true(blocked_uv >= N / 3); /* the dropped circle did block */
    poly_system *all = poly_copy_outputs(s, NULL);
    assert_non_null(all);
    assert_int_equal(poly_npass_circles(all), 2);
    poly_eval_batch(all, N, in, o5, p3);
    assert_memory_equal(p3, p5, N);
    poly_free(all);
    poly_free(c);
    poly_free(s);
    free(in);
    free(o5);
    free(o3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_copy_outputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
