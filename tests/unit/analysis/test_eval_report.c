/* The fitting-error report against a hand computation on tests/data/eval_tiny.*:
 * out_x = x, out_u = 0, out_eta = 1, passing while |out_x| <= 10; six rays:
 *   x  y  | reference out_x out_u out_eta | system  | errors (x, u, eta)
 *   1  0  | 1.5   0.01  0.9               | passes  | 0.5  0.01  0.1
 *   3  4  | 2     0     1                 | passes  | 1    0     0
 *   6  8  | 6.25 -0.02  0.5               | passes  | 0.25 0.02  0.5
 *  20  0  | 20    0     0.8               | blocks  | (false block)
 *   2  0  | blocked (eta 0)               | passes  | (false pass)
 *  50  0  | blocked                       | blocks  | (both block)  */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/eval_report.h"
#include "sparselens/eval_run.h"
#include "sparselens/poly.h"
#include "sparselens/samples.h"

static char *path_of(const char *rel, char *buf, size_t n)
{
    const char *top = getenv("TOP");
    snprintf(buf, n, "%s%s%s", top ? top : "", top ? "/" : "", rel);
    return buf;
}

static char *report(const char *extra_bins, int nbins, eval_dir_kind dirs)
{
    (void)extra_bins;
    char p1[512], p2[512];
    lens_err err;
    poly_system *s;
    if (poly_read(path_of("tests/data/eval_tiny.poly", p1, sizeof p1), &s, &err) != 0)
        fail_msg("%s", err.msg);
    samples_reader *rd = samples_open(path_of("tests/data/eval_tiny.txt", p2, sizeof p2), &err);
    if (!rd)
        fail_msg("%s", err.msg);
    eval_run_options opt;
    eval_run_options_default(&opt);
    opt.report = 1;
    opt.ropt.nbins = nbins;
    opt.ropt.dirs = dirs;
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    eval_run_stats st;
    if (eval_run(s, rd, f, &opt, &st, &err) != 0)
        fail_msg("%s", err.msg);
    fclose(f);
    assert_int_equal(st.rows, 6);
    assert_int_equal(st.bad_rows, 0);
    assert_int_equal(st.outside, 2); /* x = 20 and x = 50 lie outside [-10, 10] */
    /* of them the lens passes x = 20 (out_eta 0.8), not x = 50 (nan, out_eta 0) */
    assert_int_equal(st.lens_known, 1);
    assert_int_equal(st.outside_passing, 1);
    assert_int_equal(st.outside_passing_input[0], 1);
    assert_int_equal(st.outside_passing_input[1], 0);
    samples_close(rd);
    poly_free(s);
    return buf;
}

/* The fields of the line starting with key (and unit, if given). */
static int find_row(const char *text, const char *key, const char *unit, const char *rmin,
                    double *v, int nv)
{
    char *copy = strdup(text), *save;
    int found = 0;
    for (char *line = strtok_r(copy, "\n", &save); line && !found;
         line = strtok_r(NULL, "\n", &save)) {
        char *tok[16], *s2;
        int n = 0;
        for (char *t = strtok_r(line, " ", &s2); t && n < 16; t = strtok_r(NULL, " ", &s2))
            tok[n++] = t;
        if (n < 2 || strcmp(tok[0], key) != 0)
            continue;
        if (unit && strcmp(tok[n - 1], unit) != 0)
            continue;
        if (rmin && (n != 9 || strcmp(tok[1], rmin) != 0))
            continue;
        if (!rmin && unit && n != 7)
            continue;
        for (int k = 0; k < nv && k + 1 < n; k++)
            v[k] = strtod(tok[k + 1], NULL);
        found = 1;
    }
    free(copy);
    return found;
}

static void near(double got, double want)
{
    if (!(fabs(got - want) <= 1e-5 * fabs(want) + 1e-12))
        fail_msg("%.9g, expected %.9g", got, want);
}

static void test_overall_rows(void **st)
{
    (void)st;
    char *text = report(NULL, 2, EVAL_DIR_UNIT);
    assert_true(strncmp(text, "# columns: key rays rms mean p99 max unit\n", 42) == 0);
    double v[5];
    assert_true(find_row(text, "out_x_mm", "mm", NULL, v, 5));
    near(v[0], 3);
    near(v[1], sqrt((0.25 + 1 + 0.0625) / 3));
    near(v[2], (0.5 + 1 + 0.25) / 3);
    near(v[3], 1); /* nearest rank ceil(0.99 * 3) = 3: the largest */
    near(v[4], 1);
    assert_true(find_row(text, "out_u", "1", NULL, v, 5));
    near(v[1], sqrt((1e-4 + 4e-4) / 3));
    near(v[2], 0.01);
    near(v[4], 0.02);
    /* unit vectors (0, 0, 1) against (0.01, 0, sqrt(1 - 0.01^2)): the angle is asin(0.01) */
    double am = 180 * 60 / M_PI;
    assert_true(find_row(text, "out_u_arcmin", "arcmin", NULL, v, 5));
    near(v[1], sqrt((pow(asin(0.01) * am, 2) + pow(asin(0.02) * am, 2)) / 3));
    near(v[4], asin(0.02) * am);
    assert_true(find_row(text, "out_eta", "1", NULL, v, 5));
    near(v[1], sqrt((0.01 + 0.25) / 3));
    near(v[2], 0.2);
    near(v[4], 0.5);
    free(text);
}

static void test_bins_and_counts(void **st)
{
    (void)st;
    char *text = report(NULL, 2, EVAL_DIR_UNIT);
    double v[8];
    /* radii 1 | 5, 10: rmax is the largest radius, 10, so the bins are [0,5) and [5,10] */
    assert_true(find_row(text, "out_x_mm", "mm", "0", v, 8));
    near(v[1], 5);
    near(v[2], 1);
    near(v[3], 0.5);
    assert_true(find_row(text, "out_x_mm", "mm", "5", v, 8));
    near(v[1], 10);
    near(v[2], 2);
    near(v[3], sqrt((1 + 0.0625) / 2));
    near(v[4], 0.625);
    near(v[6], 1);
    double c;
    assert_true(find_row(text, "rays", NULL, NULL, &c, 1));
    near(c, 6);
    assert_true(find_row(text, "both_pass", NULL, NULL, &c, 1));
    near(c, 3);
    assert_true(find_row(text, "false_pass", NULL, NULL, &c, 1));
    near(c, 1);
    assert_true(find_row(text, "false_block", NULL, NULL, &c, 1));
    near(c, 1);
    assert_true(find_row(text, "both_block", NULL, NULL, &c, 1));
    near(c, 1);
    /* x = 20 and x = 50 outside [-10, 10]; the lens passes x = 20 */
    assert_true(find_row(text, "outside_domain", NULL, NULL, &c, 1));
    near(c, 2);
    assert_true(find_row(text, "outside_domain_lens_passes", NULL, NULL, &c, 1));
    near(c, 1);
    free(text);
}

/* Slope directions: (0, 0, 1) against (0.01, 0, 1): the angle is atan(0.01). */
static void test_slope_directions(void **st)
{
    (void)st;
    char *text = report(NULL, 1, EVAL_DIR_SLOPE);
    double v[5], am = 180 * 60 / M_PI;
    assert_true(find_row(text, "out_u_arcmin", "arcmin", NULL, v, 5));
    near(v[4], atan(0.02) * am);
    near(v[2], (atan(0.01) + atan(0.02)) * am / 3);
    free(text);
}

/* p99 by nearest rank on 200 errors 1..200: the 198th smallest. */
static void test_p99_rank(void **st)
{
    (void)st;
    const char *in[1] = {"x"}, *out[1] = {"out_x"};
    poly_system *s = poly_new("l", 1, in, 1, out);
    poly_add_part(s, 0, INFINITY);
    eval_report *r = eval_report_new(s, NULL);
    for (int k = 1; k <= 200; k++) {
        double x = 0, pred = 0, ref = k;
        eval_report_add(r, &x, &pred, 1, &ref, 1);
    }
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    eval_report_write(f, r);
    fclose(f);
    double v[5];
    assert_true(find_row(buf, "out_x_mm", "mm", NULL, v, 5));
    near(v[3], 198);
    near(v[4], 200);
    near(v[2], 100.5);
    assert_non_null(strstr(buf, "no radius bins"));
    free(buf);
    eval_report_free(r);
    poly_free(s);
}

/* The two rays through system s (each passed, its own reference) into a report, and
 * that report's out_x part jump: its radius and size. */
static void out_x_jump(const poly_system *s, const double rays[2][2], double *radius, double *jump)
{
    const int nout = poly_noutputs(s);
    eval_report *r = eval_report_new(s, NULL);
    for (int k = 0; k < 2; k++) {
        double pred[2], ref[2];
        int ps = poly_eval(s, rays[k], pred);
        assert_int_equal(ps, 1);
        memcpy(ref, pred, (size_t)nout * sizeof *ref);
        eval_report_add(r, rays[k], pred, ps, ref, 1);
    }
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    eval_report_write(f, r);
    fclose(f);
    const char *head = "# columns: key radius_mm jump unit\n";
    char *line = strstr(buf, head);
    assert_non_null(line);
    assert_int_equal(sscanf(line + strlen(head), "out_x_mm %lf %lf mm", radius, jump), 2);
    free(buf);
    eval_report_free(r);
}

/* Two parts meeting at r = 5: out_x = 1 inside, 1 + 0.5 x outside. A ray at (3, 0)
 * moves onto the boundary at (5, 0), where the parts differ by 0.5 * 5 = 2.5; one at
 * (0, 7) moves to (0, 5), where they agree. The largest jump is 2.5. */
static void test_part_jump(void **st)
{
    (void)st;
    const char *in[2] = {"x", "y"}, *out[1] = {"out_x"};
    poly_system *s = poly_new("l", 2, in, 1, out);
    int e0[2] = {0, 0}, e1[2] = {1, 0};
    assert_int_equal(poly_add_part(s, 0, 5), 0);
    assert_int_equal(poly_add_part(s, 5, INFINITY), 1);
    poly_add_term(s, 0, 0, e0, 1);
    poly_add_term(s, 1, 0, e0, 1);
    poly_add_term(s, 1, 0, e1, 0.5);
    const double rays[2][2] = {{3, 0}, {0, 7}};
    double radius, jump;
    out_x_jump(s, rays, &radius, &jump);
    near(radius, 5);
    near(jump, 2.5);
    poly_free(s);
}

/* A jump counts only where both parts pass the moved ray. Parts meet at r = 5; a pass
 * circle of radius 4 on (out_x, out_y); out_x = 1 inside, 1 + 0.5 x + 2 y outside,
 * out_y = 0. A ray at (3, 0) moves to (5, 0): 1 against 3.5, both pass, a jump of 2.5.
 * One at (0, 3) moves to (0, 5): 1 against 11, which the outer part blocks (11 > 4):
 * no jump, where counting it gave 10. */
static void test_part_jump_where_both_pass(void **st)
{
    (void)st;
    const char *in[2] = {"x", "y"}, *out[2] = {"out_x", "out_y"};
    poly_system *s = poly_new("l", 2, in, 2, out);
    int e0[2] = {0, 0}, ex[2] = {1, 0}, ey[2] = {0, 1};
    assert_int_equal(poly_add_part(s, 0, 5), 0);
    assert_int_equal(poly_add_part(s, 5, INFINITY), 1);
    poly_add_term(s, 0, 0, e0, 1);
    poly_add_term(s, 1, 0, e0, 1);
    poly_add_term(s, 1, 0, ex, 0.5);
    poly_add_term(s, 1, 0, ey, 2);
    assert_int_equal(poly_add_pass_circle(s, 0, 1, 4), 0);
    const double rays[2][2] = {{3, 0}, {0, 3}};
    double radius, jump;
    out_x_jump(s, rays, &radius, &jump);
    near(radius, 5);
    near(jump, 2.5);
    poly_free(s);
}

/* The value of key in a report (NAN if absent). */
static double report_value(const eval_report *r, const char *key)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    assert_int_equal(eval_report_write(f, r), 0);
    fclose(f);
    double v = NAN;
    size_t n = strlen(key);
    for (char *line = strtok(buf, "\n"); line; line = strtok(NULL, "\n"))
        if (!strncmp(line, key, n) && line[n] == ' ')
            v = atof(line + n + 1);
    free(buf);
    return v;
}

/* Passage as a share of the light: a system whose pass circle (radius 0.1 on out_x =
 * u, out_y = v) is narrower than the lens's (0.12), on a fine grid of directions at the
 * sensor centre: it blocks the light between the two, which is, with each direction
 * weighted by cos^4 theta = 1 / (1 + rho^2)^2, (1/1.01 - 1/1.0144) / (1 - 1/1.0144) of
 * the lens's (the integral of 2 pi rho / (1 + rho^2)^2 is pi (1 - 1 / (1 + rho^2))).
 * A test set without blocked rays measures nothing, and says so. */
static void test_light_share(void **state)
{
    (void)state;
    const char *in[] = {"x", "y", "u", "v"}, *out[] = {"out_x", "out_y"};
    poly_system *s = poly_new("t", 4, in, 2, out);
    poly_add_part(s, 0, INFINITY);
    int eu[4] = {0, 0, 1, 0}, ev[4] = {0, 0, 0, 1};
    poly_add_term(s, 0, 0, eu, 1);
    poly_add_term(s, 0, 1, ev, 1);
    poly_add_pass_circle(s, 0, 1, 0.1);
    eval_report *r = eval_report_new(s, NULL), *none = eval_report_new(s, NULL);
    const double h = 0.0005;
    for (double u = -0.15 + h / 2; u < 0.15; u += h)
        for (double v = -0.15 + h / 2; v < 0.15; v += h) {
            double x[4] = {0, 0, u, v}, pred[2], ref[2] = {u, v};
            int lens = u * u + v * v <= 0.12 * 0.12;
            if (!lens)
                ref[0] = ref[1] = NAN;
            int sys = poly_eval(s, x, pred);
            eval_report_add(r, x, pred, sys, ref, lens);
            if (lens)
                eval_report_add(none, x, pred, sys, ref, lens);
        }
    double want = (1 / 1.01 - 1 / 1.0144) / (1 - 1 / 1.0144);
    double got = report_value(r, "light_false_block");
    print_message("light_false_block %.5f, closed form %.5f\n", got, want);
    assert_true(fabs(got / want - 1) < 0.01);
    assert_true(report_value(r, "light_false_pass") == 0);
    assert_true(fabs(report_value(r, "worst_ring_disagree") / want - 1) < 0.01);
    assert_true(isnan(report_value(none, "false_pass")));
    assert_true(isnan(report_value(none, "light_disagree")));
    eval_report_free(r);
    eval_report_free(none);
    poly_free(s);
}

/* The worst ring is the worst of the rings the table shows, however few rays it holds:
 * ten rays at sensor radius 5.5 mm that the lens passes and the system (pass circle 0.1
 * on u, v) blocks make ring 5 disagree on all its light, beside a well-sampled centre
 * where the two agree; the summary names it with its ray count. */
static void test_sparse_worst_ring(void **state)
{
    (void)state;
    const char *in[] = {"x", "y", "u", "v"}, *out[] = {"out_x", "out_y"};
    poly_system *s = poly_new("t", 4, in, 2, out);
    poly_add_part(s, 0, INFINITY);
    int eu[4] = {0, 0, 1, 0}, ev[4] = {0, 0, 0, 1};
    poly_add_term(s, 0, 0, eu, 1);
    poly_add_term(s, 0, 1, ev, 1);
    poly_add_pass_circle(s, 0, 1, 0.1);
    eval_report *r = eval_report_new(s, NULL);
    for (int i = 0; i < 2000; i++) {
        double u = 0.2 * (i % 50) / 50 - 0.1, v = 0.2 * (i / 50) / 40 - 0.1;
        double x[4] = {0, 0, u, v}, pred[2], ref[2] = {u, v};
        int sys = poly_eval(s, x, pred);
        eval_report_add(r, x, pred, sys, ref, sys); /* lens and system agree */
    }
    for (int i = 0; i < 10; i++) {
        double x[4] = {5.5, 0, 0.105, 0}, pred[2], ref[2] = {0.105, 0};
        int sys = poly_eval(s, x, pred);
        assert_false(sys);
        eval_report_add(r, x, pred, sys, ref, 1);
    }
    assert_true(report_value(r, "worst_ring_mm") == 5);
    assert_true(fabs(report_value(r, "worst_ring_disagree") - 1) < 1e-12);
    assert_true(report_value(r, "worst_ring_rays") == 10);
    eval_report_free(r);
    poly_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_overall_rows),
        cmocka_unit_test(test_bins_and_counts),
        cmocka_unit_test(test_slope_directions),
        cmocka_unit_test(test_p99_rank),
        cmocka_unit_test(test_part_jump),
        cmocka_unit_test(test_part_jump_where_both_pass),
        cmocka_unit_test(test_light_share),
        cmocka_unit_test(test_sparse_worst_ring),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
