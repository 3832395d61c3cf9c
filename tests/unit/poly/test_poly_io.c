/* The .poly text format: bit-identical round trips and FILE:LINE errors. */
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

#include "sparselens/poly.h"
#include "poly_fixture.h"

static char *to_text(const poly_system *s, size_t *len)
{
    char *buf = NULL;
    FILE *f = open_memstream(&buf, len);
    assert_int_equal(poly_write(f, s), 0);
    fclose(f);
    return buf;
}

static poly_system *from_text(const char *text, lens_err *err)
{
    FILE *f = fmemopen((void *)text, strlen(text), "r");
    poly_system *s = NULL;
    int rc = poly_read_stream(f, "t.poly", &s, err);
    fclose(f);
    if (rc != 0)
        assert_null(s);
    return s;
}

static void test_round_trip(void **st)
{
    (void)st;
    poly_system *a = fixture_system(40, 11, 3, 42);
    poly_set_lens_path(a, "lenses/fisheye-ii.lens");
    poly_set_meta(a, "fit.terms", "40 per output");
    poly_set_meta(a, "odd", "  two\nlines\t ");
    assert_int_equal(poly_add_pass_circle(a, 0, 1, 17.25), 0);
    size_t la, lb;
    char *ta = to_text(a, &la);
    lens_err err = {{0}};
    poly_system *b = from_text(ta, &err);
    if (!b)
        fail_msg("%s", err.msg);
    assert_string_equal(poly_lens_name(b), "fixture");
    assert_string_equal(poly_lens_path(b), "lenses/fisheye-ii.lens");
    assert_string_equal(poly_get_meta(b, "fit.terms"), "40 per output");
    assert_string_equal(poly_get_meta(b, "odd"), "two lines");
    assert_int_equal(poly_nparts(b), 3);
    assert_int_equal(poly_npass_circles(b), 1);
    /* writing the re-read system gives the same text */
    char *tb = to_text(b, &lb);
    assert_int_equal(la, lb);
    assert_memory_equal(ta, tb, la);
    /* and the same bits on rays in every part */
    fixture_rng g = {3};
    for (int r = 0; r < 2000; r++) {
        double in[5], oa[5], ob[5], ja[25], jb[25];
        fixture_ray(&g, in);
        assert_int_equal(poly_eval(a, in, oa), poly_eval(b, in, ob));
        assert_memory_equal(oa, ob, sizeof oa);
        poly_eval_jacobian(a, in, oa, ja);
        poly_eval_jacobian(b, in, ob, jb);
        assert_memory_equal(ja, jb, sizeof ja);
    }
    free(ta);
    free(tb);
    poly_free(a);
    poly_free(b);
}

/* A term added after others that share its factors must not change how the re-read
 * system builds it: the plan is canonical, so interleaved additions still match. */
static void test_interleaved_build(void **st)
{
    (void)st;
    const char *in[3] = {"x", "y", "u"}, *out[2] = {"a", "b"};
    poly_system *s = poly_new("l", 3, in, 2, out);
    poly_set_scaling(s, 0, 0.1, 3.3);
    poly_set_scaling(s, 1, -0.2, 1.7);
    poly_set_scaling(s, 2, 0.3, 0.9);
    poly_add_part(s, 0, INFINITY);
    int e[][3] = {{3, 2, 1}, {0, 2, 1}, {3, 0, 0}, {1, 1, 5}, {3, 2, 0}, {0, 0, 7}};
    for (int k = 0; k < 6; k++)
        poly_add_term(s, 0, k % 2, e[k], 0.1 * (k + 1) + 1.0 / 3);
    size_t len;
    char *t = to_text(s, &len);
    lens_err err;
    poly_system *r = from_text(t, &err);
    assert_non_null(r);
    double x[3] = {0.77, -1.3, 0.41}, o1[2], o2[2];
    poly_eval(s, x, o1);
    poly_eval(r, x, o2);
    assert_memory_equal(o1, o2, sizeof o1);
    free(t);
    poly_free(s);
    poly_free(r);
}

static const char *good_head = "lens-poly 1\n"
                               "lens test lens\n"
                               "inputs x y\n"
                               "outputs out_x out_y\n"
                               "scaling x 0 2 -1 1\n"
                               "part 0 inf\n"
                               "output out_x 2\n";

static void expect_error(const char *tail, const char *line, const char *words)
{
    char text[2048];
    snprintf(text, sizeof text, "%s%s", good_head, tail);
    lens_err err = {{0}};
    poly_system *s = from_text(text, &err);
    if (s)
        fail_msg("accepted: %s", tail);
    char want[64];
    snprintf(want, sizeof want, "t.poly:%s: ", line);
    if (strncmp(err.msg, want, strlen(want)) != 0 || !strstr(err.msg, words))
        fail_msg("message '%s' lacks '%s' and '%s'", err.msg, want, words);
}

static void test_errors(void **st)
{
    (void)st;
    /* a good file first, with a hex-float coefficient, which must read exactly */
    char text[1024];
    snprintf(text, sizeof text, "%s  1 0 0x1.8p+1 # 3 s_x\n  0 0 -0.25\nend\n", good_head);
    lens_err err = {{0}};
    poly_system *s = from_text(text, &err);
    if (!s)
        fail_msg("%s", err.msg);
    assert_string_equal(poly_lens_name(s), "test lens");
    double in[2] = {1, 0}, out[2];
    poly_eval(s, in, out);
    assert_true(out[0] == 3 * 0.5 - 0.25);
    assert_true(out[1] == 0); /* an output without terms is 0 */
    poly_free(s);

    expect_error("  1 0 nan\n  0 0 1\nend\n", "8", "coefficient");
    expect_error("  1 0 1\n  30 0 1\nend\n", "9", "degree past the limit");
    expect_error("  1 0 1\n  20 20 1\nend\n", "9", "degree past the limit");
    expect_error("  1 0 1\n  -1 0 1\nend\n", "9", "exponent");
    expect_error("  1 0 1\n  1.5 0 1\nend\n", "9", "exponent");
    expect_error("  1 0 1\n  1 0 2\nend\n", "9", "same monomial");
    expect_error("  1 0 1 7\n", "8", "2 exponents and a coefficient");
    expect_error("  1 0 1\n", "9", "end of file inside the terms");
    expect_error("  1 0 1\n  0 0 1\n", "10", "without 'end'");
    expect_error("  1 0 1\n  0 0 1\nscaling z 0 1 0 1\nend\n", "10", "unknown input 'z'");
    expect_error("  1 0 1\n  0 0 1\noutput out_z 0\nend\n", "10", "unknown output 'out_z'");
    expect_error("  1 0 1\n  0 0 1\noutput out_x 0\nend\n", "10", "given twice");
    expect_error("  1 0 1\n  0 0 1\npass out_x out_y 0\nend\n", "10", "radius");
    expect_error("  1 0 1\n  0 0 1\npart 0 3\nend\n", "10", "bad part");
    expect_error("  1 0 1\n  0 0 1\nwhatever 3\nend\n", "10", "unknown keyword");
    expect_error("  1 0 1\n  0 0 1\nend\npart 0 1\n", "11", "after 'end'");
    expect_error("  1 0 1\n  0 0 1\ninputs a b\nend\n", "10", "must come before");

    /* header errors */
    const struct {
        const char *text, *line, *words;
    } h[] = {
        {"lens-poly 3\n", "1", "version"},
        {"lens-poly 0\n", "1", "version"},
        /* version 1 directions are in the old outer-pupil frame: refused, not misread */
        {"lens-poly 1\ninputs x\noutputs out_x out_u out_v\n", "3", "fit it again"},
        {"hello\n", "1", "not a polynomial system"},
        {"lens-poly 1\ninputs x\npart 0 inf\n", "3", "before the outputs"},
        {"lens-poly 1\ninputs x x\n", "2", "named twice"},
        {"lens-poly 1\ninputs x\noutputs a\nscaling x 0 0 0 1\n", "4", "scale of 'x' is 0"},
        {"lens-poly 1\ninputs x\noutputs a\nscaling x 0 1 2 1\n", "4", "empty"},
        {"lens-poly 1\ninputs x\noutputs a\nend\n", "4", "no part"},
    };
    for (size_t k = 0; k < sizeof h / sizeof h[0]; k++) {
        poly_system *q = from_text(h[k].text, &err);
        assert_null(q);
        char want[64];
        snprintf(want, sizeof want, "t.poly:%s: ", h[k].line);
        if (strncmp(err.msg, want, strlen(want)) != 0 || !strstr(err.msg, h[k].words))
            fail_msg("case %zu: '%s'", k, err.msg);
    }
    assert_null(from_text("", &err));
    assert_non_null(strstr(err.msg, "empty"));
}

/* A part without terms shares the system's empty tables until its first term (a file of
 * many declared parts costs no memory per part, tests/cli/robust.sh measures it): such a
 * part evaluates to 0 with a 0 Jacobian on every path, a part given terms after it is
 * its own, and the system writes and reads back bit-identically, framed or not. */
static void test_empty_parts(void **st)
{
    (void)st;
    static const char *const in[] = {"x", "y", "u", "v"}, *const out[] = {"out_x", "out_y"};
    for (int framed = 0; framed < 2; framed++) {
        poly_system *s = poly_new("t", 4, in, 2, out);
        assert_non_null(s);
        if (framed)
            assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
        assert_int_equal(poly_add_part(s, 0, 1), 0);
        assert_int_equal(poly_add_part(s, 1, 2), 1);
        assert_int_equal(poly_add_part(s, 2, INFINITY), 2);
        const int e_x[4] = {1, 0, 0, 0}, e_u[4] = {0, 0, 1, 0}, e_v[4] = {0, 0, 0, 1};
        assert_int_equal(poly_add_term(s, 0, 0, e_x, 2.0), 0); /* out_x = 2 x in part 0 */
        assert_int_equal(poly_add_term(s, 2, 0, e_u, -3.0), 0); /* -3 u in part 2 */
        assert_int_equal(poly_add_term(s, 2, 1, e_v, 5.0), 0);  /* out_y = 5 v */
        assert_int_equal(poly_nterms(s, 1, 0) + poly_nterms(s, 1, 1), 0);
        size_t len;
        char *text = to_text(s, &len);
        lens_err err;
        poly_system *b = from_text(text, &err);
        if (!b)
            fail_msg("%s", err.msg);
        size_t len2;
        char *text2 = to_text(b, &len2);
        assert_string_equal(text, text2);
        /* rays in each part: (r, 0) with u = 0.1, v = 0.2 */
        const double rays[3][4] = {{0.5, 0, 0.1, 0.2}, {1.5, 0, 0.1, 0.2}, {2.5, 0, 0.1, 0.2}};
        const double want[3][2] = {{1.0, 0}, {0, 0}, {-0.3, 1.0}};
        double o[2], jac[8], ob[6], jb[24];
        poly_eval_batch(b, 3, &rays[0][0], ob, NULL);
        poly_eval_jacobian_batch(b, 3, &rays[0][0], jb);
        for (int r = 0; r < 3; r++) {
            poly_eval_jacobian(b, rays[r], o, jac);
            for (int k = 0; k < 2; k++) {
                assert_true(fabs(o[k] - want[r][k]) < 1e-15);
                assert_true(o[k] == ob[2 * r + k]);
            }
            for (int k = 0; k < 8; k++)
                assert_true(jac[k] == jb[8 * r + k]);
            if (r == 1)
                for (int k = 0; k < 8; k++)
                    assert_true(jac[k] == 0);
        }
        assert_true(jac[0 * 4 + 2] == -3.0 && jac[1 * 4 + 3] == 5.0); /* part 2, unframed x,y=0 */
        free(text);
        free(text2);
        poly_free(b);
        poly_free(s);
    }
}

static void test_read_file(void **st)
{
    (void)st;
    poly_system *s = NULL;
    lens_err err;
    assert_int_not_equal(poly_read("/nonexistent/x.poly", &s, &err), 0);
    assert_non_null(strstr(err.msg, "/nonexistent/x.poly: "));
    char path[] = "/tmp/test_poly_io_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    poly_system *a = fixture_system(10, 5, 1, 1);
    poly_write(f, a);
    fclose(f);
    assert_int_equal(poly_read(path, &s, &err), 0);
    assert_int_equal(poly_nterms(s, 0, 3), 10);
    unlink(path);
    poly_free(a);
    poly_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_interleaved_build),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_read_file),
        cmocka_unit_test(test_empty_parts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
