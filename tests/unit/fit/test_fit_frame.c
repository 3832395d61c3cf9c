/* The meridional frame and input transforms (poly_frame.c, fit_frame.c): a planted
 * rotation-equivariant function recovered exactly in the frame, rotation equivariance
 * of a fitted system, 1/lambda^2 terms recovered in two terms, the Jacobian against
 * finite differences, scalar = batch (to rounding: poly_fast.c), a written file reading back to
 * the same bits. */
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

static const char *IN5[] = {"x", "y", "u", "v", "lambda"};
static const char *OUT5[] = {"out_x", "out_y", "out_u", "out_v", "out_eta"};

/* A planted "lens" in its meridional frame (r, u', v'): exponents of (r, u', v').
 * out_x' and out_u' are even in v' and out_y', out_v' odd (the mirror symmetry of the
 * meridional plane); out_eta is a scalar. In the lens frame the outputs are these
 * rotated back by the ray's angle: a rotation-equivariant function by construction. */
typedef struct {
    int e[3];
    double c;
} term;
static const term PX[] = {{{1, 0, 0}, -1.2}, {{0, 1, 0}, 30.0}, {{3, 0, 0}, 2e-3},
                          {{1, 2, 0}, 4.0},  {{1, 0, 2}, 3.0},  {{2, 1, 0}, 0.05}};
static const term PY[] = {{{0, 0, 1}, 30.0}, {{2, 0, 1}, 0.04}, {{1, 1, 1}, 2.0}};
static const term PU[] = {{{1, 0, 0}, 0.02}, {{0, 1, 0}, 0.9}, {{2, 1, 0}, 1e-3}};
static const term PV[] = {{{0, 0, 1}, 0.9}, {{1, 1, 1}, 0.3}};
static const term PE[] = {{{0, 0, 0}, 0.8}, {{2, 0, 0}, -1e-3}, {{0, 2, 0}, -0.5}};
static const term *PL[5] = {PX, PY, PU, PV, PE};
static const int NPL[5] = {6, 3, 3, 2, 3};

static double eval_terms(const term *t, int n, const double *q)
{
    double s = 0;
    for (int i = 0; i < n; i++) {
        double m = t[i].c;
        for (int v = 0; v < 3; v++)
            m *= pow(q[v], t[i].e[v]);
        s += m;
    }
    return s;
}

/* The planted outputs at a ray (x, y, u, v); lambda plays no part. */
static void planted(const double *in, double *out)
{
    double r = hypot(in[0], in[1]), a = atan2(in[1], in[0]);
    double c = cos(a), s = sin(a);
    double q[3] = {r, c * in[2] + s * in[3], -s * in[2] + c * in[3]};
    double f[5];
    for (int o = 0; o < 5; o++)
        f[o] = eval_terms(PL[o], NPL[o], q);
    out[0] = c * f[0] - s * f[1];
    out[1] = s * f[0] + c * f[1];
    out[2] = c * f[2] - s * f[3];
    out[3] = s * f[2] + c * f[3];
    out[4] = f[4];
}

static void random_ray(uint64_t *sd, double *q)
{
    q[0] = 12 * urand(sd);
    q[1] = 12 * urand(sd);
    q[2] = 0.3 * urand(sd);
    q[3] = 0.3 * urand(sd);
    q[4] = 0.55 + 0.15 * urand(sd);
}

static poly_system *fit_planted(size_t n, int nout)
{
    double *in = malloc(n * 5 * sizeof *in), *out = malloc(n * 5 * sizeof *out);
    double *o = malloc(n * (size_t)nout * sizeof *o);
    uint64_t sd = 7;
    for (size_t i = 0; i < n; i++) {
        double full[5];
        random_ray(&sd, in + i * 5);
        planted(in + i * 5, full);
        memcpy(o + i * (size_t)nout, full, (size_t)nout * sizeof *o);
    }
    fit_options opt;
    fit_options_default(&opt);
    opt.max_terms = 8;
    opt.max_degree = 5;
    opt.frame = POLY_FRAME_MERIDIONAL;
    lens_err err;
    /* lambda is an input here (constant-free: it varies) but no output needs it */
    poly_system *sys = fit_system("planted", 5, IN5, nout, OUT5, n, in, o, &opt, &err);
    if (!sys)
        fprintf(stderr, "%s\n", err.msg);
    free(in);
    free(out);
    free(o);
    return sys;
}

/* The fitted terms, in raw units, are the planted ones: exponents of x are those of r,
 * of u and v those of u' and v', and y never appears (it is 0 in the frame). */
static void test_planted_frame_recovered(void **state)
{
    (void)state;
    poly_system *sys = fit_planted(1500, 5);
    assert_non_null(sys);
    assert_int_equal(poly_get_frame(sys), POLY_FRAME_MERIDIONAL);
    double off[5], sc[5];
    for (int i = 0; i < 5; i++)
        poly_get_scaling(sys, i, &off[i], &sc[i]);
    assert_true(off[0] == 0 && off[2] == 0 && off[3] == 0);
    const int vmap[3] = {0, 2, 3};
    for (int o = 0; o < 5; o++) {
        int nt = poly_nterms(sys, 0, o);
        /* terms whose coefficient is dust (below 1e-9 of the output) may be picked up
         * after the planted ones are all in; the planted ones must all be there */
        double size = 0;
        for (int k = 0; k < NPL[o]; k++) {
            double m = fabs(PL[o][k].c);
            for (int v = 0; v < 3; v++)
                m *= pow(sc[vmap[v]], PL[o][k].e[v]);
            size += m;
        }
        int found = 0;
        for (int t = 0; t < nt; t++) {
            int e[5];
            double c;
            poly_get_term(sys, 0, o, t, e, &c);
            assert_int_equal(e[1], 0);
            assert_int_equal(e[4], 0);
            int hit = -1;
            for (int k = 0; k < NPL[o]; k++)
                if (e[0] == PL[o][k].e[0] && e[2] == PL[o][k].e[1] && e[3] == PL[o][k].e[2])
                    hit = k;
            double raw = c / (pow(sc[0], e[0]) * pow(sc[2], e[2]) * pow(sc[3], e[3]));
            if (hit < 0) {
                assert_true(fabs(c) <= 1e-9 * size);
                continue;
            }
            found++;
            assert_true(fabs(raw - PL[o][hit].c) <= 1e-7 * fabs(PL[o][hit].c));
        }
        assert_int_equal(found, NPL[o]);
    }
    /* and the system is the planted function at new rays */
    uint64_t sd = 99;
    for (int i = 0; i < 200; i++) {
        double q[5], a[5], b[5];
        random_ray(&sd, q);
        poly_eval(sys, q, a);
        planted(q, b);
        for (int o = 0; o < 5; o++)
            assert_true(fabs(a[o] - b[o]) <= 1e-9 * (1 + fabs(b[o])));
    }
    poly_free(sys);
}

/* Rotating the ray about the axis rotates the position and direction outputs and
 * leaves out_eta alone: exact in real numbers, to rounding in doubles. */
static void test_rotation_equivariance(void **state)
{
    (void)state;
    poly_system *sys = fit_planted(800, 5);
    assert_non_null(sys);
    uint64_t sd = 3;
    for (int i = 0; i < 300; i++) {
        double q[5], p[5], a[5], b[5];
        random_ray(&sd, q);
        double ang = M_PI * urand(&sd), c = cos(ang), s = sin(ang);
        memcpy(p, q, sizeof p);
        p[0] = c * q[0] - s * q[1];
        p[1] = s * q[0] + c * q[1];
        p[2] = c * q[2] - s * q[3];
        p[3] = s * q[2] + c * q[3];
        poly_eval(sys, q, a);
        poly_eval(sys, p, b);
        double ra[5] = {c * a[0] - s * a[1], s * a[0] + c * a[1], c * a[2] - s * a[3],
                        s * a[2] + c * a[3], a[4]};
        for (int o = 0; o < 5; o++)
            assert_true(fabs(ra[o] - b[o]) <= 1e-12 * (1 + fabs(b[o])));
    }
    poly_free(sys);
}

/* f = 3 + 2 / lambda^2 is linear in 1/lambda^2: with the transform, two terms of
 * degree 1 reproduce it exactly; without, a polynomial in lambda cannot. */
static void test_inverse_square_lambda(void **state)
{
    (void)state;
    const char *in1[] = {"lambda"}, *o1[] = {"f"};
    size_t n = 200;
    double in[200], out[200];
    for (size_t i = 0; i < n; i++) {
        in[i] = 0.4 + 0.3 * (double)i / (double)(n - 1);
        out[i] = 3 + 2 / (in[i] * in[i]);
    }
    fit_options opt;
    fit_options_default(&opt);
    opt.max_terms = 2;
    opt.max_degree = 3;
    opt.lambda_transform = POLY_XFORM_INVERSE_SQUARE;
    lens_err err;
    poly_system *sys = fit_system("l", 1, in1, 1, o1, n, in, out, &opt, &err);
    assert_non_null(sys);
    assert_int_equal(poly_get_transform(sys, 0), POLY_XFORM_INVERSE_SQUARE);
    assert_int_equal(poly_max_degree(sys, 0), 1);
    double lo, hi;
    poly_get_domain(sys, 0, &lo, &hi); /* the domain stays in raw units */
    assert_true(lo == 0.4 && hi == 0.7);
    double worst = 0, f;
    for (int k = 0; k < 50; k++) {
        double l = 0.41 + 0.0057 * k;
        poly_eval(sys, &l, &f);
        worst = fmax(worst, fabs(f - (3 + 2 / (l * l))));
    }
    assert_true(worst <= 1e-12 * 15);
    poly_free(sys);
    opt.lambda_transform = POLY_XFORM_IDENTITY;
    sys = fit_system("l", 1, in1, 1, o1, n, in, out, &opt, &err);
    assert_non_null(sys);
    worst = 0;
    for (int k = 0; k < 50; k++) {
        double l = 0.41 + 0.0057 * k;
        poly_eval(sys, &l, &f);
        worst = fmax(worst, fabs(f - (3 + 2 / (l * l))));
    }
    assert_true(worst > 1e-6);
    poly_free(sys);
}

/* A system with every kind of step: the frame, 1/lambda^2, outputs outside the frame. */
static poly_system *fit_mixed(void)
{
    size_t n = 1200;
    double *in = malloc(n * 5 * sizeof *in), *out = malloc(n * 5 * sizeof *out);
    uint64_t sd = 11;
    for (size_t i = 0; i < n; i++) {
        double *q = in + i * 5;
        random_ray(&sd, q);
        planted(q, out + i * 5);
        double g = 1 / (q[4] * q[4]);
        out[i * 5] *= 1 + 0.01 * g;
        out[i * 5 + 1] *= 1 + 0.01 * g;
        /* out_u, out_v: not rotating with the ray, fitted outside the frame */
        out[i * 5 + 2] = 0.1 * q[0] + 0.5 * q[2] + 0.02 * q[1] * q[3] * g;
        out[i * 5 + 3] = 0.2 * q[1] - 0.4 * q[3] + 0.01 * q[0] * q[0] * q[3];
    }
    fit_options opt;
    fit_options_default(&opt);
    opt.max_terms = 12;
    opt.max_degree = 6;
    opt.frame = POLY_FRAME_MERIDIONAL;
    opt.lambda_transform = POLY_XFORM_INVERSE_SQUARE;
    const unsigned char plain[5] = {0, 0, 1, 1, 0};
    opt.frame_plain = plain;
    lens_err err;
    poly_system *sys = fit_system("mixed", 5, IN5, 5, OUT5, n, in, out, &opt, &err);
    if (!sys)
        fprintf(stderr, "%s\n", err.msg);
    free(in);
    free(out);
    return sys;
}

static void test_jacobian_finite_differences(void **state)
{
    (void)state;
    poly_system *sys = fit_mixed();
    assert_non_null(sys);
    assert_int_equal(poly_get_output_plain(sys, 2), 1);
    uint64_t sd = 5;
    for (int i = 0; i < 100; i++) {
        double q[5], out[5], jac[25], o0[5];
        random_ray(&sd, q);
        poly_eval_jacobian(sys, q, out, jac);
        poly_eval(sys, q, o0);
        for (int o = 0; o < 5; o++) /* poly_eval (vectors) agrees to rounding (mm, 1) */
            assert_true(fabs(out[o] - o0[o]) <= 1e-12 * fmax(fabs(o0[o]), 1));
        for (int j = 0; j < 5; j++) {
            double h = 1e-5 * (j < 2 ? 10 : j < 4 ? 0.3 : 0.5);
            double qp[5], qm[5], op[5], om[5];
            memcpy(qp, q, sizeof qp);
            memcpy(qm, q, sizeof qm);
            qp[j] += h;
            qm[j] -= h;
            poly_eval(sys, qp, op);
            poly_eval(sys, qm, om);
            for (int o = 0; o < 5; o++) {
                double fd = (op[o] - om[o]) / (2 * h), an = jac[o * 5 + j];
                assert_true(fabs(fd - an) <= 1e-6 * (1 + fabs(an)));
            }
        }
    }
    poly_free(sys);
}

static void test_batch_and_file_bit_identical(void **state)
{
    (void)state;
    poly_system *sys = fit_mixed();
    assert_non_null(sys);
    enum { N = 700 };
    double *in = malloc(N * 5 * sizeof *in), *ob = malloc(N * 5 * sizeof *ob);
    double *ob2 = malloc(N * 5 * sizeof *ob2);
    unsigned char pb[N], pb2[N];
    uint64_t sd = 17;
    for (int i = 0; i < N; i++)
        random_ray(&sd, in + i * 5);
    in[0] = in[1] = 0; /* on the axis */
    poly_eval_batch(sys, N, in, ob, pb);
    for (int i = 0; i < N; i++) {
        double o[5];
        int p = poly_eval(sys, in + i * 5, o);
        for (int k = 0; k < 5; k++) { /* poly_eval (vectors) agrees to rounding */
            const double b = ob[i * 5 + k];
            assert_true(o[k] == b || fabs(o[k] - b) <= 1e-12 * fmax(fabs(b), 1));
        }
        assert_int_equal(p, pb[i]);
    }
    /* written and read back: the same file and the same bits */
    char *text = NULL, *text2 = NULL;
    size_t len = 0, len2 = 0;
    FILE *f = open_memstream(&text, &len);
    assert_int_equal(poly_write(f, sys), 0);
    fclose(f);
    assert_non_null(strstr(text, "\nframe meridional except out_u out_v\n"));
    assert_non_null(strstr(text, "\ntransform lambda inverse-square\n"));
    f = fmemopen(text, len, "r");
    poly_system *back = NULL;
    lens_err err;
    assert_int_equal(poly_read_stream(f, "mem", &back, &err), 0);
    fclose(f);
    poly_eval_batch(back, N, in, ob2, pb2);
    assert_memory_equal(ob, ob2, N * 5 * sizeof *ob);
    assert_memory_equal(pb, pb2, N);
    f = open_memstream(&text2, &len2);
    poly_write(f, back);
    fclose(f);
    assert_int_equal(len, len2);
    assert_memory_equal(text, text2, len);
    poly_free(back);
    free(text);
    free(text2);
    free(in);
    free(ob);
    free(ob2);
    poly_free(sys);
}

/* A frame the file cannot hold is refused: x without y, an output pair cut in two. */
static void test_frame_errors(void **state)
{
    (void)state;
    const char *in3[] = {"x", "u", "v"};
    poly_system *s = poly_new("t", 3, in3, 2, OUT5);
    assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), -1);
    poly_free(s);
    const char *o3[] = {"out_x", "out_y", "out_u"};
    s = poly_new("t", 5, IN5, 3, o3);
    assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), -1); /* out_u without out_v */
    poly_free(s);
    s = poly_new("t", 5, IN5, 5, OUT5);
    assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
    poly_set_output_plain(s, 2, 1);
    assert_int_equal(poly_frame_check(s), -1); /* out_v still in the frame */
    poly_set_output_plain(s, 3, 1);
    assert_int_equal(poly_frame_check(s), 0);
    poly_free(s);
    const char *bad = "lens-poly 1\nlens t\ninputs x y u v\noutputs out_x out_y\n"
                      "frame meridional except out_x\npart 0 inf\nend\n";
    FILE *f = fmemopen((void *)bad, strlen(bad), "r");
    poly_system *r = NULL;
    lens_err err;
    assert_int_not_equal(poly_read_stream(f, "bad", &r, &err), 0);
    assert_non_null(strstr(err.msg, "bad:5:"));
    fclose(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_planted_frame_recovered),
        cmocka_unit_test(test_rotation_equivariance),
        cmocka_unit_test(test_inverse_square_lambda),
        cmocka_unit_test(test_jacobian_finite_differences),
        cmocka_unit_test(test_batch_and_file_bit_identical),
        cmocka_unit_test(test_frame_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
