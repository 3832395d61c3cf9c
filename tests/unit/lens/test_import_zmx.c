/* Zemax .zmx import: test designs written for these tests (tests/data/import/), read in
 * both encodings and in other lens units, checked against first-order values from
 * closed forms or an independent matrix product; refusals and errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <unistd.h>

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

static int parse(const char *text, const lens_load_options *opt, lens_t *lens, lens_err *err)
{
    return lens_parse_zmx(text, strlen(text), "mem.zmx", opt, lens, err);
}

/* Biconvex R = +-50, t = 5, n = 1.5 (a model glass, so n_d is exact). Thick-lens formula:
 * 1/f = (n-1) (2/R + (n-1) t / (n R^2)) with R2 = -R1: 1/f = 0.5 (0.04 - 2.5/3750),
 * f = 50.847457...; bfl = f (1 - (n-1) t / (n R1)) = f (1 - 1/30). */
static void test_singlet_utf16(void **state)
{
    (void)state;
    lens_t lens;
    load(DATA "singlet.zmx", NULL, &lens);
    assert_int_equal(lens.nsurf, 2); /* the dummy plane is merged into the gap */
    assert_near(lens.surf[0].radius, 50, 1e-12);
    assert_near(lens.surf[1].radius, -50, 1e-12);
    assert_near(lens.surf[0].thickness, 5, 1e-12);
    assert_near(lens.surf[1].thickness, 20 + 29.152542372881356, 1e-12);
    assert_int_equal(lens.surf[0].medium.kind, GLASS_NDVD);
    assert_near(lens.surf[0].medium.nd, 1.5, 0);
    assert_near(lens.surf[0].medium.vd, 60, 0);
    assert_true(lens.surf[0].is_stop);
    assert_near(lens.surf[0].semi_diameter, 5, 0);
    assert_string_equal(lens.name, "Biconvex singlet, test file");
    /* What was skipped is said, not dropped. */
    assert_non_null(strstr(lens.notes, "coatings (2)"));
    assert_non_null(strstr(lens.notes, "tolerance operands (3)"));
    assert_non_null(strstr(lens.notes, "dummy"));
    assert_non_null(strstr(lens.notes, "0.5875618 (primary)"));

    double f = 1 / (0.5 * (0.04 - 2.5 / 3750)), bfl = f * (1 - 1.0 / 30);
    paraxial_data p = first_order(&lens);
    assert_near(p.efl, f, 1e-9);
    assert_near(p.bfl, bfl, 1e-9);
    /* The file puts the image at the paraxial focus. */
    assert_near(lens.surf[1].thickness, bfl, 1e-9);
    lens_free(&lens);
}

/* The same singlet in centimetres, 8-bit text with a Latin-1 degree sign. */
static void test_singlet_cm_8bit(void **state)
{
    (void)state;
    lens_t mm, cm;
    load(DATA "singlet.zmx", NULL, &mm);
    load(DATA "singlet_cm.zmx", NULL, &cm);
    assert_same_lens(&mm, &cm, 1e-9);
    assert_near(first_order(&cm).efl, 1 / (0.5 * (0.04 - 2.5 / 3750)), 1e-9);
    lens_free(&mm);
    lens_free(&cm);
}

/* Cemented doublet with catalog glasses from an AGF file given as an extra catalog. */
static void test_doublet_catalog(void **state)
{
    (void)state;
    lens_t lens;
    load(DATA "doublet.zmx", &with_catalog, &lens);
    assert_int_equal(lens.nsurf, 3);
    assert_string_equal(lens.surf[0].material, "N-BK7");
    assert_string_equal(lens.surf[1].material, "N-F2");
    assert_int_equal(lens.surf[0].medium.kind, GLASS_FORMULA);
    /* Schott's published n_d of N-BK7 through the AGF reader and Sellmeier formula. */
    double n1, n2;
    lens_err err;
    assert_int_equal(glass_index(&lens.surf[0].medium, GLASS_D_LINE, &n1, &err), 0);
    assert_int_equal(glass_index(&lens.surf[1].medium, GLASS_D_LINE, &n2, &err), 0);
    assert_near(n1, 1.5168, 5e-6);
    assert_near(n2, 1.62004, 3e-5);
    /* Three refractions and two transfers multiplied out by hand (import_check.h). */
    double R[] = {61.47, -44.64, -129.94}, t[] = {6, 2.5, 0}, n[] = {n1, n2, 1}, f, b;
    table_first_order(3, R, t, n, &f, &b);
    paraxial_data p = first_order(&lens);
    assert_near(p.efl, f, 1e-9 * f);
    assert_near(p.bfl, b, 1e-9 * f);
    /* A 93 mm achromat focused by the file within 1 um of its focus. */
    assert_near(lens.surf[2].thickness, b, 1e-3);
    assert_near(f, 93.12, 0.01);
    lens_free(&lens);
}

/* Even asphere in cm: coefficients on r^(2i) scale by 10^(1-2i) into mm, so the sag at
 * h = 5 mm is 10 x the sag the cm coefficients give at h = 0.5 cm. Paraxially the
 * asphere is its base sphere: R 40, -200, t 6, n 1.6 thick lens. */
static void test_asphere_units(void **state)
{
    (void)state;
    lens_t lens;
    load(DATA "asphere.zmx", NULL, &lens);
    const lens_surface *s = &lens.surf[0];
    assert_near(s->conic, -0.6, 0);
    assert_near(s->asphere[0], 1e-3 * 1e-3, 1e-18); /* 0.001 cm^-3 */
    assert_near(s->asphere[1], -2e-4 * 1e-5, 1e-21); /* -0.0002 cm^-5 */
    double h = 0.5, c = 0.25, k = -0.6;
    double sag_cm = c * h * h / (1 + sqrt(1 - (1 + k) * c * c * h * h)) + 1e-3 * pow(h, 4) -
                    2e-4 * pow(h, 6);
    assert_near(lens_sag(s, 25.0), 10 * sag_cm, 1e-12);
    double n = 1.6, R1 = 40, R2 = -200, t = 6;
    double f = 1 / ((n - 1) * (1 / R1 - 1 / R2 + (n - 1) * t / (n * R1 * R2)));
    assert_near(first_order(&lens).efl, f, 1e-9);
    assert_near(first_order(&lens).bfl, f * (1 - (n - 1) * t / (n * R1)), 1e-9);
    lens_free(&lens);
}

/* The Cooke triplet of Zemax's classic example (f = 50 mm) with SK16 and F2 from the AGF. */
static void test_cooke(void **state)
{
    (void)state;
    lens_t lens;
    load(DATA "cooke.zmx", &with_catalog, &lens);
    assert_int_equal(lens.nsurf, 6);
    assert_int_equal(lens.stop, 3);
    double nsk, nf;
    lens_err err;
    assert_int_equal(glass_index(&lens.surf[0].medium, GLASS_D_LINE, &nsk, &err), 0);
    assert_int_equal(glass_index(&lens.surf[2].medium, GLASS_D_LINE, &nf, &err), 0);
    assert_near(nsk, 1.62041, 3e-5); /* Schott SK16 */
    assert_near(nf, 1.62004, 3e-5);  /* Schott F2 */
    double R[] = {22.01359, -435.7604, -22.21328, 20.29192, 79.6836, -18.39533};
    double t[] = {3.25896, 6.00755, 0.99997, 4.75041, 2.95208, 0};
    double n[] = {nsk, 1, nf, 1, nsk, 1}, f, b;
    table_first_order(6, R, t, n, &f, &b);
    paraxial_data p = first_order(&lens);
    assert_near(p.efl, f, 1e-9 * f);
    assert_near(p.bfl, b, 1e-9 * f);
    assert_near(p.efl, 50, 0.05); /* the design's focal length */
    /* ENPD 10: the stop is scaled so that the entrance pupil is 10 mm (f/5.002). */
    assert_near(p.entrance_pupil_diameter, 10, 1e-9);
    assert_near(p.fnumber, f / 10, 1e-9);
    assert_near(lens.fnumber, f / 10, 1e-9);
    assert_non_null(strstr(lens.notes, "stop semi-diameter"));
    lens_free(&lens);
}

/* Tronnier's double Gauss (US 2,673,491) scaled to f = 50 mm, model glasses. */
static void test_double_gauss(void **state)
{
    (void)state;
    lens_t lens;
    load(DATA "dgauss.zmx", NULL, &lens);
    assert_int_equal(lens.nsurf, 11);
    assert_int_equal(lens.stop, 5);
    assert_near(lens.fnumber, 2, 0);
    double R[] = {29.475, 84.83, 19.275, 40.77, 12.75, 0, -14.495, 40.77, -20.385, 437.065, -39.73};
    double t[] = {3.76, 0.12, 4.025, 3.275, 5.705, 4.5, 1.18, 6.065, 0.19, 3.22, 0};
    double n[] = {1.67, 1, 1.67, 1.699, 1, 1, 1.603, 1.658, 1, 1.717, 1}, f, b;
    table_first_order(11, R, t, n, &f, &b);
    paraxial_data p = first_order(&lens);
    assert_near(p.efl, f, 1e-9 * f);
    assert_near(p.bfl, b, 1e-9 * f);
    assert_true(near_rel(p.efl, 50, 0.01)); /* the patent's 100 mm, halved */
    assert_near(p.fnumber, 2, 1e-12);       /* FNUM 2 */
    lens_free(&lens);
}

static const char *const HEAD = "VERS 1\nUNIT MM\nSURF 0\n  DISZ INFINITY\n";

static void expect_error(const char *body, const char *want1, const char *want2)
{
    char text[2048];
    snprintf(text, sizeof text, "%s%s", HEAD, body);
    lens_t lens;
    lens_err err;
    if (parse(text, &with_catalog, &lens, &err) == 0)
        fail_msg("accepted a file it should refuse (%s)", want1);
    if (!strstr(err.msg, want1) || (want2 && !strstr(err.msg, want2)))
        fail_msg("message '%s' lacks '%s' / '%s'", err.msg, want1, want2 ? want2 : "");
    assert_int_equal(lens.nsurf, 0);
}

static void test_refusals(void **state)
{
    (void)state;
    expect_error("SURF 1\n  STOP\n  CURV 0.01\n  DISZ 5\n  GLAS N-BK7\n  DIAM 5\n"
                 "SURF 2\n  CURV 0\n  DISZ 20\n  GLAS MIRROR\n  DIAM 5\nSURF 3\n  DISZ 0\n",
                 "mem.zmx:14: surface 2", "mirror");
    expect_error("SURF 1\n  STOP\n  CURV 0.01\n  DISZ 5\n  GLAS N-BK7\n  DIAM 5\n"
                 "SURF 2\n  TYPE COORDBRK\n  DISZ 0\n  PARM 1 0\n  PARM 3 45\n"
                 "SURF 3\n  CURV -0.01\n  DISZ 50\n  DIAM 5\nSURF 4\n  DISZ 0\n",
                 "surface 2", "coordinate break");
    expect_error("SURF 1\n  STOP\n  TYPE TOROIDAL\n  CURV 0.01\n  DISZ 5\n  DIAM 5\n"
                 "SURF 2\n  DISZ 0\n",
                 "surface 1", "TOROIDAL");
    expect_error("SURF 1\n  STOP\n  TYPE EVENASPH\n  CURV 0.01\n  DISZ 5\n  DIAM 5\n"
                 "  PARM 1 0.001\nSURF 2\n  DISZ 0\n",
                 "surface 1", "r^2");
    expect_error("SURF 1\n  STOP\n  CURV 0.01\n  DISZ 5\n  DIAM 5\n  DECX 0.5\nSURF 2\n  DISZ 0\n",
                 "surface 1", "decentred");
    expect_error("SURF 1\n  CURV 0.01\n  DISZ 5\n  DIAM 5\n", "surfaces", NULL);
    expect_error("SURF 1\n  CURV zero\n", "mem.zmx:6", "CURV");
    expect_error("SURF 2\n", "SURF 2", "surface number 1");
    expect_error("UNIT FURLONG\n", "FURLONG", NULL);

    lens_t lens;
    lens_err err;
    const char *nsc = "VERS 1\nMODE NSC\n";
    assert_int_not_equal(parse(nsc, NULL, &lens, &err), 0);
    assert_non_null(strstr(err.msg, "non-sequential"));
    /* A zero coordinate break is a plain gap: accepted, merged. */
    char text[1024];
    snprintf(text, sizeof text, "%s%s", HEAD,
             "SURF 1\n  STOP\n  CURV 0.02\n  DISZ 5\n  GLAS ___BLANK 1 0 1.5 60\n  DIAM 5\n"
             "SURF 2\n  CURV -0.02\n  DISZ 10\n  DIAM 5\n"
             "SURF 3\n  TYPE COORDBRK\n  DISZ 39.152542372881356\n  PARM 1 0\n  PARM 3 0\n"
             "SURF 4\n  DISZ 0\n");
    if (parse(text, NULL, &lens, &err) != 0)
        fail_msg("%s", err.msg);
    assert_int_equal(lens.nsurf, 2);
    assert_near(lens.surf[1].thickness, 49.152542372881356, 1e-12);
    lens_free(&lens);
}

/* The system aperture against a hard clear aperture (CLAP) on the stop, which is the
 * first surface, so the entrance pupil is the stop itself: EPD = 2 x semi-diameter.
 * ENPD 8 shrinks the stop to 4; ENPD 12 cannot open it past CLAP 5. */
static void test_aperture_vs_clap(void **state)
{
    (void)state;
    static const double enpd[] = {8, 12}, want_sd[] = {4, 5};
    for (int i = 0; i < 2; i++) {
        char text[1024];
        snprintf(text, sizeof text,
                 "VERS 1\nENPD %g\nSURF 0\n  DISZ INFINITY\nSURF 1\n  STOP\n  CURV 0.02\n"
                 "  DISZ 5\n  GLAS ___BLANK 1 0 1.5 60\n  DIAM 5\n  CLAP 0 5 0\nSURF 2\n"
                 "  CURV -0.02\n  DISZ 49\n  DIAM 5\nSURF 3\n  DISZ 0\n",
                 enpd[i]);
        lens_t lens;
        lens_err err;
        if (parse(text, NULL, &lens, &err) != 0)
            fail_msg("%s", err.msg);
        double f = 1 / (0.5 * (0.04 - 2.5 / 3750));
        assert_near(lens.surf[0].semi_diameter, want_sd[i], 1e-9);
        assert_near(first_order(&lens).fnumber, f / (2 * want_sd[i]), 1e-9);
        assert_near(lens.fnumber, f / enpd[i], 1e-9); /* the file's nominal f-number */
        assert_true((strstr(lens.notes, "clear aperture 5 mm is kept") != NULL) == (i == 1));
        lens_free(&lens);
    }
}

/* Without the extension the content decides: the BOM, or a VERS line; RDM for CODE V. */
static void test_sniffed(void **state)
{
    (void)state;
    static const char *const names[] = {"singlet.zmx", "singlet_cm.zmx", "singlet.seq"};
    for (int i = 0; i < 3; i++) {
        char src[128], dst[128];
        snprintf(src, sizeof src, DATA "%s", names[i]);
        snprintf(dst, sizeof dst, "/tmp/sparselens-sniff-%ld-%d.txt", (long)getpid(), i);
        size_t len;
        char *data = slurp(src, &len);
        FILE *f = fopen(dst, "wb");
        assert_non_null(f);
        assert_int_equal(fwrite(data, 1, len, f), len);
        fclose(f);
        free(data);
        lens_t lens;
        load(dst, NULL, &lens);
        assert_near(first_order(&lens).efl, 1 / (0.5 * (0.04 - 2.5 / 3750)), 1e-9);
        lens_free(&lens);
        remove(dst);
    }
}

/* A glass in no catalog: the message names it and the catalogs searched; with the
 * n_d/V_d fallback the file's values are used and the fallback is noted. */
static void test_missing_glass(void **state)
{
    (void)state;
    char text[1024];
    snprintf(text, sizeof text, "%s%s", HEAD,
             "SURF 1\n  STOP\n  CURV 0.02\n  DISZ 5\n  GLAS XG-NOPE 0 0 1.6 40 0 0 0 0 0 0\n"
             "  DIAM 5\nSURF 2\n  CURV -0.02\n  DISZ 40\n  DIAM 5\nSURF 3\n  DISZ 0\n");
    lens_t lens;
    lens_err err;
    assert_int_not_equal(parse(text, &with_catalog, &lens, &err), 0);
    assert_non_null(strstr(err.msg, "mem.zmx:9: glass XG-NOPE not found in"));
    assert_non_null(strstr(err.msg, "test.agf"));
    /* 1.6 and 40 beside a catalog glass are placeholders: never recommended, never used. */
    assert_null(strstr(err.msg, "--glass-fallback"));
    assert_non_null(strstr(err.msg, "placeholders"));
    /* With GCAT, the message says which maker catalogs the design used. */
    char with_gcat[1100];
    snprintf(with_gcat, sizeof with_gcat, "GCAT SCHOTT OHARA\n%s", text);
    assert_int_not_equal(parse(with_gcat, &with_catalog, &lens, &err), 0);
    assert_non_null(strstr(err.msg, "the file names the catalogs SCHOTT OHARA"));
    lens_load_options fb = {.catalogs = test_catalogs, .ndvd_fallback = 1};
    assert_int_not_equal(parse(text, &fb, &lens, &err), 0);
    assert_non_null(strstr(err.msg, "placeholders"));
    /* A catalog glass's own values (five decimals) are data: recommended, then used. */
    char *ph = strstr(text, "1.6 40");
    memmove(ph + 13, ph + 6, strlen(ph + 6) + 1);
    memcpy(ph, "1.61272 58.63", 13);
    assert_int_not_equal(parse(text, &with_catalog, &lens, &err), 0);
    assert_non_null(strstr(err.msg, "--glass-fallback ndvd would use them"));
    if (parse(text, &fb, &lens, &err) != 0)
        fail_msg("%s", err.msg);
    assert_int_equal(lens.surf[0].medium.kind, GLASS_NDVD);
    assert_near(lens.surf[0].medium.nd, 1.61272, 0);
    assert_near(lens.surf[0].medium.vd, 58.63, 0);
    assert_non_null(strstr(lens.notes, "XG-NOPE"));
    lens_free(&lens);
}

/* Truncated and damaged copies of every test file: an error or a lens, never a crash
 * (the sanitizer build checks the memory side). */
static void test_truncated(void **state)
{
    (void)state;
    static const char *const files[] = {"singlet.zmx", "singlet_cm.zmx", "doublet.zmx",
                                        "asphere.zmx", "cooke.zmx", "dgauss.zmx"};
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        char path[256];
        snprintf(path, sizeof path, DATA "%s", files[i]);
        size_t len;
        char *data = slurp(path, &len);
        check_truncations(lens_parse_zmx, path, data, len, &with_catalog);
        size_t step = len / 23 + 1;
        /* a byte flipped in the middle of each line's number */
        for (size_t at = 7; at < len; at += step) {
            char *copy = malloc(len);
            memcpy(copy, data, len);
            copy[at] = (char)(copy[at] ^ 0x15);
            lens_t lens;
            lens_err err;
            if (lens_parse_zmx(copy, len, path, &with_catalog, &lens, &err) == 0)
                lens_free(&lens);
            free(copy);
        }
        free(data);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_singlet_utf16),   cmocka_unit_test(test_singlet_cm_8bit),
        cmocka_unit_test(test_doublet_catalog), cmocka_unit_test(test_asphere_units),
        cmocka_unit_test(test_cooke),           cmocka_unit_test(test_double_gauss),
        cmocka_unit_test(test_refusals),        cmocka_unit_test(test_missing_glass),
        cmocka_unit_test(test_truncated),       cmocka_unit_test(test_sniffed),
        cmocka_unit_test(test_aperture_vs_clap),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
