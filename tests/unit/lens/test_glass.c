/* Glass: the shipped catalog against Schott's own nominal n_d and V_d, the (n_d, V_d)
 * model, range checks, the catalog reader's errors, and each AGF formula against a
 * hand evaluation. */
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

#include "sparselens/glass.h"
#include "sparselens/glass_formula.h"

#define CATALOG "lenses/glass.catalog"

static void near_tol(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.15g, want %.15g (tol %g)", got, want, tol);
}

static double n_at(const glass_t *g, double l)
{
    double n = NAN;
    lens_err err;
    assert_int_equal(glass_index(g, l, &n, &err), 0);
    return n;
}

static void test_catalog_matches_nominal(void **state)
{
    (void)state;
    static const char *const required[] = {"N-BK7", "N-SK2", "N-SK16", "SK16", "N-SSK2", "F2",
                                           "F5", "N-F2", "SF5", "N-SF5", "SF6", "N-SF6",
                                           "N-LAK9", "N-BAF10", "N-SF10", "N-LASF9", "N-SSK8"};
    glass_catalog *cat = NULL;
    lens_err err;
    assert_int_equal(glass_catalog_load(&cat, CATALOG, &err), 0);
    assert_true(glass_catalog_size(cat) >= sizeof required / sizeof *required);
    for (size_t i = 0; i < sizeof required / sizeof *required; i++) {
        const glass_t *g = glass_catalog_find(cat, required[i]);
        if (!g)
            fail_msg("glass %s missing from %s", required[i], CATALOG);
        double nd = n_at(g, GLASS_D_LINE), nf = n_at(g, GLASS_F_LINE), nc = n_at(g, GLASS_C_LINE);
        double vd = (nd - 1) / (nf - nc);
        if (fabs(nd - g->nd) > 1e-5 || fabs(vd - g->vd) > 0.05)
            fail_msg("%s: n_d %.6f (catalog %.5f), V_d %.3f (catalog %.2f)", g->name, nd, g->nd,
                     vd, g->vd);
    }
    /* A value known independently of the file: N-BK7 is the 517642 glass. */
    const glass_t *bk7 = glass_catalog_find(cat, "n-bk7");
    assert_non_null(bk7);
    assert_true(fabs(bk7->nd - 1.5168) < 1e-4 && fabs(bk7->vd - 64.17) < 0.01);
    assert_non_null(strstr(glass_catalog_sources(cat), CATALOG));
    assert_null(glass_catalog_find(cat, "UNOBTAINIUM"));
    glass_catalog_free(cat);
}

static void test_ndvd_model_exact(void **state)
{
    (void)state;
    const double cases[][2] = {{1.62041, 60.29}, {1.5168, 64.17}, {1.84666, 23.78}, {1.497, 81.61}};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        glass_t g = glass_from_ndvd(cases[i][0], cases[i][1]);
        double nd = n_at(&g, GLASS_D_LINE), nf = n_at(&g, GLASS_F_LINE), nc = n_at(&g, GLASS_C_LINE);
        assert_true(fabs(nd - cases[i][0]) < 1e-12);
        assert_true(fabs((nd - 1) / (nf - nc) - cases[i][1]) < 1e-9);
        assert_true(nf > nd && nd > nc); /* normal dispersion */
    }
}

/* The model's partial dispersions lie on Schott's normal lines (K7-F2), and for normal
 * catalog glasses the model, built from their nominal n_d and V_d alone, follows the
 * catalog's Sellmeier curve (Zemax quotes about 1e-4 for its own model glass). */
static void test_ndvd_model_normal_glasses(void **state)
{
    (void)state;
    const double g_line = 0.4358343, t_line = 1.0139722;
    glass_t m = glass_from_ndvd(1.6, 45);
    double nF = n_at(&m, GLASS_F_LINE), nC = n_at(&m, GLASS_C_LINE), dfc = nF - nC;
    double ng = glass_index_unchecked(&m, g_line), nt = glass_index_unchecked(&m, t_line);
    near_tol((ng - nF) / dfc, 0.6438 - 0.001682 * 45, 1e-9);
    near_tol((nC - nt) / dfc, 0.5450 + 0.004743 * 45, 1e-9);

    glass_catalog *cat = NULL;
    lens_err err;
    assert_int_equal(glass_catalog_load(&cat, CATALOG, &err), 0);
    static const char *const normal[] = {"N-BK7", "N-SK16", "N-BAF10", "F2", "F5"};
    for (size_t i = 0; i < sizeof normal / sizeof *normal; i++) {
        const glass_t *g = glass_catalog_find(cat, normal[i]);
        glass_t mg = glass_from_ndvd(g->nd, g->vd);
        for (int k = 0; k <= 30; k++) {
            double l = 0.40 + 0.01 * k;
            if (fabs(n_at(&mg, l) - n_at(g, l)) > 1e-4)
                fail_msg("%s at %.2f um: model %.6f, catalog %.6f", g->name, l, n_at(&mg, l),
                         n_at(g, l));
        }
    }
    glass_catalog_free(cat);

    /* Far off the glass map the Cauchy fallback keeps n_d and V_d exact; dispersion stays
     * normal (n falls with wavelength) everywhere in the range. */
    const double odd[][2] = {{1.45, 300}, {2.4, 8}, {1.6, 45}, {1.9, 20}};
    for (size_t i = 0; i < sizeof odd / sizeof *odd; i++) {
        glass_t o = glass_from_ndvd(odd[i][0], odd[i][1]);
        double nd = n_at(&o, GLASS_D_LINE);
        near_tol(nd, odd[i][0], 1e-12);
        near_tol((nd - 1) / (n_at(&o, GLASS_F_LINE) - n_at(&o, GLASS_C_LINE)), odd[i][1], 1e-8);
        for (int k = 0; k < 64; k++) {
            double l = 0.36 + 0.01 * k;
            assert_true(n_at(&o, l + 0.01) < n_at(&o, l));
        }
    }
}

static void test_out_of_range(void **state)
{
    (void)state;
    glass_catalog *cat = NULL;
    lens_err err;
    assert_int_equal(glass_catalog_load(&cat, CATALOG, &err), 0);
    const glass_t *g = glass_catalog_find(cat, "N-SF10"); /* valid from 0.38 um */
    double n = 0;
    assert_int_not_equal(glass_index(g, 0.30, &n, &err), 0);
    assert_non_null(strstr(err.msg, "N-SF10"));
    assert_int_not_equal(glass_index(g, 3.0, &n, &err), 0);
    assert_int_equal(glass_index(g, 0.38, &n, &err), 0);
    glass_t m = glass_from_ndvd(1.6, 40);
    assert_int_not_equal(glass_index(&m, 0.2, &n, &err), 0);
    assert_int_not_equal(glass_index(&m, 1.5, &n, &err), 0);
    assert_int_not_equal(glass_index(&m, NAN, &n, &err), 0);
    glass_t air = glass_air();
    assert_int_equal(glass_index(&air, 0.55, &n, &err), 0);
    assert_true(n == 1.0);
    glass_catalog_free(cat);
}

/* Each formula at lambda = 0.5 um (l^2 = 0.25, l^-2 = 4, l^-4 = 16, l^-6 = 64,
 * l^-8 = 256, l^-10 = 1024, l^-12 = 4096, l^4 = 0.0625, l^6 = 0.015625), with n^2 or n
 * summed by hand term by term. */
static void test_formulas_by_hand(void **state)
{
    (void)state;
    const double L = 1 / (0.25 - 0.028);
    struct {
        int f;
        double c[GLASS_MAX_COEF];
        double n;
    } cases[] = {
        {GLASS_F_SCHOTT, {2, 0.1, 0.01, 0.001, 1e-4, 1e-5}, sqrt(2.08996)},
        {GLASS_F_SELLMEIER1, {1, 0.05, 0.5, 0.15, 0, 1}, sqrt(3.5)},
        {GLASS_F_HERZBERGER, {1.5, 0.01, 0.001, -0.002, 1e-4, 1e-5},
         1.5 + 0.01 * L + 0.001 * L * L - 0.002 * 0.25 + 1e-4 * 0.0625 + 1e-5 * 0.015625},
        {GLASS_F_SELLMEIER2, {0.1, 1.0, 0.2, 0.01, 0.3}, sqrt(1.1 + 0.25 / 0.21 + 0.01 / 0.16)},
        {GLASS_F_CONRADY, {1.5, 0.01, 0.001}, 1.5 + 0.02 + 0.001 * 8 * sqrt(2)},
        {GLASS_F_SELLMEIER3, {1, 0.05, 0.5, 0.15, 0.2, 0, 0.1, -0.25}, sqrt(3.75)},
        {GLASS_F_HANDBOOK1, {2, 0.1, 0.05, 0.01}, sqrt(2.4975)},
        {GLASS_F_HANDBOOK2, {2, 0.1, 0.05, 0.01}, sqrt(2.1225)},
        {GLASS_F_SELLMEIER4, {2, 1, 0.05, 0.5, 0.15}, sqrt(4.5)},
        {GLASS_F_EXTENDED1, {2, 0.1, 0.01, 0.001, 1e-4, 1e-5, 1e-6, 1e-7}, sqrt(2.0913936)},
        {GLASS_F_SELLMEIER5, {1, 0.05, 0.5, 0.15, 0.2, 0, 0.1, -0.25, 0.4, 0}, sqrt(4.15)},
        {GLASS_F_EXTENDED2, {2, 0.1, 0.01, 0.001, 1e-4, 1e-5, 0.2, 0.4}, sqrt(2.10871)},
        {GLASS_F_EXTENDED3, {2, 0.1, 0.2, 0.01, 0.001, 1e-4, 1e-5, 1e-6, 1e-7}, sqrt(2.1038936)},
    };
    int seen[14] = {0};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        double n = glass_formula_eval(cases[i].f, cases[i].c, 0.5);
        if (!(fabs(n - cases[i].n) < 1e-12))
            fail_msg("formula %d (%s): %.15f, by hand %.15f", cases[i].f,
                     glass_formula_name(cases[i].f), n, cases[i].n);
        assert_true(glass_formula_ncoef(cases[i].f) > 0);
        seen[cases[i].f] = 1;
    }
    for (int f = 1; f <= 13; f++)
        assert_true(seen[f]);
    assert_true(isnan(glass_formula_eval(14, cases[0].c, 0.5)));
    assert_int_equal(glass_formula_ncoef(0), 0);
}

static char *write_tmp(const char *text)
{
    static char name[64];
    strcpy(name, "/tmp/test_glass_XXXXXX.catalog");
    int fd = mkstemps(name, 8);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    fputs(text, f);
    fclose(f);
    return name;
}

static void expect_catalog_error(const char *text, const char *line, const char *what)
{
    char *path = write_tmp(text);
    glass_catalog *cat = NULL;
    lens_err err;
    assert_int_not_equal(glass_catalog_load(&cat, path, &err), 0);
    assert_null(cat);
    char want[128];
    snprintf(want, sizeof want, "%s:%s: ", path, line);
    if (strncmp(err.msg, want, strlen(want)) != 0 || !strstr(err.msg, what))
        fail_msg("message '%s' lacks '%s' or '%s'", err.msg, want, what);
    unlink(path);
}

static void test_catalog_errors(void **state)
{
    (void)state;
    const char *ok = "# comment\nG1 sellmeier1 1.03961212 0.00600069867 0.231792344 "
                     "0.0200179144 1.01046945 103.560653 0.3 2.5 1.5168 64.17\n";
    char buf[1024];
    snprintf(buf, sizeof buf, "%sG2 sellmeier9 1 2 3 0.3 2.5 1.5 60\n", ok);
    expect_catalog_error(buf, "3", "unknown dispersion formula");
    snprintf(buf, sizeof buf, "%sG2 sellmeier1 1 2 3 0.3 2.5 1.5 60\n", ok);
    expect_catalog_error(buf, "3", "takes 6 coefficients");
    snprintf(buf, sizeof buf, "\n%s", ok);
    strcat(buf, "G3 2 1.03961212 0.006 0.2317 0.02 1.0104 nan 0.3 2.5 1.5168 64.17\n");
    expect_catalog_error(buf, "4", "not a finite number");
    snprintf(buf, sizeof buf, "%s%s", ok, ok);
    expect_catalog_error(buf, "4", "listed twice");
    expect_catalog_error("G4 conrady 1.5 0.01 0.001 0.7 0.4 1.5 50\n", "1", "range");
    /* Coefficients in the wrong order (K and L swapped): that glass is unusable, named
     * with its reason, and the file's other glasses load. */
    char *bad = write_tmp("G5 sellmeier1 0.00600069867 1.03961212 0.0200179144 0.231792344 "
                          "103.560653 1.01046945 0.3 2.5 1.5168 64.17\n"
                          "G6 sellmeier1 1.03961212 0.00600069867 0.231792344 0.0200179144 "
                          "1.01046945 103.560653 0.3 2.5 1.5168 64.17\n");
    glass_catalog *mixed = NULL;
    lens_err e2;
    if (glass_catalog_load(&mixed, bad, &e2) != 0)
        fail_msg("%s", e2.msg);
    const glass_t *g5 = glass_catalog_find(mixed, "G5"), *g6 = glass_catalog_find(mixed, "G6");
    assert_non_null(g5);
    assert_non_null(g6);
    const char *why = glass_catalog_problem(mixed, glass_catalog_index(mixed, g5));
    assert_non_null(why);
    assert_non_null(strstr(why, "wrong order"));
    assert_non_null(strstr(why, "where the entry says 1.516800"));
    assert_null(glass_catalog_problem(mixed, glass_catalog_index(mixed, g6)));
    glass_catalog_free(mixed);
    unlink(bad);
    /* vendor and alias lines */
    expect_catalog_error("vendor\n", "1", "expected: vendor NAME");
    expect_catalog_error("alias OLD NONE\n", "1", "no glass NONE");
    expect_catalog_error("alias OLD\n", "1", "expected: alias");

    glass_catalog *cat = NULL;
    lens_err err;
    assert_int_not_equal(glass_catalog_load(&cat, "/nonexistent/x.catalog", &err), 0);
    assert_non_null(strstr(err.msg, "/nonexistent/x.catalog"));

    /* Loading more files extends a catalog; the first file wins on a repeated name. */
    char *p1 = strdup(write_tmp(ok));
    char *p2 = strdup(write_tmp("G1 conrady 1.7 0 0 0.3 2.5 1.7 0\n"));
    assert_int_equal(glass_catalog_load(&cat, p1, &err), 0);
    assert_int_equal(glass_catalog_load(&cat, p2, &err), 0);
    assert_int_equal(glass_catalog_size(cat), 2);
    assert_true(fabs(glass_catalog_find(cat, "g1")->nd - 1.5168) < 1e-12);
    assert_non_null(strstr(glass_catalog_sources(cat), p2));
    glass_catalog_free(cat);
    unlink(p1);
    unlink(p2);
    free(p1);
    free(p2);
}

static void test_new_add(void **state)
{
    (void)state;
    glass_catalog *cat = glass_catalog_new();
    assert_non_null(cat);
    lens_err err;
    glass_t g = glass_from_ndvd(1.6, 40);
    assert_int_not_equal(glass_catalog_add(cat, &g, &err), 0); /* no name */
    for (int i = 0; i < 200; i++) {
        snprintf(g.name, sizeof g.name, "M%d", i);
        assert_int_equal(glass_catalog_add(cat, &g, &err), 0);
    }
    assert_int_equal(glass_catalog_size(cat), 200);
    assert_string_equal(glass_catalog_at(cat, 123)->name, "M123");
    assert_null(glass_catalog_at(cat, 200));
    glass_catalog_free(cat);
}

static void test_default_path(void **state)
{
    (void)state;
    setenv("SPARSELENS_GLASS_CATALOG", CATALOG, 1);
    const char *p = glass_default_catalog_path();
    assert_non_null(p);
    assert_string_equal(p, CATALOG);
    setenv("SPARSELENS_GLASS_CATALOG", "/nonexistent/glass.catalog", 1);
    assert_null(glass_default_catalog_path());
    unsetenv("SPARSELENS_GLASS_CATALOG");
    /* From build/tests/ the tree's lenses/ is found beside the executable. */
    p = glass_default_catalog_path();
    assert_non_null(p);
    assert_non_null(strstr(p, "lenses/glass.catalog"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_catalog_matches_nominal), cmocka_unit_test(test_ndvd_model_exact),
        cmocka_unit_test(test_ndvd_model_normal_glasses),
        cmocka_unit_test(test_out_of_range),           cmocka_unit_test(test_formulas_by_hand),
        cmocka_unit_test(test_catalog_errors),         cmocka_unit_test(test_new_add),
        cmocka_unit_test(test_default_path),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
