/* A batch Jacobian of more rows than the cache holds (more than 2 MB: 11000 rays of 25
 * columns) goes out of the AVX-512 kernel past the caches, a block at a time, its whole
 * cache lines streamed and the partial ones at the block's ends stored as usual
 * (poly_eval.c, STREAM_MIN). It must give the bits of the same rays in short calls,
 * which store their rows the usual way, wherever the output starts (not on a cache line
 * here: one double in), and write nothing outside its rows. With the meridional frame
 * (the chain rule over the derivatives), a transform alone, and neither. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "poly_fixture.h"

static void test_streamed_rows(void **st)
{
    (void)st;
    enum { N = 11003, NJ = 25, SHORT = 1000 }; /* 2.2 MB; a partial last block */
    double *in = malloc(N * 5 * sizeof *in), *buf = malloc((N * NJ + 2) * sizeof *buf);
    double *ref = malloc(N * NJ * sizeof *ref);
    assert_true(in && buf && ref);
    fixture_rng g = {77};
    for (int r = 0; r < N; r++)
        fixture_ray(&g, in + r * 5);
    in[5 * 4000] = in[5 * 4000 + 1] = 0; /* on the axis */
    for (int layout = 0; layout < 3; layout++) {
        poly_system *s = fixture_system(30, 9, 1, 60 + (uint64_t)layout);
        assert_non_null(s);
        if (layout == 0)
            assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
        if (layout < 2)
            assert_int_equal(poly_set_transform(s, 4, POLY_XFORM_INVERSE_SQUARE), 0);
        for (int r = 0; r < N; r += SHORT)
            poly_eval_jacobian_batch(s, (size_t)(N - r < SHORT ? N - r : SHORT), in + 5 * r,
                                     ref + (size_t)r * NJ);
        buf[0] = buf[N * NJ + 1] = -12345.5;
        poly_eval_jacobian_batch(s, N, in, buf + 1);
        assert_memory_equal(buf + 1, ref, (size_t)N * NJ * sizeof *ref);
        assert_true(buf[0] == -12345.5 && buf[N * NJ + 1] == -12345.5);
        int finite = 0;
        for (size_t k = 0; k < (size_t)N * NJ; k++)
            finite += isfinite(ref[k]) && ref[k] != 0;
        assert_true(finite > N * NJ / 2); /* rows of real derivatives, not all zero */
        poly_free(s);
    }
    free(in);
    free(buf);
    free(ref);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_streamed_rows)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
