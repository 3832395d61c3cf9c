/* Lens files: the native format's round trip and every parser error (each message must
 * name the file and the line), glass look-up order, the format chosen by extension or
 * content, and the checks every lens passes whatever its format (test_import_table.c:
 * the .fx and .dat importers). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "lens/lens_material.h"
#include "lens_files_fixture.h"
#include "sparselens/lens.h"
#include "sparselens/paraxial.h"

/* ---- native format ------------------------------------------------------------ */

static const char *full_lens =
    "# name: test triplet\n"
    "# source: made up for test_lens_io.c\n"
    "# focal: 50.5\n"
    "# fnumber : 2.8\n"
    "# sensor: 36x24\n"
    "# note: first note\n"
    "# note: second note\n"
    "# radius thickness material semi-diameter\n"
    "\n"
    "85.00      2.040      1.62041/60.29   26   # a trailing comment\n"
    "16.45      8.320      air             15.5 k=-0.5 a4=1.25e-5 a12=-3e-20\n"
    "inf        0.30000000000000004  1.7   14\n"
    "40.1       3          N-BK7           14 stop\n"
    "60         5          N-SF10          14 k=0.1 a6=2e-8 a8=-1e-11 a10=5e-14\n"
    "-60        40.123456789012345 air     14\n";

static void assert_same_lens(const lens_t *a, const lens_t *b)
{
    assert_string_equal(a->name, b->name);
    assert_string_equal(a->source, b->source);
    assert_string_equal(a->notes, b->notes);
    assert_true(a->focal == b->focal && a->fnumber == b->fnumber);
    assert_true(a->sensor_w == b->sensor_w && a->sensor_h == b->sensor_h);
    assert_int_equal(a->nsurf, b->nsurf);
    assert_int_equal(a->stop, b->stop);
    for (size_t i = 0; i < a->nsurf; i++) {
        const lens_surface *s = &a->surf[i], *t = &b->surf[i];
        assert_true(s->radius == t->radius && s->thickness == t->thickness);
        assert_true(s->semi_diameter == t->semi_diameter && s->conic == t->conic);
        for (int k = 0; k < LENS_ASPHERE_TERMS; k++)
            assert_true(s->asphere[k] == t->asphere[k]);
        assert_int_equal(s->is_stop, t->is_stop);
        assert_int_equal(s->medium.kind, t->medium.kind);
        assert_true(s->medium.nd == t->medium.nd && s->medium.vd == t->medium.vd);
        assert_string_equal(s->medium.name, t->medium.name);
    }
}

static void test_native_parse(void **state)
{
    (void)state;
    const char *path = write_file("full.lens", full_lens);
    lens_t l;
    lens_err err;
    if (lens_load(path, NULL, &l, &err) != 0)
        fail_msg("%s", err.msg);
    assert_string_equal(l.name, "test triplet");
    assert_string_equal(l.notes, "first note\nsecond note");
    near(l.focal, 50.5, 0);
    near(l.fnumber, 2.8, 0); /* spaces before the colon are allowed */
    near(l.sensor_w, 36, 0);
    near(l.sensor_h, 24, 0);
    assert_int_equal(l.nsurf, 6);
    assert_int_equal(l.stop, 3); /* a curved stop with glass after it */
    assert_int_equal(l.surf[3].medium.kind, GLASS_FORMULA);
    assert_string_equal(l.surf[3].medium.name, "N-BK7");
    assert_int_equal(l.surf[0].medium.kind, GLASS_NDVD);
    assert_int_equal(l.surf[2].medium.kind, GLASS_CONSTANT);
    assert_true(isinf(l.surf[2].radius));
    near(l.surf[2].thickness, 0.1 + 0.2, 0);
    near(l.surf[1].conic, -0.5, 0);
    near(l.surf[1].asphere[0], 1.25e-5, 0);
    near(l.surf[1].asphere[4], -3e-20, 0);
    near(l.surf[4].asphere[3], 5e-14, 0);
    assert_int_equal(l.surf[4].line, 14);
    near(l.vertex_z[5], 2.04 + 8.32 + (0.1 + 0.2) + 3 + 5, 1e-12);
    lens_free(&l);
}

static void test_native_round_trip(void **state)
{
    (void)state;
    const char *path = write_file("rt.lens", full_lens);
    lens_t a, b;
    lens_err err;
    assert_int_equal(lens_load(path, NULL, &a, &err), 0);
    /* Awkward values: every digit must survive. */
    a.surf[0].radius = 1.0 / 3.0;
    a.surf[0].radius = 85 + 1e-13;
    a.surf[1].asphere[2] = -1.0 / 7.0 * 1e-9;
    a.surf[5].thickness = 0.1 + 0.7;
    char *text = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&text, &len);
    assert_int_equal(lens_write(m, &a), 0);
    fclose(m);
    path = write_file("rt2.lens", text);
    if (lens_load(path, NULL, &b, &err) != 0)
        fail_msg("%s\n%s", err.msg, text);
    assert_same_lens(&a, &b);
    /* Writing the re-read lens gives the same text. */
    char *text2 = NULL;
    m = open_memstream(&text2, &len);
    lens_write(m, &b);
    fclose(m);
    assert_string_equal(text, text2);
    free(text);
    free(text2);
    lens_free(&a);
    lens_free(&b);
}

static void test_fmt_double(void **state)
{
    (void)state;
    char buf[32];
    const double v[] = {10, 400, 0.1, 1.0 / 3, 1e-20, -2.5e17, 123456789.125, 5e-324, 1.7976931348623157e308};
    for (size_t i = 0; i < sizeof v / sizeof *v; i++) {
        lens_fmt_double(v[i], buf);
        assert_true(strtod(buf, NULL) == v[i]);
    }
    lens_fmt_double(10, buf);
    assert_string_equal(buf, "10");
    lens_fmt_double(-INFINITY, buf);
    assert_string_equal(buf, "-inf");
}

/* The message must start with "PATH:LINE: " and contain `what`. */
static void expect_error(const char *text, long line, const char *what)
{
    const char *path = write_file("bad.lens", text);
    lens_t l;
    lens_err err;
    if (lens_load(path, NULL, &l, &err) == 0)
        fail_msg("accepted:\n%s", text);
    char want[300];
    snprintf(want, sizeof want, "%s:%ld: ", path, line);
    if (strncmp(err.msg, want, strlen(want)) != 0 || !strstr(err.msg, what))
        fail_msg("message '%s' lacks '%s' or '%s'", err.msg, want, what);
    assert_int_equal(l.nsurf, 0);
}

#define GOOD "50 5 1.5 10\n-50 40 stop 10\n"

static void test_native_errors(void **state)
{
    (void)state;
    expect_error("abc 5 1.5 10\n-50 40 stop 10\n", 1, "radius 'abc'");
    expect_error(GOOD "0 5 air 10\n", 3, "radius 0");
    expect_error("50 nan 1.5 10\n-50 40 stop 10\n", 1, "thickness 'nan'");
    expect_error("50 inf 1.5 10\n-50 40 stop 10\n", 1, "thickness 'inf'");
    expect_error("50 5 1.5 -10\n-50 40 stop 10\n", 1, "semi-diameter '-10'");
    expect_error("50 5 1.5 inf\n-50 40 stop 10\n", 1, "semi-diameter 'inf'");
    expect_error("50 5 1.5 1e400\n-50 40 stop 10\n", 1, "semi-diameter");
    expect_error("# name: x\n50 5 N-UNOBTAINIUM 10\n-50 40 stop 10\n", 2, CATALOG);
    expect_error("# name: x\n50 5 N-UNOBTAINIUM 10\n-50 40 stop 10\n", 2,
                 "unknown material 'N-UNOBTAINIUM'");
    expect_error("# colour: red\n" GOOD, 1, "unknown header key 'colour'");
    expect_error("# focal: -5\n" GOOD, 1, "focal");
    expect_error("# focal: nan\n" GOOD, 1, "focal");
    expect_error("# sensor: 36by24\n" GOOD, 1, "sensor");
    expect_error("# name: a\n# name: b\n" GOOD, 2, "twice");
    expect_error(GOOD "50 5 1.5\n", 3, "3 fields found");
    expect_error(GOOD "50\n", 3, "1 field found");
    expect_error("50 5 1.5 10 a5=1\n-50 40 stop 10\n", 1, "unknown surface coefficient 'a5'");
    expect_error("50 5 1.5 10 k=1 k=2\n-50 40 stop 10\n", 1, "twice");
    expect_error("50 5 1.5 10 k=nan\n-50 40 stop 10\n", 1, "not a finite number");
    expect_error("50 5 1.5 10 extra\n-50 40 stop 10\n", 1, "unexpected field 'extra'");
    expect_error("50 5 0.9 10\n-50 40 stop 10\n", 1, "below 1");
    expect_error("50 5 1.5/x 10\n-50 40 stop 10\n", 1, "nd/Vd");
    expect_error("50 5 1.5/-3 10\n-50 40 stop 10\n", 1, "Abbe");
    expect_error("50 5 1.5 10 stop stop\n-50 40 air 10\n", 1, "twice");
    expect_error("", 1, "empty file");
    expect_error("# just a comment\n\n", 2, "no surfaces");
    expect_error("50 5 1.5 10\n-50 40 air 10\n# end\n", 3, "no aperture stop");
    expect_error("50 5 stop 10\n-50 40 stop 10\n", 2, "second aperture stop");
    expect_error("5 1 1.5 10\n-50 40 stop 10\n", 1, "semi-diameter 10 exceeds");
    expect_error("50 -5 1.5 10\n-50 40 stop 10\n", 1, "thickness");
}

/* A lens in its own directory with its own glass.catalog: the options' catalogs come
 * first, then the one beside the lens, then the default. */
static void test_glass_lookup_order(void **state)
{
    (void)state;
    char dir[128], path[160], local[160], extra[160];
    snprintf(dir, sizeof dir, "%s/sub", tmpdir);
    mkdir(dir, 0700);
    snprintf(local, sizeof local, "%s/glass.catalog", dir);
    snprintf(extra, sizeof extra, "%s/extra.catalog", tmpdir);
    snprintf(path, sizeof path, "%s/l.lens", dir);
    FILE *f = fopen(local, "w");
    /* Conrady with only n0: a constant index, easy to tell apart. */
    fputs("LOCAL1 conrady 1.6 0 0 0.3 2.5 1.6 0\nN-BK7 conrady 1.55 0 0 0.3 2.5 1.55 0\n", f);
    fclose(f);
    f = fopen(extra, "w");
    fputs("N-BK7 conrady 1.65 0 0 0.3 2.5 1.65 0\n", f);
    fclose(f);
    f = fopen(path, "w");
    fputs("50 5 LOCAL1 10\n-50 2 stop 10\n50 5 N-BK7 10\n-50 40 N-SF6 10\n", f);
    fclose(f);
    lens_t l;
    lens_err err;
    if (lens_load(path, NULL, &l, &err) != 0)
        fail_msg("%s", err.msg);
    near(l.surf[0].medium.nd, 1.6, 0);
    near(l.surf[2].medium.nd, 1.55, 0);   /* beside the lens beats the default */
    near(l.surf[3].medium.nd, 1.80518, 0); /* only in the default catalog */
    lens_free(&l);
    const char *cats[] = {extra, NULL};
    lens_load_options opt = {.catalogs = cats};
    assert_int_equal(lens_load(path, &opt, &l, &err), 0);
    near(l.surf[2].medium.nd, 1.65, 0); /* the options' catalog beats both */
    lens_free(&l);
    /* A broken catalog is reported with its own file and line. */
    f = fopen(extra, "w");
    fputs("N-BK7 conrady 1.65 0\n", f);
    fclose(f);
    assert_int_not_equal(lens_load(path, &opt, &l, &err), 0);
    char want[200];
    snprintf(want, sizeof want, "%s:1: ", extra);
    assert_non_null(strstr(err.msg, want));
}

static void test_load_dispatch(void **state)
{
    (void)state;
    lens_t l;
    lens_err err;
    /* Unknown extension: content decides. */
    const char *p = write_file("x.txt", "# pbrt-like\n#  radius axpos N aperture\n"
                                        "50 5 1.5 20\n0 2 0 10\n-50 40 1 20\n");
    assert_int_equal(lens_load(p, NULL, &l, &err), 0);
    near(l.surf[0].semi_diameter, 10, 0); /* read as pbrt: a diameter */
    assert_string_equal(l.name, "pbrt-like"); /* its first comment names it, as pbrt's do */
    lens_free(&l);
    p = write_file("y.txt", "50 5 abbe 1.5 50 10\n1e5 2 iris 8\n-50 40 air 10\n");
    assert_int_equal(lens_load(p, NULL, &l, &err), 0);
    assert_int_equal(l.stop, 1);
    lens_free(&l);
    p = write_file("z.txt", "50 5 1.5 10\n-50 40 stop 10\n");
    assert_int_equal(lens_load(p, NULL, &l, &err), 0);
    near(l.surf[0].semi_diameter, 10, 0);
    lens_free(&l);
    assert_int_not_equal(lens_load("/nonexistent.lens", NULL, &l, &err), 0);
    assert_non_null(strstr(err.msg, "/nonexistent.lens"));
}

/* ---- checks every lens passes, whatever its format ------------------------------
 * Glass numbers in range in all five readers, the hemisphere limit of a semi-diameter,
 * consecutive surfaces that do not cross. Expected values from closed forms. */

/* Loading name (with text) fails at line, with what in the message. */
static void refused(const char *name, const char *text, long line, const char *what)
{
    const char *path = write_file(name, text);
    lens_t l;
    lens_err err;
    if (lens_load(path, NULL, &l, &err) == 0)
        fail_msg("%s accepted:\n%s", name, text);
    char want[300];
    snprintf(want, sizeof want, "%s:%ld: ", path, line);
    if (strncmp(err.msg, want, strlen(want)) != 0 || !strstr(err.msg, what))
        fail_msg("message '%s' lacks '%s' or '%s'", err.msg, want, what);
    assert_int_equal(l.nsurf, 0);
}

static void accepted(const char *name, const char *text, lens_t *l)
{
    const char *path = write_file(name, text);
    lens_err err;
    if (lens_load(path, NULL, l, &err) != 0)
        fail_msg("%s refused: %s", name, err.msg);
}

/* n_d below 1, absurdly high, and V_d <= 0 where a model glass needs it: refused at the
 * material's line by each reader. */
static void test_glass_ranges(void **state)
{
    (void)state;
    refused("a.lens", "50 5 0.6/40 10\n-50 40 stop 10\n", 1, "below 1");
    refused("b.lens", "50 5 1e17/40 10\n-50 40 stop 10\n", 1, "above 3");
    refused("c.lens", "50 5 3.5 10\n-50 40 stop 10\n", 1, "above 3");
    refused("d.lens", "50 5 1.5/0 10\n-50 40 stop 10\n", 1, "Abbe");
    refused("a.dat", "50 5 1e17 20\n0 2 0 10\n-50 40 1 20\n", 1, "above 3");
    refused("a.fx", "# c\n30 5 abbe 3.2 50 10\n1e5 2 iris 8\n-50 40 air 10\n", 2, "above 3");
    refused("b.fx", "# c\n30 5 abbe 0.8 50 10\n1e5 2 iris 8\n-50 40 air 10\n", 2, "below 1");
    refused("c.fx", "# c\n30 5 abbe 1.5 0 10\n1e5 2 iris 8\n-50 40 air 10\n", 2, "Abbe");
    /* CODE V: n_d:V_d and six-digit codes carry V_d, so 0 there is a bad code */
    refused("a.seq", "SO 0 1e10\nS 50 5 0.6:40; CIR 5; STO\nS -50 40; CIR 5\nSI 0 0\n", 2,
            "below 1");
    refused("b.seq", "SO 0 1e10\nS 50 5 4.1:40; CIR 5; STO\nS -50 40; CIR 5\nSI 0 0\n", 2,
            "above 3");
    refused("c.seq", "SO 0 1e10\nS 50 5 1.5:0; CIR 5; STO\nS -50 40; CIR 5\nSI 0 0\n", 2,
            "Abbe");
    refused("d.seq", "SO 0 1e10\nS 50 5 517000; CIR 5; STO\nS -50 40; CIR 5\nSI 0 0\n", 2,
            "Abbe");
    static const char zmx[] = "VERS 1\nUNIT MM\nSURF 0\n  DISZ INFINITY\nSURF 1\n  STOP\n"
                              "  CURV 0.02\n  DISZ 5\n  GLAS ___BLANK 1 0 %s %s 0 0 0 0 0\n"
                              "  DIAM 5\nSURF 2\n  CURV -0.02\n  DISZ 40\n  DIAM 5\nSURF 3\n"
                              "  DISZ 0\n";
    char text[400];
    snprintf(text, sizeof text, zmx, "0.6", "40");
    refused("a.zmx", text, 9, "below 1");
    snprintf(text, sizeof text, zmx, "1e17", "40");
    refused("b.zmx", text, 9, "above 3");
    snprintf(text, sizeof text, zmx, "1.5", "-2");
    refused("c.zmx", text, 9, "Abbe");
    /* Zemax's V_d 0 is a model glass without dispersion: a bare index */
    lens_t l;
    snprintf(text, sizeof text, zmx, "1.5", "0");
    accepted("d.zmx", text, &l);
    assert_int_equal(l.surf[0].medium.kind, GLASS_CONSTANT);
    lens_free(&l);
    /* the limits themselves are glasses */
    accepted("e.lens", "50 5 3/40 10\n-50 40 stop 10\n", &l);
    lens_free(&l);
    accepted("f.lens", "50 5 1 10\n-50 40 stop 10\n", &l);
    lens_free(&l);
}

/* A lens built in code meets the same range in lens_finish. */
static void test_finish_checks_media(void **state)
{
    (void)state;
    lens_t l;
    lens_init(&l);
    strcpy(l.path, "mem.lens");
    lens_surface *s = lens_add_surface(&l);
    s->radius = 50;
    s->thickness = 5;
    s->semi_diameter = 10;
    s->medium = glass_from_ndvd(0.6, 40);
    s->line = 7;
    s = lens_add_surface(&l);
    s->radius = -50;
    s->thickness = 40;
    s->semi_diameter = 10;
    s->is_stop = 1;
    lens_err err;
    assert_int_not_equal(lens_finish(&l, &err), 0);
    assert_non_null(strstr(err.msg, "7: surface 1"));
    assert_non_null(strstr(err.msg, "below 1"));
    lens_free(&l);
}

/* |R| = sd is a hemisphere, whose rim lies R behind the vertex; R short of sd by 1e-12 of
 * it still is (rounding), by 1e-10 it is not. */
static void test_hemisphere(void **state)
{
    (void)state;
    lens_t l;
    accepted("h.lens", "10 12 1.5/60 10\ninf 1 stop 3\n-20 30 air 8\n", &l);
    assert_true(fabs(lens_sag(&l.surf[0], 100) - 10) < 1e-9);
    lens_free(&l);
    accepted("h2.lens", "-10 12 air 10\ninf 1 stop 3\n-20 30 air 8\n", &l);
    assert_true(fabs(lens_sag(&l.surf[0], 100) + 10) < 1e-9);
    lens_free(&l);
    accepted("h3.lens", "9.99999999999 12 1.5/60 10\ninf 1 stop 3\n-20 30 air 8\n", &l);
    lens_free(&l);
    refused("h4.lens", "9.999999999 12 1.5/60 10\ninf 1 stop 3\n-20 30 air 8\n", 1, "exceeds");
}

/* A biconvex element R1 = 10, R2 = -10, sd = 5: its faces meet where both sags are t/2,
 * h0 = sqrt(R^2 - (R - t/2)^2). With t = 1, h0 = 3.12 mm, well inside 5 mm: no lens.
 * With t = 2 sag(5) = 2 (10 - sqrt(75)) the faces meet exactly at the rim: a knife edge,
 * a lens. */
static void test_crossing(void **state)
{
    (void)state;
    refused("x1.lens", "# c\n10 1 1.5/60 5\n-10 1 air 5\ninf 20 stop 2\n", 2, "cross");
    double h0 = sqrt(100 - 9.5 * 9.5);
    const char *path = write_file("x1b.lens", "10 1 1.5/60 5\n-10 1 air 5\ninf 20 stop 2\n");
    lens_t l;
    lens_err err;
    assert_int_not_equal(lens_load(path, NULL, &l, &err), 0);
    double got = atof(strstr(err.msg, "height ") + 7);
    if (!(fabs(got - h0) <= 5.0 / 256 + 0.01)) /* 256 heights sampled; 3 digits printed */
        fail_msg("crossing at %g, expected %g: %s", got, h0, err.msg);

    char text[200];
    double t = 2 * (10 - sqrt(75));
    snprintf(text, sizeof text, "%.17g %.17g 1.5/60 5\n-10 1 air 5\ninf 20 stop 2\n", 10.0, t);
    accepted("x2.lens", text, &l);
    double h;
    assert_true(fabs(lens_min_gap(&l, 0, &h)) < 1e-9);
    lens_free(&l);
    /* two elements whose air gap closes: a rear face concave to the back (R 10, its rim
     * 10 - sqrt(75) = 1.34 mm behind its vertex) before a front face concave to the front
     * (R -10, its rim 1.34 mm ahead): the gap at h is t - 2 (10 - sqrt(100 - h^2)). */
    refused("x3.lens", "-20 2 1.5/60 5\n10 0.3 air 5\n-10 2 1.5/60 5\ninf 20 stop 2\n", 2,
            "air gap");
    refused("x4.lens", "-20 2 1.5/60 5\n10 1.3 air 5\n-10 2 1.5/60 5\ninf 20 stop 2\n", 2,
            "cross");
    accepted("x5.lens", "-20 2 1.5/60 5\n10 2.7 air 5\n-10 2 1.5/60 5\ninf 20 stop 2\n", &l);
    lens_free(&l);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_native_parse),
        cmocka_unit_test(test_native_round_trip),
        cmocka_unit_test(test_fmt_double),
        cmocka_unit_test(test_native_errors),
        cmocka_unit_test(test_glass_lookup_order),
        cmocka_unit_test(test_load_dispatch),
        cmocka_unit_test(test_glass_ranges),
        cmocka_unit_test(test_finish_checks_media),
        cmocka_unit_test(test_hemisphere),
        cmocka_unit_test(test_crossing),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
