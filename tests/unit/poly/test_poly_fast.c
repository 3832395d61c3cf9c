/* The one-ray paths on the layout lens-fit writes (lens-poly 2: every output in the
 * meridional frame, out_x/out_y and out_u/out_v turned back as pairs, 1/lambda^2, a pass
 * circle): poly_eval (poly_fast.c: power tables, fused multiply-adds, the frame and the
 * pass test in one pass) against poly_eval_batch, the systems poly_fast declines
 * against the batch bit for bit, and the Jacobian of this layout (poly_jacobian.c's
 * chain rule as 2 x 2 rotations) against central differences, on and off the axis. */
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

static int nrays(int n)
{
    return getenv("SANITIZE") && *getenv("SANITIZE") ? n / 10 + 1 : n;
}

/* The fixture's 5 x 40 terms in the layout of a lens-poly 2 fit. */
static poly_system *framed_system(uint64_t seed)
{
    poly_system *s = fixture_system(40, 11, 1, seed);
    assert_non_null(s);
    assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
    assert_int_equal(poly_set_transform(s, 4, POLY_XFORM_INVERSE_SQUARE), 0);
    poly_set_scaling(s, 4, 4.25, 2.0); /* 1/lambda^2 over 0.40..0.70 um */
    assert_int_equal(poly_add_pass_circle(s, 0, 1, 30), 0);
    return s;
}

/* poly_eval against the batch: each output to 1e-12 of its size over the rays (its
 * largest magnitude: a value that cancels to nearly 0 keeps the rounding of its terms),
 * and the same pass flags. */
static void check_against_batch(const poly_system *s, int n, const double *in, int exact)
{
    const int no = poly_noutputs(s), ni = poly_ninputs(s);
    double *out = malloc((size_t)n * no * sizeof(double)), *one = malloc(no * sizeof(double));
    unsigned char *pass = malloc((size_t)n);
    double size[POLY_MAX_OUTPUTS] = {0};
    poly_eval_batch(s, (size_t)n, in, out, pass);
    for (int r = 0; r < n; r++)
        for (int o = 0; o < no; o++)
            if (isfinite(out[r * no + o]))
                size[o] = fmax(size[o], fabs(out[r * no + o]));
    int same = 0;
    for (int r = 0; r < n; r++) {
        assert_int_equal(poly_eval(s, in + (size_t)r * ni, one), pass[r]);
        for (int o = 0; o < no; o++) {
            const double b = out[r * no + o];
            same += one[o] == b || (isnan(one[o]) && isnan(b));
            if (!(one[o] == b || (isnan(one[o]) && isnan(b)) ||
                  (!exact && fabs(one[o] - b) <= 1e-12 * size[o])))
                fail_msg("ray %d output %d: poly_eval %.17g, batch %.17g", r, o, one[o], b);
        }
    }
    print_message("%d of %d values bit-identical to the batch\n", same, n * no);
    free(out);
    free(one);
    free(pass);
}

static void test_framed_eval(void **st)
{
    (void)st;
    poly_system *s = framed_system(11);
    const int n = nrays(3000);
    double *in = malloc((size_t)n * 5 * sizeof(double));
    fixture_rng g = {77};
    for (int r = 0; r < n; r++) {
        fixture_ray(&g, in + 5 * r);
        if (r % 11 == 0) /* far outside the domain: some rays fail the circle */
            in[5 * r] *= 2.5;
        if (r == 4) /* on the axis: the frame held at c = 1, s = 0 */
            in[5 * r] = in[5 * r + 1] = 0;
        if (r == 6) /* 1/lambda^2 infinite: every output not finite (the plan's values) */
            in[5 * r + 4] = 0;
        if (r == 8) /* nan in: nan out where the plan has it */
            in[5 * r + 2] = NAN;
    }
    check_against_batch(s, n, in, 0);
    poly_free(s);
    /* an even number of outputs (their sums across lanes are taken two at a time) */
    static const char *const xy[2] = {"x", "y"}, *const o4[4] = {"a", "b", "c", "d"};
    s = poly_new("four", 2, xy, 4, o4);
    assert_int_equal(poly_add_part(s, 0, INFINITY), 0);
    for (int o = 0; o < 4; o++)
        for (int t = 0; t < 5 + 7 * o; t++) {
            const int e[2] = {t % 9, (t * 5 + o) % 7};
            assert_int_equal(poly_add_term(s, 0, o, e, fixture_uniform(&g) - 0.5), 0);
        }
    for (int k = 0; k < 2 * n; k++)
        in[k] = 2 * fixture_uniform(&g) - 1;
    check_against_batch(s, n, in, 0);
    free(in);
    poly_free(s);
}

/* Turned pairs that are not outputs (2j, 2j + 1): out_eta first, so the pairs are (1, 2)
 * and (3, 4), as a default fit's passage hit points come after its out_eta: poly_fast
 * adds each pair's lanes together and turns them there (out_eta alone), and with the
 * pair bits off by one output the values are far off (checked). */
static void test_shifted_pairs(void **st)
{
    (void)st;
    static const char *const outs[5] = {"out_eta", "out_x", "out_y", "out_u", "out_v"};
    poly_system *s = poly_new("shifted", 5, fixture_inputs, 5, outs);
    assert_non_null(s);
    assert_int_equal(poly_add_part(s, 0, INFINITY), 0);
    fixture_rng g = {31};
    for (int o = 0; o < 5; o++)
        for (int t = 0; t < 30; t++) {
            int e[5];
            fixture_monomial(&g, 9, o == 0 ? 0 : 1, 0, e);
            e[1] = 0; /* y is 0 in the frame */
            poly_add_term(s, 0, o, e, (2 * fixture_uniform(&g) - 1) / (1 + t));
        }
    poly_set_scaling(s, 0, 0, 18);
    poly_set_scaling(s, 2, 0, 0.6);
    poly_set_scaling(s, 3, 0, 0.6);
    assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
    assert_int_equal(poly_set_transform(s, 4, POLY_XFORM_INVERSE_SQUARE), 0);
    poly_set_scaling(s, 4, 4.25, 2.0);
    assert_int_equal(poly_add_pass_circle(s, 1, 2, 1.5), 0);
    const int n = nrays(2000);
    double *in = malloc((size_t)n * 5 * sizeof(double));
    for (int r = 0; r < n; r++)
        fixture_ray(&g, in + 5 * r);
    check_against_batch(s, n, in, 0);
    free(in);
    poly_free(s);
}

/* Exponents past 15 and more than 6 inputs with terms: poly_fast declines, the plan's
 * interpreter runs, and poly_eval is the batch's value bit for bit. */
static void test_declined_systems(void **st)
{
    (void)st;
    poly_system *s = framed_system(12);
    const int e17[5] = {17, 0, 0, 0, 0}, e16[5] = {0, 0, 16, 0, 1};
    assert_int_equal(poly_add_term(s, 0, 0, e17, 1e-4), 0);
    assert_int_equal(poly_add_term(s, 0, 4, e16, 2e-3), 0);
    const int n = nrays(500);
    double *in = malloc((size_t)n * 7 * sizeof(double));
    fixture_rng g = {5};
    for (int r = 0; r < n; r++)
        fixture_ray(&g, in + 5 * r);
    check_against_batch(s, n, in, 1);
    poly_free(s);
    static const char *const in7[7] = {"a", "b", "c", "d", "e", "f", "h"};
    static const char *const out2[2] = {"p", "q"};
    s = poly_new("seven", 7, in7, 2, out2);
    assert_int_equal(poly_add_part(s, 0, INFINITY), 0);
    for (int i = 0; i < 7; i++) {
        int e[7] = {0};
        e[i] = 1 + i % 3;
        e[(i + 1) % 7] = 1;
        assert_int_equal(poly_add_term(s, 0, i % 2, e, 0.3 + 0.1 * i), 0);
    }
    for (int k = 0; k < 7 * n; k++)
        in[k] = 2 * fixture_uniform(&g) - 1;
    check_against_batch(s, n, in, 1);
    free(in);
    poly_free(s);
}

/* A system in the frame that is exactly rotationally symmetric (smooth across the
 * axis): in the frame out_x = A r + B u', out_y = B v', out_u = 0.02 r + 0.9 u' l,
 * out_v = 0.9 v' l, out_eta = 0.9 - 0.01 r^2 - 0.2 (u'^2 + v'^2) + 0.3 r u' + 0.1 l, with
 * A = 0.7 + 0.3 r^2, B = 1.2 + 0.05 r^2 + 0.4 r u' and l = 1/lambda^2 scaled. */
static poly_system *symmetric_system(void)
{
    poly_system *s = poly_new("sym", 5, fixture_inputs, 5, fixture_outputs);
    assert_int_equal(poly_add_part(s, 0, INFINITY), 0);
    static const struct {
        int o, e[5];
        double c;
    } terms[] = {
        {0, {1, 0, 0, 0, 0}, 0.7},   {0, {3, 0, 0, 0, 0}, 0.3},   {0, {0, 0, 1, 0, 0}, 1.2},
        {0, {2, 0, 1, 0, 0}, 0.05},  {0, {1, 0, 2, 0, 0}, 0.4},   {1, {0, 0, 0, 1, 0}, 1.2},
        {1, {2, 0, 0, 1, 0}, 0.05},  {1, {1, 0, 1, 1, 0}, 0.4},   {4, {0, 0, 0, 0, 0}, 0.9},
        {4, {2, 0, 0, 0, 0}, -0.01}, {4, {0, 0, 2, 0, 0}, -0.2},  {4, {0, 0, 0, 2, 0}, -0.2},
        {4, {1, 0, 1, 0, 0}, 0.3},   {4, {0, 0, 0, 0, 1}, 0.1},   {2, {1, 0, 0, 0, 0}, 0.02},
        {2, {0, 0, 1, 0, 1}, 0.9},   {3, {0, 0, 0, 1, 1}, 0.9}};
    for (size_t t = 0; t < sizeof terms / sizeof terms[0]; t++)
        assert_int_equal(poly_add_term(s, 0, terms[t].o, terms[t].e, terms[t].c), 0);
    assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
    assert_int_equal(poly_set_transform(s, 4, POLY_XFORM_INVERSE_SQUARE), 0);
    poly_set_scaling(s, 0, 0, 2);
    poly_set_scaling(s, 2, 0, 0.5); /* u', v' alike: the symmetry holds in s too */
    poly_set_scaling(s, 3, 0, 0.5);
    poly_set_scaling(s, 4, 4.25, 2.0);
    return s;
}

/* The Jacobian of ray in against central differences of poly_eval (step h_i per input,
 * tolerance tol (1 + |fd|)), the batch Jacobian to 1e-12 relative (its sums fused,
 * fixture_jacobian_differs), and the bits of two outputs alone. */
static void check_jacobian(const poly_system *s, const double *in, const double *h, double tol)
{
    double out[5], jac[25], jb[25], jo[10], oo[2], o0[5];
    assert_int_equal(poly_eval_jacobian(s, in, out, jac), poly_eval(s, in, o0));
    poly_eval_jacobian_batch(s, 1, in, jb);
    double scale[25]; /* each output's largest derivative: the size of its row's terms */
    for (int k = 0; k < 25; k++) {
        scale[k] = 0;
        for (int i = 0; i < 5; i++)
            scale[k] = fmax(scale[k], fabs(jac[k / 5 * 5 + i]));
    }
    assert_int_equal(fixture_jacobian_differs(jac, jb, scale, 25), -1);
    static const int sel[2] = {3, 1}; /* out_v and out_y, with their partners inside */
    assert_int_equal(poly_eval_jacobian_outputs(s, in, 2, sel, oo, jo), 0);
    for (int j = 0; j < 2; j++)
        assert_memory_equal(jo + 5 * j, jac + 5 * sel[j], 5 * sizeof *jo);
    for (int i = 0; i < 5; i++) {
        double a[5], b[5], op[5], om[5];
        memcpy(a, in, sizeof a);
        memcpy(b, in, sizeof b);
        a[i] += h[i];
        b[i] -= h[i];
        poly_eval(s, a, op);
        poly_eval(s, b, om);
        for (int o = 0; o < 5; o++) {
            const double fd = (op[o] - om[o]) / (2 * h[i]);
            if (!(fabs(fd - jac[o * 5 + i]) <= tol * (1 + fabs(fd))))
                fail_msg("ray (%g %g %g %g %g): d out%d / d in%d: %.10g vs fd %.10g", in[0],
                         in[1], in[2], in[3], in[4], o, i, jac[o * 5 + i], fd);
        }
    }
}

static void test_framed_jacobian(void **st)
{
    (void)st;
    poly_system *s = framed_system(13);
    fixture_rng g = {4321};
    const double h[5] = {3e-4, 3e-4, 1e-5, 1e-5, 3e-6};
    for (int r = 0; r < nrays(200); r++) {
        double in[5];
        fixture_ray(&g, in);
        check_jacobian(s, in, h, 2e-6);
    }
    poly_free(s);
    s = symmetric_system();
    const double rays[4][5] = {{0, 0, 0.2, -0.1, 0.55}, {0, 0, -0.3, 0.25, 0.45},
                               {1e-3, -2e-3, 0.1, 0.2, 0.6}, {3, -4, -0.2, 0.15, 0.5}};
    const double hs[5] = {1e-5, 1e-5, 1e-5, 1e-5, 1e-5};
    for (int r = 0; r < 4; r++)
        check_jacobian(s, rays[r], hs, 1e-7);
    poly_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_framed_eval),
        cmocka_unit_test(test_shifted_pairs),
        cmocka_unit_test(test_declined_systems),
        cmocka_unit_test(test_framed_jacobian),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
