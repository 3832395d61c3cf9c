/* lens-fit's job without a process: samples drawn from known polynomials (a few terms,
 * degree <= 3) are fitted back exactly, at points the fit never saw; blocked rows are
 * counted and left out; the one wavelength of samples without lambda among the inputs
 * is recorded; and a tolerance naming an output that is not fitted is refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sparselens/fit_run.h"

static void truth(const double in[4], double out[2])
{
    double x = in[0], y = in[1], u = in[2], v = in[3];
    out[0] = 0.9 * x - 3 * u + 0.01 * x * x * u + 0.2 * y * v;
    out[1] = -1.1 * y + 2 * v * v * v - 0.05 * x * y;
}

static double uniform(unsigned long long *s, double lo, double hi)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * (double)(*s >> 11) / 9007199254740992.0;
}

/* 400 rows; every tenth is a blocked ray (out_eta 0, outputs nan). */
static void write_samples(const char *path)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "# columns: x y u v lambda out_x out_y out_eta\n");
    unsigned long long s = 42;
    for (int i = 0; i < 400; i++) {
        double in[4] = {uniform(&s, -5, 5), uniform(&s, -5, 5), uniform(&s, -0.3, 0.3),
                        uniform(&s, -0.3, 0.3)}, out[2];
        truth(in, out);
        if (i % 10 == 9)
            fprintf(f, "%.17g %.17g %.17g %.17g 0.55 nan nan 0\n", in[0], in[1], in[2], in[3]);
        else
            fprintf(f, "%.17g %.17g %.17g %.17g 0.55 %.17g %.17g 1\n", in[0], in[1], in[2], in[3],
                    out[0], out[1]);
    }
    fclose(f);
}

static fit_cli options(const char *path)
{
    fit_cli o;
    fit_cli_default(&o);
    o.samples_path = path;
    o.inputs = "x,y,u,v";
    o.outputs = "out_x,out_y";
    o.frame = "none";
    o.fit.max_terms = 8;
    o.fit.max_degree = 3;
    o.fit.threads = 1;
    return o;
}

static void fits_known_polynomials(void **state)
{
    (void)state;
    char path[] = "/tmp/test_fit_run.XXXXXX";
    close(mkstemp(path));
    write_samples(path);
    fit_cli o = options(path);
    lens_err err;
    samples_reader *r = samples_open(path, &err);
    assert_non_null(r);
    fit_run_stats st;
    poly_system *sys = fit_run(&o, r, NULL, &st, &err);
    samples_close(r);
    if (!sys)
        fail_msg("%s", err.msg);
    assert_int_equal(st.samples, 400);
    assert_int_equal(st.blocked, 40);
    assert_int_equal(st.nin, 4);
    assert_int_equal(st.nout, 2);
    assert_string_equal(poly_get_meta(sys, "lambda"), "0.55000000000000004");
    assert_true(st.no_lens_path);
    unsigned long long s = 7;
    for (int i = 0; i < 200; i++) {
        /* inside the training domain, at points not among the samples */
        double in[4] = {uniform(&s, -4.9, 4.9), uniform(&s, -4.9, 4.9), uniform(&s, -0.29, 0.29),
                        uniform(&s, -0.29, 0.29)}, want[2], got[2];
        truth(in, want);
        poly_eval(sys, in, got);
        for (int k = 0; k < 2; k++)
            if (!(fabs(got[k] - want[k]) <= 1e-9 * (1 + fabs(want[k]))))
                fail_msg("output %d at point %d: %.17g, want %.17g", k, i, got[k], want[k]);
    }
    poly_free(sys);
    remove(path);
}

static void tolerance_names_an_output(void **state)
{
    (void)state;
    char path[] = "/tmp/test_fit_run.XXXXXX";
    close(mkstemp(path));
    write_samples(path);
    fit_cli o = options(path);
    o.tolerance = "out_x=0.1,out_eta=0.1";
    lens_err err;
    samples_reader *r = samples_open(path, &err);
    fit_run_stats st;
    assert_null(fit_run(&o, r, NULL, &st, &err));
    samples_close(r);
    assert_string_equal(err.msg, "--tolerance: 'out_eta' is not among the outputs");
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fits_known_polynomials),
        cmocka_unit_test(tolerance_names_an_output),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
