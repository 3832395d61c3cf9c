/* The checks every lens passes whatever format it came in: glass numbers in range in all
 * five readers, the hemisphere limit of a semi-diameter, and consecutive surfaces that
 * do not cross. Expected values come from closed forms (the sag of a sphere, the height
 * where two spheres meet), not from the code under test. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "glass.h"
#include "import.h"
#include "lens.h"

static char tmpdir[64];

static int setup(void **state)
{
    (void)state;
    strcpy(tmpdir, "/tmp/test_lens_checks_XXXXXX");
    if (!mkdtemp(tmpdir))
        return -1;
    setenv("SPARSELENS_GLASS_CATALOG", "lenses/glass.catalog", 1);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    return system(cmd) == 0 ? 0 : -1;
}

static const char *write_file(const char *name, const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

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
        cmocka_unit_test(test_glass_ranges),
        cmocka_unit_test(test_finish_checks_media),
        cmocka_unit_test(test_hemisphere),
        cmocka_unit_test(test_crossing),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
