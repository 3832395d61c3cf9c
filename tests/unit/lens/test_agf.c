/* AGF glass catalogs: tests/data/import/test.agf holds one made-up glass per AGF
 * formula and four Schott glasses. Each made-up glass is checked at 0.5 um against its
 * formula written out by hand (l^2 = 0.25, l^-2 = 4, l^-4 = 16, ...), the Schott glasses
 * against Schott's published n_d; then the reader's errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/agf.h"
#include "sparselens/glass.h"

#define AGF "tests/data/import/test.agf"

static glass_catalog *load(void)
{
    glass_catalog *cat = NULL;
    lens_err err;
    if (glass_catalog_load(&cat, AGF, &err) != 0)
        fail_msg("%s", err.msg);
    return cat;
}

static double n_of(const glass_catalog *cat, const char *name, double l)
{
    const glass_t *g = glass_catalog_find(cat, name);
    if (!g)
        fail_msg("%s not in %s", name, AGF);
    double n;
    lens_err err;
    if (glass_index(g, l, &n, &err) != 0)
        fail_msg("%s: %s", name, err.msg);
    return n;
}

#define CHECK(name, expected)                                                              \
    do {                                                                                   \
        double got_ = n_of(cat, name, 0.5), want_ = (expected);                            \
        if (fabs(got_ - want_) > 1e-12)                                                    \
            fail_msg("%s: n(0.5 um) = %.15f, by hand %.15f", name, got_, want_);           \
    } while (0)

static void test_each_formula(void **state)
{
    (void)state;
    glass_catalog *cat = load();
    assert_int_equal(glass_catalog_size(cat), 17);
    /* 1 Schott: a0 + a1 l^2 + a2 l^-2 + a3 l^-4 + a4 l^-6 + a5 l^-8 */
    CHECK("T01-SCHOTT", sqrt(2.25 - 0.01 * 0.25 + 0.01 * 4 + 1e-4 * 16 + 1e-5 * 64 + 1e-6 * 256));
    /* 2 Sellmeier 1: 1 + K l^2 / (l^2 - L), (K, L) = (1, 0.01), (0.2, 0.04), (1, 100) */
    CHECK("T02-SELLMEIER1", sqrt(1 + 0.25 / 0.24 + 0.2 * 0.25 / 0.21 + 0.25 / (0.25 - 100)));
    /* 3 Herzberger: L = 1 / (l^2 - 0.028) = 1 / 0.222 */
    double L = 1 / 0.222;
    CHECK("T03-HERZBERGER", 1.5 + 0.005 * L + 0.0001 * L * L - 0.001 * 0.25 + 0.0001 * 0.0625 -
                                0.00001 * 0.015625);
    /* 4 Sellmeier 2: 1 + A + B1 l^2 / (l^2 - l1^2) + B2 / (l^2 - l2^2) */
    CHECK("T04-SELLMEIER2", sqrt(1 + 0.2 + 1.0 * 0.25 / (0.25 - 0.01) + 0.01 / (0.25 - 100)));
    /* 5 Conrady: n0 + A / l + B / l^3.5, l^-3.5 = 2^3.5 = 8 sqrt(2) */
    CHECK("T05-CONRADY", 1.5 + 0.01 * 2 + 0.001 * 8 * sqrt(2.0));
    /* 6 Sellmeier 3: four terms */
    CHECK("T06-SELLMEIER3", sqrt(1 + 0.25 / 0.24 + 0.2 * 0.25 / 0.21 + 0.1 * 0.25 / 0.2 +
                                 0.25 / (0.25 - 100)));
    /* 7 Handbook 1: A + B / (l^2 - C) - D l^2 */
    CHECK("T07-HANDBOOK1", sqrt(2.3 + 0.01 / 0.23 - 0.01 * 0.25));
    /* 8 Handbook 2: A + B l^2 / (l^2 - C) - D l^2 */
    CHECK("T08-HANDBOOK2", sqrt(2.3 + 0.01 * 0.25 / 0.23 - 0.01 * 0.25));
    /* 9 Sellmeier 4: A + B l^2 / (l^2 - C) + D l^2 / (l^2 - E) */
    CHECK("T09-SELLMEIER4", sqrt(1.5 + 0.8 * 0.25 / 0.24 + 0.5 * 0.25 / (0.25 - 100)));
    /* 10 Extended: Schott + a6 l^-10 + a7 l^-12 */
    CHECK("T10-EXTENDED", sqrt(2.25 - 0.01 * 0.25 + 0.01 * 4 + 1e-4 * 16 + 1e-5 * 64 +
                               1e-6 * 256 + 1e-7 * 1024 + 1e-8 * 4096));
    /* 11 Sellmeier 5: five terms */
    CHECK("T11-SELLMEIER5", sqrt(1 + 0.25 / 0.24 + 0.2 * 0.25 / 0.21 + 0.1 * 0.25 / 0.2 +
                                 0.05 * 0.25 / 0.19 + 0.25 / (0.25 - 100)));
    /* 12 Extended 2: Schott + a6 l^4 + a7 l^6 */
    CHECK("T12-EXTENDED2", sqrt(2.25 - 0.01 * 0.25 + 0.01 * 4 + 1e-4 * 16 + 1e-5 * 64 +
                                1e-6 * 256 + 1e-3 * 0.0625 + 1e-4 * 0.015625));
    /* 13 Extended 3: a0 + a1 l^2 + a2 l^4 + a3 l^-2 + ... + a8 l^-12 */
    CHECK("T13-EXTENDED3", sqrt(2.25 - 0.01 * 0.25 + 0.001 * 0.0625 + 0.01 * 4 + 1e-4 * 16 +
                                1e-5 * 64 + 1e-6 * 256 + 1e-7 * 1024 + 1e-8 * 4096));
    for (int f = 1; f <= 13; f++)
        assert_int_equal(glass_catalog_at(cat, (size_t)f - 1)->formula, f);
    glass_catalog_free(cat);
}

static void test_schott_and_ranges(void **state)
{
    (void)state;
    glass_catalog *cat = load();
    /* Schott's published n_d (5 decimals) from the published Sellmeier coefficients. */
    assert_true(fabs(n_of(cat, "N-BK7", GLASS_D_LINE) - 1.51680) < 5e-6);
    assert_true(fabs(n_of(cat, "SK16", GLASS_D_LINE) - 1.62041) < 5e-6);
    assert_true(fabs(n_of(cat, "F2", GLASS_D_LINE) - 1.62004) < 5e-6);
    const glass_t *bk7 = glass_catalog_find(cat, "N-BK7");
    assert_true(fabs(bk7->nd - 1.5168) < 1e-4 && fabs(bk7->vd - 64.17) < 0.01);
    assert_true(bk7->lambda_min == 0.3 && bk7->lambda_max == 2.5);
    /* LD 0.4 0.8 on the Conrady glass: 0.3 um is refused, not extrapolated. */
    const glass_t *con = glass_catalog_find(cat, "T05-CONRADY");
    double n;
    lens_err err;
    assert_int_not_equal(glass_index(con, 0.3, &n, &err), 0);
    assert_int_equal(glass_index(con, 0.5, &n, &err), 0);
    assert_non_null(strstr(glass_catalog_sources(cat), "test.agf"));
    glass_catalog_free(cat);
}

static int count_add(void *ctx, const glass_t *g, lens_err *err)
{
    (void)g;
    (void)err;
    ++*(int *)ctx;
    return 0;
}

static void expect_error(const char *text, const char *want)
{
    int n = 0;
    lens_err err;
    if (agf_parse(text, strlen(text), "mem.agf", count_add, &n, &err) == 0)
        fail_msg("accepted a bad catalog (%s)", want);
    if (!strstr(err.msg, want))
        fail_msg("message '%s' lacks '%s'", err.msg, want);
}

static void test_errors_and_utf16(void **state)
{
    (void)state;
    expect_error("CD 1 2 3\n", "mem.agf:1: CD line before any NM");
    expect_error("NM X 14 0 1.5 60 0 1\nCD 1\n", "mem.agf:1: glass X: unknown dispersion formula 14");
    expect_error("NM X 5 0 1.5 60 0 1\nCD 1.5 0.01 0.001 7\n", "mem.agf:2: glass X: formula 5");
    expect_error("NM X 5 0 1.5 60 0 1\nCD 1.5 0.01 0.001\nLD 0.8 0.4\n", "mem.agf:3: LD");
    expect_error("NM X 5 0 1.5 60 0 1\nNM Y 5 0 1.5 60 0 1\nCD 1 0 0\n", "mem.agf:1: glass X has no CD");
    expect_error("NM X 5\n", "mem.agf:1: NM line");
    /* n_d = 1.5 + 0.01 / 0.5875618 + ... = 1.52, not the 1.6 claimed (a wrong column):
     * the glass is read, and the catalog marks it (test_inconsistent_entry). */
    {
        int read = 0;
        lens_err e;
        const char *wrong = "NM X 5 0 1.6 60 0 1\nCD 1.5 0.01 0.001\n";
        assert_int_equal(agf_parse(wrong, strlen(wrong), "mem.agf", count_add, &read, &e), 0);
        assert_int_equal(read, 1);
    }
    expect_error("CC nothing\n", "no glasses");
    expect_error("NM X 5 0 1.5 60 0 1\nCD 1.5 zero 0\n", "mem.agf:2: glass X: CD value 'zero'");

    /* The same records in UTF-16 LE with a byte-order mark, as Zemax writes them. */
    const char *ascii = "CC utf-16\r\nNM U16 5 0 1.52345 50 0 1\r\nCD 1.5 0.01 0.001 0 0\r\nLD 0.4 0.8\r\n";
    size_t n = strlen(ascii);
    char *u16 = malloc(2 * n + 2);
    u16[0] = (char)0xFF;
    u16[1] = (char)0xFE;
    for (size_t i = 0; i < n; i++) {
        u16[2 + 2 * i] = ascii[i];
        u16[3 + 2 * i] = 0;
    }
    int count = 0;
    lens_err err;
    if (agf_parse(u16, 2 * n + 2, "u16.agf", count_add, &count, &err) != 0)
        fail_msg("%s", err.msg);
    assert_int_equal(count, 1);
    free(u16);
    assert_true(agf_is_agf_path("x/SCHOTT.AGF"));
    assert_false(agf_is_agf_path("glass.catalog"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_each_formula),
        cmocka_unit_test(test_schott_and_ranges),
        cmocka_unit_test(test_errors_and_utf16),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
