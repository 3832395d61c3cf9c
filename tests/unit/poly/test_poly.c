/* Polynomial systems: the builder, scalar / batch / Jacobian evaluation, parts, passage. */
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

static const char *const xy_in[2] = {"x", "y"};
static const char *const xy_out[2] = {"out_x", "out_y"};

static void test_builder_rejects(void **st)
{
    (void)st;
    const char *dup[2] = {"x", "x"};
    const char *space[2] = {"x", "a b"};
    assert_null(poly_new("l", 2, dup, 2, xy_out));
    assert_null(poly_new("l", 2, space, 2, xy_out));
    assert_null(poly_new("l", 0, xy_in, 2, xy_out));
    poly_system *s = poly_new("l", 2, xy_in, 2, xy_out);
    assert_non_null(s);
    int e[2] = {1, 0};
    assert_int_equal(poly_add_term(s, 0, 0, e, 1), -1); /* no part yet */
    assert_int_equal(poly_add_part(s, 0, 5), 0);
    assert_int_equal(poly_add_part(s, 4, 8), -1); /* overlaps */
    assert_int_equal(poly_add_part(s, 5, INFINITY), 1);
    assert_int_equal(poly_add_part(s, -1, 0), -1);
    assert_int_equal(poly_add_term(s, 0, 0, e, 1), 0);
    assert_int_equal(poly_add_term(s, 0, 0, e, 2), -1); /* same monomial twice */
    assert_int_equal(poly_add_term(s, 0, 2, e, 1), -1); /* no such output */
    assert_int_equal(poly_add_term(s, 0, 1, e, NAN), -1);
    int big[2] = {POLY_MAX_DEGREE, 1};
    assert_int_equal(poly_add_term(s, 0, 1, big, 1), -1);
    int neg[2] = {-1, 0};
    assert_int_equal(poly_add_term(s, 0, 1, neg, 1), -1);
    assert_int_equal(poly_add_pass_circle(s, 0, 1, -1), -1);
    assert_int_equal(poly_nterms(s, 0, 0), 1);
    assert_int_equal(poly_nterms(s, 0, 1), 0);
    poly_set_meta(s, "terms", "40");
    poly_set_meta(s, "terms", "41\nx");
    assert_string_equal(poly_get_meta(s, "terms"), "41 x");
    assert_null(poly_get_meta(s, "nope"));
    assert_int_equal(poly_input_index(s, "y"), 1);
    assert_int_equal(poly_output_index(s, "out_z"), -1);
    poly_free(s);
    /* a part away from the axis needs inputs named x and y to select it by */
    const char *uv[2] = {"u", "v"};
    s = poly_new("l", 2, uv, 2, xy_out);
    assert_int_equal(poly_add_part(s, 1, 2), -1);
    poly_free(s);
}

/* out_x = 3 + 2 s_x - s_x^2 s_y^3, out_y = 0.5 s_y with s = (in - offset) / scale:
 * values and derivatives by hand. */
static void test_closed_form(void **st)
{
    (void)st;
    poly_system *s = poly_new("l", 2, xy_in, 2, xy_out);
    poly_set_scaling(s, 0, 1, 2);  /* s_x = (x - 1) / 2 */
    poly_set_scaling(s, 1, -1, 4); /* s_y = (y + 1) / 4 */
    int p = poly_add_part(s, 0, INFINITY);
    int e0[2] = {0, 0}, e1[2] = {1, 0}, e2[2] = {2, 3}, e3[2] = {0, 1};
    assert_int_equal(poly_add_term(s, p, 0, e0, 3), 0);
    assert_int_equal(poly_add_term(s, p, 0, e1, 2), 0);
    assert_int_equal(poly_add_term(s, p, 0, e2, -1), 0);
    assert_int_equal(poly_add_term(s, p, 1, e3, 0.5), 0);
    double in[2] = {5, 7}, out[2], jac[4]; /* s_x = 2, s_y = 2 */
    assert_int_equal(poly_eval(s, in, out), 1);
    assert_true(out[0] == 3 + 4 - 4 * 8);
    assert_true(out[1] == 1);
    poly_eval_jacobian(s, in, out, jac);
    double jb[4];
    poly_eval_jacobian_batch(s, 1, in, jb);
    assert_memory_equal(jac, jb, sizeof jb);
    /* d/dx = (2 - 2 s_x s_y^3) / 2 = (2 - 32) / 2; d/dy = (-3 s_x^2 s_y^2) / 4 = -48 / 4 */
    assert_true(jac[0] == -15);
    assert_true(jac[1] == -12);
    assert_true(jac[2] == 0);
    assert_true(jac[3] == 0.125);
    assert_int_equal(poly_max_degree(s, 0), 5);
    poly_free(s);
}

static double term_norm(const poly_system *s, const double *in, int o)
{
    int p = poly_part_of(s, in);
    double acc = 0;
    for (int t = 0; t < poly_nterms(s, p, o); t++) {
        int e[5];
        double c, m;
        poly_get_term(s, p, o, t, e, &c);
        m = fabs(c);
        for (int i = 0; i < 5; i++) {
            double off, sc;
            poly_get_scaling(s, i, &off, &sc);
            m *= pow(fabs((in[i] - off) / sc), e[i]);
        }
        acc += m;
    }
    return acc;
}

/* poly_eval (poly_fast.c: vectors, another order of additions, fused multiply-adds)
 * against the batch kernel's value: the same to 1e-12 relative to the larger of the value
 * and scale (the size of the output's terms: a sum that cancels to nearly 0 keeps their
 * rounding), inf and nan where it is. */
static void agree(double one, double batch, double scale, int r, int o)
{
    if ((isnan(one) && isnan(batch)) || one == batch)
        return;
    if (!(fabs(one - batch) <= 1e-12 * fmax(fabs(batch), scale)))
        fail_msg("ray %d output %d: poly_eval %.17g, batch %.17g", r, o, one, batch);
}

/* Short batches (a narrower kernel takes a last block of up to 8 rays; its scratch on
 * the stack) give the rows of the long batch outb, pb, jb bit for bit, from an offset
 * that is no multiple of a block. */
static void check_short_batches(const poly_system *s, const double *in, const double *outb,
                                const unsigned char *pb, const double *jb)
{
    static const int counts[] = {1, 2, 3, 4, 5, 7, 8, 9, 31, 33, 41};
    double o[41 * 5], j[41 * 25];
    unsigned char p[41];
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
        const int c = counts[k], at = 17;
        poly_eval_batch(s, (size_t)c, in + 5 * at, o, p);
        poly_eval_jacobian_batch(s, (size_t)c, in + 5 * at, j);
        assert_memory_equal(o, outb + 5 * at, (size_t)c * 5 * sizeof *o);
        assert_memory_equal(p, pb + at, (size_t)c);
        assert_memory_equal(j, jb + 25 * at, (size_t)c * 25 * sizeof *j);
    }
}

static void check_batch(int nparts)
{
    poly_system *s = fixture_system(40, 11, nparts, 7 + (uint64_t)nparts);
    for (int p = 0; p < nparts; p++)
        for (int o = 0; o < 5; o++)
            assert_int_equal(poly_nterms(s, p, o), 40);
    assert_int_equal(poly_max_degree(s, 4), 11);
    int n = nrays(2000) + 3; /* not a multiple of the block size */
    double *in = malloc((size_t)n * 5 * sizeof(double));
    double *out = malloc((size_t)n * 5 * sizeof(double));
    unsigned char *pass = malloc((size_t)n);
    fixture_rng g = {99};
    for (int r = 0; r < n; r++)
        fixture_ray(&g, in + r * 5);
    double *jac = malloc((size_t)n * 25 * sizeof(double));
    poly_eval_batch(s, (size_t)n, in, out, pass);
    poly_eval_jacobian_batch(s, (size_t)n, in, jac);
    double jscale[25];
    fixture_jacobian_scale(jac, (size_t)n, 25, jscale);
    for (int r = 0; r < n; r++) {
        double one[5], naive[5], o2[5], j1[25];
        int ps = poly_eval(s, in + r * 5, one);
        /* the Jacobian's outputs are the batch's bits; batch and one-ray derivatives to
         * 1e-12 relative (the batch's sums fused) */
        assert_int_equal(poly_eval_jacobian(s, in + r * 5, o2, j1), ps);
        assert_memory_equal(o2, out + r * 5, sizeof o2);
        assert_int_equal(fixture_jacobian_differs(j1, jac + (size_t)r * 25, jscale, 25), -1);
        fixture_naive(s, in + r * 5, naive);
        assert_int_equal(ps, pass[r]);
        for (int o = 0; o < 5; o++) {
            const double norm = term_norm(s, in + r * 5, o);
            agree(one[o], out[r * 5 + o], norm, r, o); /* poly_fast: to rounding */
            double tol = 1e-13 * norm + 1e-300;
            if (fabs(one[o] - naive[o]) > tol)
                fail_msg("ray %d output %d: %.17g vs naive %.17g", r, o, one[o], naive[o]);
        }
    }
    check_short_batches(s, in, out, pass, jac);
    free(in);
    free(out);
    free(pass);
    free(jac);
    poly_free(s);
}

static void test_batch_one_part(void **st)
{
    (void)st;
    check_batch(1);
}

static void test_batch_three_parts(void **st)
{
    (void)st;
    check_batch(3);
}

static void test_jacobian_fd(void **st)
{
    (void)st;
    poly_system *s = fixture_system(40, 11, 1, 5);
    fixture_rng g = {1234};
    for (int r = 0; r < nrays(200); r++) {
        double in[5], out[5], jac[25];
        fixture_ray(&g, in);
        poly_eval_jacobian(s, in, out, jac);
        for (int i = 0; i < 5; i++) {
            double lo, hi;
            poly_get_domain(s, i, &lo, &hi);
            double h = 1e-5 * (hi - lo), a[5], b[5], op[5], om[5];
            memcpy(a, in, sizeof a);
            memcpy(b, in, sizeof b);
            a[i] += h;
            b[i] -= h;
            poly_eval(s, a, op);
            poly_eval(s, b, om);
            for (int o = 0; o < 5; o++) {
                double fd = (op[o] - om[o]) / (2 * h);
                /* central differences: O(h^2) truncation plus rounding of the outputs */
                double tol = 1e-6 * (fabs(fd) + term_norm(s, in, o) / (hi - lo));
                if (fabs(fd - jac[o * 5 + i]) > tol)
                    fail_msg("d out%d / d in%d: %.10g vs fd %.10g", o, i, jac[o * 5 + i], fd);
            }
        }
    }
    poly_free(s);
}

/* The meridional frame's Jacobian on the axis (x = y = 0), where the frame's angle is
 * undefined, against central differences of poly_eval across it, on a system that is
 * exactly rotationally symmetric (so the outputs are smooth there): in the frame
 * out_x = A r + B u', out_y = B v' with A = 0.7 + 0.3 r^2, B = 1.2 + 0.05 r^2 + 0.4 r u',
 * out_eta = 0.9 - 0.01 r^2 - 0.2 (u'^2 + v'^2) + 0.3 r u'; out_u, out_v outside the frame
 * (1/lambda^2 as lens-fit writes it). Before the limit was taken there, d out_y / dy came
 * out 0.7 short (and d out_eta / dy missing 0.3 v). Also just off the axis, and the
 * batch Jacobian the same to 1e-12 relative (fixture_jacobian_differs). */
static void test_jacobian_axis(void **st)
{
    (void)st;
    poly_system *s = poly_new("sym", 5, fixture_inputs, 5, fixture_outputs);
    assert_int_equal(poly_add_part(s, 0, INFINITY), 0);
    static const struct { int o, e[5]; double c; } terms[] = {
        {0, {1, 0, 0, 0, 0}, 0.7},  {0, {3, 0, 0, 0, 0}, 0.3},  {0, {0, 0, 1, 0, 0}, 1.2},
        {0, {2, 0, 1, 0, 0}, 0.05}, {0, {1, 0, 2, 0, 0}, 0.4},  {1, {0, 0, 0, 1, 0}, 1.2},
        {1, {2, 0, 0, 1, 0}, 0.05}, {1, {1, 0, 1, 1, 0}, 0.4},  {4, {0, 0, 0, 0, 0}, 0.9},
        {4, {2, 0, 0, 0, 0}, -0.01}, {4, {0, 0, 2, 0, 0}, -0.2}, {4, {0, 0, 0, 2, 0}, -0.2},
        {4, {1, 0, 1, 0, 0}, 0.3},  {4, {0, 0, 0, 0, 1}, 0.1},  {2, {1, 0, 0, 0, 0}, 0.02},
        {2, {0, 0, 1, 0, 1}, 0.9},  {3, {0, 1, 0, 0, 0}, 0.02}, {3, {0, 0, 0, 1, 1}, 0.9}};
    for (size_t t = 0; t < sizeof terms / sizeof terms[0]; t++)
        assert_int_equal(poly_add_term(s, 0, terms[t].o, terms[t].e, terms[t].c), 0);
    assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
    assert_int_equal(poly_set_output_plain(s, 2, 1), 0);
    assert_int_equal(poly_set_output_plain(s, 3, 1), 0);
    assert_int_equal(poly_set_transform(s, 4, POLY_XFORM_INVERSE_SQUARE), 0);
    poly_set_scaling(s, 0, 0, 2);
    poly_set_scaling(s, 2, 0, 0.5); /* u', v' alike: the symmetry holds in s too */
    poly_set_scaling(s, 3, 0, 0.5);
    poly_set_scaling(s, 4, 4.25, 2.0);
    const double rays[3][5] = {{0, 0, 0.2, -0.1, 0.55}, {0, 0, -0.3, 0.25, 0.45},
                               {1e-3, -2e-3, 0.1, 0.2, 0.6}};
    double jb[3 * 25], jscale[25];
    poly_eval_jacobian_batch(s, 3, &rays[0][0], jb);
    fixture_jacobian_scale(jb, 3, 25, jscale);
    for (int r = 0; r < 3; r++) {
        double out[5], jac[25];
        poly_eval_jacobian(s, rays[r], out, jac);
        assert_int_equal(fixture_jacobian_differs(jac, jb + 25 * r, jscale, 25), -1);
        for (int i = 0; i < 5; i++) {
            const double h = 1e-5;
            double a[5], b[5], op[5], om[5];
            memcpy(a, rays[r], sizeof a);
            memcpy(b, rays[r], sizeof b);
            a[i] += h;
            b[i] -= h;
            poly_eval(s, a, op);
            poly_eval(s, b, om);
            for (int o = 0; o < 5; o++) {
                const double fd = (op[o] - om[o]) / (2 * h);
                if (fabs(fd - jac[o * 5 + i]) > 1e-7 * (1 + fabs(fd)))
                    fail_msg("ray %d: d out%d / d in%d: %.10g vs fd %.10g", r, o, i,
                             jac[o * 5 + i], fd);
            }
        }
    }
    poly_free(s);
}

/* Part 0 says 1, part 1 says 2, on [0, 5) and [5, 10); beyond 10 the nearest part. */
static void test_part_selection(void **st)
{
    (void)st;
    poly_system *s = poly_new("l", 2, xy_in, 2, xy_out);
    int e0[2] = {0, 0};
    assert_int_equal(poly_add_part(s, 0, 5), 0);
    assert_int_equal(poly_add_part(s, 5, 10), 1);
    for (int p = 0; p < 2; p++)
        for (int o = 0; o < 2; o++)
            poly_add_term(s, p, o, e0, p + 1);
    struct {
        double x, y, want;
    } c[] = {{0, 0, 1}, {3, 3.9, 1}, {3, 4, 2}, {-6, 8, 2}, {30, 40, 2}, {0, -4.999, 1}};
    double in[8 * 2], outb[8 * 2];
    int n = (int)(sizeof c / sizeof c[0]);
    for (int k = 0; k < n; k++) {
        double out[2];
        in[2 * k] = c[k].x;
        in[2 * k + 1] = c[k].y;
        poly_eval(s, in + 2 * k, out);
        assert_true(out[0] == c[k].want && out[1] == c[k].want);
    }
    poly_eval_batch(s, (size_t)n, in, outb, NULL);
    for (int k = 0; k < n; k++)
        assert_true(outb[2 * k] == c[k].want);
    poly_free(s);
}

/* out = (x, y) unscaled, a circle of radius 2 on (out_x, out_y). */
static void test_pass_and_domain(void **st)
{
    (void)st;
    poly_system *s = poly_new("l", 2, xy_in, 2, xy_out);
    int p = poly_add_part(s, 0, INFINITY);
    int ex[2] = {1, 0}, ey[2] = {0, 1};
    poly_add_term(s, p, 0, ex, 1);
    poly_add_term(s, p, 1, ey, 1);
    assert_int_equal(poly_add_pass_circle(s, 0, 1, 2), 0);
    poly_set_domain(s, 0, -1, 1);
    double a[2] = {1, 1}, b[2] = {2, 1}, c[2] = {NAN, 0}, out[2];
    assert_int_equal(poly_eval(s, a, out), 1);
    assert_int_equal(poly_eval(s, b, out), 0);
    assert_int_equal(poly_eval(s, c, out), 0);
    assert_true(isnan(out[0]));
    assert_int_equal(poly_in_domain(s, a), 1);
    assert_int_equal(poly_in_domain(s, b), 0);
    assert_int_equal(poly_in_domain(s, c), 0);
    double in4[6] = {1, 1, 2, 1, 0, 1.9}, out4[6];
    unsigned char ps[3];
    poly_eval_batch(s, 3, in4, out4, ps);
    assert_int_equal(ps[0], 1);
    assert_int_equal(ps[1], 0);
    assert_int_equal(ps[2], 1);
    poly_free(s);
}

/* The batch kernel applies the frame and transforms itself (poly_eval_kernel.h); the
 * scalar path applies them ray by ray in poly_frame.c: two implementations of the same
 * expressions, which must agree bit for bit, for each layout lens-fit can write, with
 * two parts, a pass circle, a count that leaves a partial block, rays on the axis and
 * rays whose 1/lambda^2 is infinite (they must not pass). */
/* poly_eval_batch_outputs against poly_eval_batch's outb and pb on the same n rays:
 * the columns asked for and the pass flags bit for bit, with and without the pass test,
 * five columns (the kernel's row transpose) or three, none; bad selections refused. And
 * poly_eval_jacobian_batch_outputs and poly_eval_jacobian_outputs against the whole
 * Jacobian jb (of a turned pair one output alone too, whose derivative needs its
 * partner's; jscale: its entries' sizes, fixture_jacobian_scale). */
static void check_selected_outputs(const poly_system *s, int n, const double *in,
                                   const double *outb, const unsigned char *pb,
                                   const double *jb, const double *jscale)
{
    static const int sel5[5] = {4, 3, 2, 1, 0}, sel3[3] = {4, 0, 1}, bad[2] = {0, 5};
    double *o = malloc((size_t)n * 5 * sizeof *o);
    unsigned char *p = malloc((size_t)n);
    assert_non_null(o);
    assert_non_null(p);
    for (int k = 0; k < 4; k++) {
        const int ns = k < 2 ? 5 : k == 2 ? 3 : 0;
        const int *sel = k < 2 ? sel5 : sel3;
        memset(p, 7, (size_t)n);
        assert_int_equal(poly_eval_batch_outputs(s, (size_t)n, in, ns, sel, o, k == 1 ? NULL : p), 0);
        for (int r = 0; r < n; r++) {
            for (int j = 0; j < ns; j++)
                assert_memory_equal(&o[r * ns + j], &outb[r * 5 + sel[j]], sizeof *o);
            assert_int_equal(p[r], k == 1 ? 7 : pb[r]);
        }
    }
    assert_int_equal(poly_eval_batch_outputs(s, 1, in, 2, bad, o, p), -1);
    assert_int_equal(poly_eval_batch_outputs(s, 1, in, -1, sel3, o, p), -1);
    double *js = malloc((size_t)n * 15 * sizeof *js);
    assert_non_null(js);
    static const int sel1[1] = {1};
    for (int k = 0; k < 2; k++) {
        const int ns = k ? 1 : 3, *sel = k ? sel1 : sel3;
        assert_int_equal(poly_eval_jacobian_batch_outputs(s, (size_t)n, in, ns, sel, js), 0);
        for (int r = 0; r < n; r++)
            for (int j = 0; j < ns; j++)
                assert_memory_equal(js + (r * ns + j) * 5, jb + r * 25 + sel[j] * 5,
                                    5 * sizeof *js);
    }
    assert_int_equal(poly_eval_jacobian_batch_outputs(s, 1, in, 2, bad, js), -1);
    for (int r = 0; r < n; r++) { /* one ray: poly_eval_jacobian_outputs, the value's bits,
                                   * the derivatives to 1e-12 relative (the batch's fused) */
        double v1[1], j1[5];
        assert_int_equal(poly_eval_jacobian_outputs(s, in + 5 * r, 1, sel1, v1, j1), 0);
        assert_memory_equal(v1, outb + 5 * r + 1, sizeof v1);
        assert_int_equal(fixture_jacobian_differs(j1, jb + r * 25 + 5, jscale + 5, 5), -1);
    }
    assert_int_equal(poly_eval_jacobian_outputs(s, in, 2, bad, js, js), -1);
    free(js);
    free(o);
    free(p);
}

static void test_batch_frame_layouts(void **st)
{
    (void)st;
    enum { N = 303 }; /* more than one chunk of the batch Jacobian */
    double *in = malloc(N * 5 * sizeof *in), *outb = malloc(N * 5 * sizeof *outb);
    double *jb = malloc(N * 25 * sizeof *jb);
    unsigned char pb[N];
    for (int layout = 0; layout < 4; layout++) {
        poly_system *s = fixture_system(30, 9, 2, 40 + (uint64_t)layout);
        assert_non_null(s);
        if (layout != 2) /* 2: the transform without the frame */
            assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
        if (layout == 0 || layout == 3) { /* lens-fit's default: out_u, out_v outside */
            assert_int_equal(poly_set_output_plain(s, 2, 1), 0);
            assert_int_equal(poly_set_output_plain(s, 3, 1), 0);
        }
        if (layout != 1) {
            assert_int_equal(poly_set_transform(s, 4, POLY_XFORM_INVERSE_SQUARE), 0);
            poly_set_scaling(s, 4, 4.25, 2.0);
        }
        if (layout == 3)
            assert_int_equal(poly_add_pass_circle(s, 0, 1, 50), 0);
        fixture_rng g = {90 + (uint64_t)layout};
        for (int r = 0; r < N; r++)
            fixture_ray(&g, in + r * 5);
        in[0] = in[1] = 0;         /* on the axis */
        in[5 * 7 + 1] = 0;         /* on +x: c = 1 exactly */
        in[5 * 9 + 4] = 0;         /* 1/lambda^2 infinite */
        in[5 * 300 + 4] = 0;       /* the same in the last, partial block */
        poly_eval_batch(s, N, in, outb, pb);
        poly_eval_jacobian_batch(s, N, in, jb);
        double jscale[25];
        fixture_jacobian_scale(jb, N, 25, jscale);
        int npass = 0;
        double range[5] = {0}; /* the size of each output over the rays */
        for (int r = 0; r < N; r++)
            for (int k = 0; k < 5; k++)
                if (isfinite(outb[r * 5 + k]))
                    range[k] = fmax(range[k], fabs(outb[r * 5 + k]));
        for (int r = 0; r < N; r++) {
            double o[5], oj[5], j1[25];
            int p = poly_eval(s, in + r * 5, o);
            for (int k = 0; k < 5; k++)
                agree(o[k], outb[r * 5 + k], range[k], r, k);
            assert_int_equal(p, pb[r]);
            /* the batch Jacobian (cores through the kernel, chunk by chunk) is the
             * scalar's to 1e-12 relative (its sums fused); the values' bits */
            assert_int_equal(poly_eval_jacobian(s, in + r * 5, oj, j1), p);
            assert_memory_equal(oj, outb + r * 5, sizeof oj);
            assert_int_equal(fixture_jacobian_differs(j1, jb + (size_t)r * 25, jscale, 25), -1);
            npass += p;
        }
        if (layout != 1)
            assert_int_equal(pb[9], 0);
        assert_true(npass > N / 2);
        check_selected_outputs(s, N, in, outb, pb, jb, jscale);
        check_short_batches(s, in, outb, pb, jb);
        poly_free(s);
    }
    free(in);
    free(outb);
    free(jb);
}

/* Rows of more than 32 columns (a Jacobian of 9 outputs: 45) go out of the kernel a
 * whole block at a time: the batch Jacobian, with the frame and without, gives one
 * ray's Jacobian to 1e-12 relative (fixture_jacobian_differs), and the bits of calls
 * that start at other rays and end in a partial block. */
static void test_jacobian_wide_rows(void **st)
{
    (void)st;
    enum { N = 203, NO = 9, NJ = 5 * NO };
    static const char *const names[NO] = {"out_x", "out_y", "out_u", "out_v", "out_eta",
                                           "a",     "b",     "c",     "d"};
    double *in = malloc(N * 5 * sizeof *in), *jb = malloc(N * NJ * sizeof *jb);
    double *jp = malloc(N * NJ * sizeof *jp);
    assert_true(in && jb && jp);
    fixture_rng g = {55};
    for (int r = 0; r < N; r++)
        fixture_ray(&g, in + r * 5);
    for (int framed = 0; framed < 2; framed++) {
        poly_system *s = poly_new("wide", 5, fixture_inputs, NO, names);
        assert_int_equal(poly_add_part(s, 0, INFINITY), 0);
        for (int i = 0; i < 5; i++)
            poly_set_scaling(s, i, i == 4 ? 0.55 : 0, i < 2 ? 18 : i < 4 ? 0.6 : 0.15);
        for (int o = 0; o < NO; o++)
            for (int t = 0; t < 25; t++) {
                int e[5];
                fixture_monomial(&g, 7, o == 0 || o == 2, o == 1 || o == 3, e);
                fixture_add(s, 0, o, e, &g);
            }
        if (framed)
            assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
        poly_eval_jacobian_batch(s, N, in, jb);
        double jscale[NJ];
        fixture_jacobian_scale(jb, N, NJ, jscale);
        for (int r = 0; r < N; r++) {
            double o[NO], j1[NJ];
            poly_eval_jacobian(s, in + r * 5, o, j1);
            assert_int_equal(fixture_jacobian_differs(j1, jb + (size_t)r * NJ, jscale, NJ), -1);
        }
        poly_eval_jacobian_batch(s, N - 7, in + 7 * 5, jp);
        assert_memory_equal(jp, jb + 7 * NJ, (size_t)(N - 7) * NJ * sizeof *jp);
        poly_free(s);
    }
    free(in);
    free(jb);
    free(jp);
}

/* A monomial that is inf or nan reaches only the outputs with a term on it, in
 * poly_eval as in the batch kernel (poly_fast.c evaluates such a ray again by the plan):
 * out_x depends on x and y alone, out_y on u and v, out_u is a constant. */
static void test_scalar_nonfinite(void **st)
{
    (void)st;
    poly_system *s = poly_new("nf", 5, fixture_inputs, 5, fixture_outputs);
    assert_int_equal(poly_add_part(s, 0, INFINITY), 0);
    static const struct { int o, e[5]; double c; } terms[] = {
        {0, {0, 0, 0, 0, 0}, 1},   {0, {1, 0, 0, 0, 0}, 2}, {0, {3, 1, 0, 0, 0}, 0.5},
        {0, {2, 2, 0, 0, 0}, -0.25}, {1, {0, 0, 2, 1, 0}, 1}, {1, {0, 0, 1, 0, 0}, 3},
        {2, {0, 0, 0, 0, 0}, 4}};
    for (size_t t = 0; t < sizeof terms / sizeof terms[0]; t++)
        assert_int_equal(poly_add_term(s, 0, terms[t].o, terms[t].e, terms[t].c), 0);
    const double x = 0.3, y = -0.7;
    const double rays[4][5] = {{x, y, 0.2, 0.1, 0.5}, {x, y, NAN, 0.1, 0.5},
                               {x, y, 1e200, 0.1, 0.5}, {x, y, 0.2, -INFINITY, 0.5}};
    double ob[4 * 5];
    unsigned char pb[4];
    poly_eval_batch(s, 4, &rays[0][0], ob, pb);
    for (int r = 0; r < 4; r++) {
        double o[5];
        assert_int_equal(poly_eval(s, rays[r], o), pb[r]);
        assert_int_equal(pb[r], r == 0);
        for (int k = 0; k < 5; k++)
            agree(o[k], ob[r * 5 + k], 0, r, k);
        const double want = 1 + 2 * x + 0.5 * x * x * x * y - 0.25 * x * x * y * y;
        assert_true(fabs(o[0] - want) <= 1e-15 * fabs(want));
        assert_true(isfinite(o[0]) && o[2] == 4);
        assert_true(r == 0 ? isfinite(o[1]) : !isfinite(o[1]));
    }
    poly_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_builder_rejects), cmocka_unit_test(test_closed_form),
        cmocka_unit_test(test_batch_one_part),  cmocka_unit_test(test_batch_three_parts),
        cmocka_unit_test(test_jacobian_fd), cmocka_unit_test(test_jacobian_axis),     cmocka_unit_test(test_part_selection),
        cmocka_unit_test(test_pass_and_domain), cmocka_unit_test(test_batch_frame_layouts),
        cmocka_unit_test(test_scalar_nonfinite), cmocka_unit_test(test_jacobian_wide_rows),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
