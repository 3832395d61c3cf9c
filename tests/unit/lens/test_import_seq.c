/* CODE V .seq import: the test designs of test_import_zmx.c written as sequence files,
 * which must give the same lenses and the same first-order values; CODE V's own forms
 * (commands joined by ';', STO alone or as a surface, curvature mode, fictitious glass
 * codes, maker-qualified glass names); refusals and errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "sparselens/import_design.h"
#include "import_check.h"

static const char *const test_catalogs[] = {DATA "test.agf", NULL};
static const lens_load_options with_catalog = {.catalogs = test_catalogs};

static void load(const char *path, const lens_load_options *opt, lens_t *lens)
{
    lens_err err;
    if (lens_load(path, opt, lens, &err) != 0)
        fail_msg("%s", err.msg);
}

/* Each .seq against its .zmx twin, and one first-order value from a closed form. */
static void test_same_as_zmx(void **state)
{
    (void)state;
    static const char *const names[] = {"singlet", "doublet", "asphere", "cooke", "dgauss"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        char a[128], b[128];
        snprintf(a, sizeof a, DATA "%s.seq", names[i]);
        snprintf(b, sizeof b, DATA "%s.zmx", names[i]);
        lens_t seq, zmx;
        load(a, &with_catalog, &seq);
        load(b, &with_catalog, &zmx);
        assert_same_lens(&seq, &zmx, 1e-9);
        assert_near(first_order(&seq).efl, first_order(&zmx).efl, 1e-9);
        lens_free(&seq);
        lens_free(&zmx);
    }
}

static void test_singlet(void **state)
{
    (void)state;
    lens_t lens;
    load(DATA "singlet.seq", NULL, &lens);
    /* thick lens, R = +-50, t = 5, n = 1.5 (see test_import_zmx.c) */
    double f = 1 / (0.5 * (0.04 - 2.5 / 3750));
    assert_near(first_order(&lens).efl, f, 1e-9);
    assert_near(first_order(&lens).bfl, f * (1 - 1.0 / 30), 1e-9);
    assert_string_equal(lens.name, "Biconvex singlet, test file");
    assert_non_null(strstr(lens.notes, "paraxial image solve"));
    assert_non_null(strstr(lens.notes, "0.5875618 (primary)"));
    /* EPD 10 gives the nominal f-number efl / 10. */
    assert_near(lens.fnumber, f / 10, 1e-9);
    lens_free(&lens);
}

/* 670472 is CODE V's code for n_d 1.670, V_d 47.2. */
static void test_glass_codes(void **state)
{
    (void)state;
    lens_t lens;
    load(DATA "dgauss.seq", NULL, &lens);
    assert_int_equal(lens.surf[0].medium.kind, GLASS_NDVD);
    assert_near(lens.surf[0].medium.nd, 1.670, 1e-12);
    assert_near(lens.surf[0].medium.vd, 47.2, 1e-12);
    assert_true(lens.surf[3].medium.nd == 1.699); /* the decimal, exactly as written */
    assert_near(lens.surf[3].medium.vd, 30.1, 1e-12);
    assert_int_equal(lens.stop, 5);
    assert_near(lens.fnumber, 2, 0);
    lens_free(&lens);
    /* NBK7_SCHOTT: maker suffix dropped, hyphen-less name matched to N-BK7. */
    load(DATA "doublet.seq", &with_catalog, &lens);
    assert_string_equal(lens.surf[0].material, "N-BK7");
    assert_string_equal(lens.surf[1].material, "N-F2");
    assert_int_equal(lens.stop, 0);
    lens_free(&lens);
}

static void expect_error(const char *text, const char *want1, const char *want2)
{
    lens_t lens;
    lens_err err;
    if (lens_parse_seq(text, strlen(text), "mem.seq", &with_catalog, &lens, &err) == 0)
        fail_msg("accepted a file it should refuse (%s)", want1);
    if (!strstr(err.msg, want1) || (want2 && !strstr(err.msg, want2)))
        fail_msg("message '%s' lacks '%s' / '%s'", err.msg, want1, want2 ? want2 : "");
    assert_int_equal(lens.nsurf, 0);
}

static void test_refusals(void **state)
{
    (void)state;
    expect_error("SO 0 1e10\nS 50 5 NBK7_SCHOTT; CIR 5; STO\nS 0 20 REFL; CIR 5\nSI 0 0\n",
                 "mem.seq:3: surface 2", "mirror");
    expect_error("SO 0 1e10\nS 50 5 NBK7_SCHOTT; CIR 5; STO\nS -50 40; CIR 5\n  YDE 0.1\nSI 0 0\n",
                 "mem.seq:4: surface 2", "decentred");
    expect_error("SO 0 1e10\nS 50 5 NBK7_SCHOTT; CIR 5; STO\nS -50 40; CIR 5\n  ADE 2\nSI 0 0\n",
                 "surface 2", "tilted");
    expect_error("SO 0 1e10\nS 50 5 NBK7_SCHOTT; STO\nS -50 40; CIR 5\nSI 0 0\n",
                 "without a clear aperture (CIR), and no EPD or FNO", NULL);
    expect_error("SO 0 1e10\nS 50 5 UNOBTAINIUM_ACME; CIR 5; STO\nS -50 40; CIR 5\nSI 0 0\n",
                 "mem.seq:2: glass UNOBTAINIUM_ACME not found in", "test.agf");
    expect_error("SO 0 1e10\nS 50 five; CIR 5\n", "mem.seq:2", "thickness");
    expect_error("SO 0 1e10\nS 50 5; CIR 5\n  XYP\nSI 0 0\n", "surface 1", "XYP");
    expect_error("DIM Q\n", "DIM Q", NULL);
    expect_error("TITLE 'nothing'\n", "no lens surfaces", NULL);
    /* A zero decentre is no decentre; an x field is noted; solves are ignored. */
    const char *ok = "RDM;LEN\nXAN 0 3; YAN 0 3\nSO 0 1e10\nS 50 5 1.5:60; CIR 5; STO\n"
                     "  CCY 0; THC 0; XDE 0\nS -50 49.152542372881356; CIR 5\nSI 0 0\nGO\n";
    lens_t lens;
    lens_err err;
    if (lens_parse_seq(ok, strlen(ok), "mem.seq", NULL, &lens, &err) != 0)
        fail_msg("%s", err.msg);
    assert_non_null(strstr(lens.notes, "x fields"));
    lens_free(&lens);
}

/* No CIR: apertures from paraxial rays. Stop on the first surface, so there the chief
 * ray height is 0 and the semi-diameter is EPD/2 = 5. At the second: marginal ray
 * 5 + 5 (-5 (0.5/50)) / 1.5 = 5 - 1/6, chief ray 5 tan(5 deg) / 1.5. */
static void test_apertures_from_rays(void **state)
{
    (void)state;
    const char *text = "EPD 10\nYAN 0 5\nSO 0 1e10\nS 50 5 1.5:60; STO\nS -50 49.15\nSI 0 0\n";
    lens_t lens;
    lens_err err;
    if (lens_parse_seq(text, strlen(text), "mem.seq", NULL, &lens, &err) != 0)
        fail_msg("%s", err.msg);
    assert_near(lens.surf[0].semi_diameter, 5, 1e-12);
    assert_near(lens.surf[1].semi_diameter, 5 - 1.0 / 6 + 5 * tan(5 * M_PI / 180) / 1.5, 1e-12);
    assert_non_null(strstr(lens.notes, "2 semi-diameters not in the file (CIR)"));
    lens_free(&lens);
}

/* CODE V's own habits: a continued line (&), the two-part fictitious code
 * nnnnnn.vvvvvv, a private glass catalog (PRV ... END) with indices at C, d, F. */
static void test_codev_habits(void **state)
{
    (void)state;
    const char *text = "RDM;LEN \"VERSION: X\"\nTITLE 'habits'\nEPD 10\nDIM M\n"
                       "WL 656.2725 587.5618 486.1327; REF 2\nYOB 0.0 5.0 &\n   10.0\n"
                       "SO 0.0 0.1e14\nS 50.0 5.0 516800.641700 ; CIR 6\n  STO\n"
                       "S -50.0 2.0 'MYGLASS'; CIR 6\nS -200 90; CIR 6\nSI 0 0\n"
                       "PRV\nPWL 656.2725 587.5618 486.1327\n'MYGLASS' 1.615 1.62 1.632\nEND\nGO\n";
    lens_t lens;
    lens_err err;
    if (lens_parse_seq(text, strlen(text), "mem.seq", NULL, &lens, &err) != 0)
        fail_msg("%s", err.msg);
    assert_true(lens.surf[0].medium.nd == 1.5168);
    assert_near(lens.surf[0].medium.vd, 64.17, 1e-12);
    /* three indices: the formula through them gives them back */
    assert_near(lens.surf[1].medium.nd, 1.62, 1e-12);
    assert_near(lens.surf[1].medium.vd, 0.62 / (1.632 - 1.615), 1e-9);
    assert_non_null(strstr(lens.notes, "fields object height: 0 5 10"));
    assert_non_null(strstr(lens.notes, "private glass MYGLASS"));
    assert_int_equal(lens.stop, 0);
    lens_free(&lens);
    /* a private glass without the d line cannot be used */
    const char *bad = "SO 0 1e10\nS 50 5 'P1'; CIR 5; STO\nS -50 40; CIR 5\nSI 0 0\n"
                      "PRV\nPWL 1000 1500\n'P1' 1.5 1.49\nEND\n";
    assert_int_not_equal(lens_parse_seq(bad, strlen(bad), "mem.seq", NULL, &lens, &err), 0);
    assert_non_null(strstr(err.msg, "mem.seq:2: private glass P1 gives no index at the d line"));
}

/* N-BK7 (Schott's Sellmeier coefficients) tabulated at eight wavelengths, none of them
 * the d, F or C line: the private glass disperses as N-BK7 does at those lines. */
static double bk7(double um)
{
    double l2 = um * um;
    return sqrt(1 + 1.03961212 * l2 / (l2 - 0.00600069867) + 0.231792344 * l2 / (l2 - 0.0200179144) +
                1.01046945 * l2 / (l2 - 103.560653));
}

static void test_private_table(void **state)
{
    (void)state;
    static const double nm[8] = {400, 450, 500, 550, 600, 650, 700, 750};
    char text[1024];
    int o = snprintf(text, sizeof text, "WL 656.2725 587.5618 486.1327\nSO 0 1e10\n"
                                        "S 50 5 'TAB'; CIR 5; STO\nS -50 40; CIR 5\nSI 0 0\nPRV\nPWL");
    for (int i = 0; i < 8; i++)
        o += snprintf(text + o, sizeof text - (size_t)o, " %g", nm[i]);
    o += snprintf(text + o, sizeof text - (size_t)o, "\n'TAB'");
    for (int i = 0; i < 8; i++)
        o += snprintf(text + o, sizeof text - (size_t)o, " %.6f", bk7(nm[i] * 1e-3));
    snprintf(text + o, sizeof text - (size_t)o, "\nEND\n");
    lens_t lens;
    lens_err err;
    if (lens_parse_seq(text, strlen(text), "mem.seq", NULL, &lens, &err) != 0)
        fail_msg("%s", err.msg);
    static const double lines[3] = {0.4861327, 0.5875618, 0.6562725};
    for (int i = 0; i < 3; i++) {
        double n;
        assert_int_equal(glass_index(&lens.surf[0].medium, lines[i], &n, &err), 0);
        assert_near(n, bk7(lines[i]), 5e-6); /* the table's six decimals */
    }
    assert_near(lens.surf[0].medium.vd, 64.17, 0.05);
    assert_non_null(strstr(lens.notes, "private glass TAB: the Schott formula fitted"));
    lens_free(&lens);
}

static void test_truncated(void **state)
{
    (void)state;
    static const char *const files[] = {"singlet.seq", "doublet.seq", "asphere.seq", "cooke.seq",
                                        "dgauss.seq"};
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        char path[256];
        snprintf(path, sizeof path, DATA "%s", files[i]);
        size_t len;
        char *data = slurp(path, &len);
        check_truncations(lens_parse_seq, path, data, len, &with_catalog);
        free(data);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_as_zmx), cmocka_unit_test(test_singlet),
        cmocka_unit_test(test_glass_codes), cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_apertures_from_rays), cmocka_unit_test(test_truncated),
        cmocka_unit_test(test_codev_habits), cmocka_unit_test(test_private_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
