/* The pass test of a framed system takes each circle's pair as the frame gives it,
 * before the pair turns back (poly_eval_part): the turn keeps the pair's radius, so it
 * is the same circle with one rounding less, and the batch kernel need not turn the
 * pairs it does not write. Every path must test the same values, or a ray on a circle's
 * edge passes in one and not in another: pass_edge_fixture.h's rays tell (the emitted
 * C: test_poly_emit). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>

#include "pass_edge_fixture.h"

static void check_edge(int plan)
{
    poly_system *s = edge_system(plan);
    assert_non_null(s);
    enum { N = 500 };
    double *in = malloc(N * 5 * sizeof(double)), *out = malloc(N * 5 * sizeof(double));
    double *sel = malloc(N * sizeof(double)), one[5], jac[25];
    unsigned char *pass = malloc(N), *pass_sel = malloc(N);
    const int n = edge_rays(in, N);
    print_message("%d edge rays inside the circle once turned back, outside before\n", n);
    assert_int_equal(n, N);
    poly_eval_batch(s, (size_t)n, in, out, pass);
    static const int only_x[1] = {0};
    assert_int_equal(poly_eval_batch_outputs(s, (size_t)n, in, 1, only_x, sel, pass_sel), 0);
    for (int r = 0; r < n; r++) {
        assert_int_equal(pass[r], 0);
        assert_int_equal(pass_sel[r], 0);
        assert_int_equal(poly_eval(s, in + 5 * r, one), 0);
        assert_int_equal(poly_eval_jacobian(s, in + 5 * r, one, jac), 0);
        /* the written values are still the turned ones */
        assert_true(fabs(out[5 * r] - in[5 * r]) <= 1e-14 * EDGE_R0);
        assert_true(fabs(out[5 * r + 1] - in[5 * r + 1]) <= 1e-14 * EDGE_R0);
        assert_true(sel[r] == out[5 * r]);
    }
    /* and the circle still passes what is inside: the same rays 1e-12 nearer the axis */
    for (int r = 0; r < n; r++) {
        in[5 * r] *= 1 - 1e-12;
        in[5 * r + 1] *= 1 - 1e-12;
    }
    poly_eval_batch(s, (size_t)n, in, out, pass);
    for (int r = 0; r < n; r++) {
        assert_int_equal(pass[r], 1);
        assert_int_equal(poly_eval(s, in + 5 * r, one), 1);
        assert_int_equal(poly_eval_jacobian(s, in + 5 * r, one, jac), 1);
    }
    free(in);
    free(out);
    free(sel);
    free(pass);
    free(pass_sel);
    poly_free(s);
}

static void test_pass_on_frame_values(void **st)
{
    (void)st;
    check_edge(0);
    check_edge(1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_pass_on_frame_values)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
