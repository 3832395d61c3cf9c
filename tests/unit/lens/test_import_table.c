/* The table importers (import_table.h): pbrt's .dat and the 2016 set's .fx, their traps
 * checked against what the reference files say by themselves, and their errors (each
 * message must name the file and the line). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lens_files_fixture.h"
#include "sparselens/lens.h"
#include "sparselens/paraxial.h"

/* Distance from the last surface to where a ray from infinity (y = 1, nu = 0) crosses
 * the axis: zero when the sensor sits at the paraxial focus. */
static double defocus_height(const lens_t *l)
{
    double n[64], y, nu;
    for (size_t i = 0; i < l->nsurf; i++)
        n[i] = glass_index_unchecked(&l->surf[i].medium, GLASS_D_LINE);
    paraxial_trace_forward(l, n, 1.0, 0.0, &y, &nu);
    return y;
}

static void test_pbrt_dgauss(void **state)
{
    (void)state;
    need_reference();
    lens_t l;
    load_ok(REF "/pbrt/dgauss.50mm.dat", &l);
    assert_int_equal(l.nsurf, 11);
    near(l.surf[0].semi_diameter, 25.2 / 2, 0); /* the column is a diameter */
    assert_int_equal(l.stop, 5);                /* radius 0 */
    assert_true(isinf(l.surf[5].radius));
    assert_int_equal(l.surf[5].medium.kind, GLASS_AIR); /* n 0 */
    assert_int_equal(l.surf[1].medium.kind, GLASS_AIR); /* n 1 */
    near(l.surf[0].medium.nd, 1.67, 0);
    near(l.surf[0].thickness, 3.76, 0); /* to the next surface */
    /* Last row 0: focus decides. */
    near(defocus_height(&l), 0, 1e-9);
    paraxial_data p;
    lens_err err;
    assert_int_equal(paraxial_compute(&l, GLASS_D_LINE, &p, &err), 0);
    near(p.efl, 50, 1.0); /* the file's name: 50 mm */
    near(l.surf[10].thickness, p.bfl, 1e-9);
    lens_free(&l);
}

static void test_pbrt_wide_shift(void **state)
{
    (void)state;
    need_reference();
    lens_t l;
    load_ok(REF "/pbrt/wide.dat", &l);
    assert_int_equal(l.nsurf, 13);
    /* Thickness column is from the previous surface: row 2's 5.529 separates rows 1, 2. */
    near(l.surf[0].thickness, 5.529, 0);
    near(l.surf[1].thickness, 45.435, 0);
    near(l.surf[11].thickness, 5.529, 0);
    near(l.surf[0].semi_diameter, 107.8 / 2, 0);
    assert_int_equal(l.stop, 5);
    near(defocus_height(&l), 0, 1e-9);
    assert_non_null(strstr(l.notes, "previous surface"));
    lens_free(&l);
}

static void test_pbrt_errors(void **state)
{
    (void)state;
    lens_t l;
    lens_err err;
    const char *p = write_file("bad.dat", "# c\n50 5 1.5 20\n0 2 0\n-50 40 1 20\n");
    assert_int_not_equal(lens_load(p, NULL, &l, &err), 0);
    char want[300];
    snprintf(want, sizeof want, "%s:3: ", p);
    assert_non_null(strstr(err.msg, want));
    p = write_file("bad2.dat", "50 5 1.5 20\n10 2 x 10\n");
    assert_int_not_equal(lens_load(p, NULL, &l, &err), 0);
    assert_non_null(strstr(err.msg, ":2: 'x'"));
    p = write_file("nostop.dat", "50 5 1.5 20\n-50 40 1 20\n");
    assert_int_not_equal(lens_load(p, NULL, &l, &err), 0);
    assert_non_null(strstr(err.msg, "no aperture stop"));
}

static void test_fx_fisheye_ii(void **state)
{
    (void)state;
    need_reference();
    lens_t l;
    load_ok(REF "/fx/fisheye-ii.fx", &l);
    assert_int_equal(l.nsurf, 18); /* the commented "#10000 0.100 air 500" is not a surface */
    near(l.surf[0].radius, 85, 0);
    near(l.surf[0].semi_diameter, 26, 0); /* housing radius = semi-diameter */
    near(l.surf[0].medium.nd, 1.62041, 0);
    near(l.surf[0].medium.vd, 60.29, 0);
    assert_int_equal(l.stop, 12);
    assert_true(isinf(l.surf[12].radius)); /* 10000 = flat */
    near(l.surf[13].radius, -1732, 0);     /* large, but a real radius */
    near(l.surf[17].thickness, 41.1, 0);
    lens_free(&l);
}

static void test_fx_scale(void **state)
{
    (void)state;
    need_reference();
    lens_t l;
    load_ok(REF "/fx/kreitzer-tele.fx", &l);
    near(l.surf[0].radius, 33.072 * 4, 1e-12);
    near(l.surf[0].thickness, 2.366 * 4, 1e-12);
    near(l.surf[0].semi_diameter, 8.9 * 4, 1e-12);
    near(l.focal, 400, 1e-12); /* #EFL 100, scaled */
    near(l.surf[0].medium.nd, 1.518, 0);
    lens_free(&l);
    load_ok(REF "/fx/double-gauss-angenieux.fx", &l);
    near(l.surf[0].radius, 164.12 * 0.5, 1e-12);
    assert_int_equal(l.stop, 7); /* IRIS */
    near(l.focal, 50, 1e-12);
    assert_string_equal(l.surf[0].medium.name, "SF5"); /* in the catalog */
    /* BAF10, an old Schott name, is read as its successor N-BAF10 of the catalog */
    assert_int_not_equal(l.surf[2].medium.kind, GLASS_NDVD);
    near(l.surf[2].medium.nd, 1.67003, 1e-5);
    lens_free(&l);
}

/* Scaling an asphere by s must give the same shape, s times larger:
 * sag_s(s h) = s sag(h). */
static void test_fx_scale_asphere(void **state)
{
    (void)state;
    char *a = strdup(write_file("a.fx", "30 5 abbe 1.5 50 10 #!aspheric=-0.7,1e-4,-2e-6,3e-8,-4e-10\n"
                                       "1e5 2 iris 8\n-50 40 air 10\n"));
    const char *b = write_file("b.fx", "#!scale 2.5\n30 5 abbe 1.5 50 10 #!aspheric=-0.7,1e-4,-2e-6,3e-8,-4e-10\n"
                                       "1e5 2 iris 8\n-50 40 air 10\n");
    lens_t la, lb;
    load_ok(a, &la);
    load_ok(b, &lb);
    near(la.surf[0].conic, -0.7, 0);
    near(la.surf[0].asphere[3], -4e-10, 0);
    for (double h = 0; h <= 9; h += 1.5)
        near(lens_sag(&lb.surf[0], 2.5 * 2.5 * h * h), 2.5 * lens_sag(&la.surf[0], h * h), 1e-12);
    lens_free(&la);
    lens_free(&lb);
    free(a);
}

static void test_fx_traps(void **state)
{
    (void)state;
    need_reference();
    lens_t l;
    lens_err err;
    /* Zoom thicknesses take the first position; CRLF lines; // comments. */
    load_ok(REF "/fx/nikon-zoom.fx", &l);
    assert_int_equal(l.nsurf, 22);
    near(l.surf[4].thickness, 1.86, 0);
    near(l.surf[9].thickness, 36.928, 0);
    near(l.surf[21].thickness, 40.08, 0);
    near(l.surf[21].semi_diameter, 12.6, 0);
    near(l.focal, 80, 0); /* #EFL 80 140 200 */
    assert_non_null(strstr(l.notes, "zoom"));
    lens_free(&l);
    /* Cylinders are refused, naming the line. */
    assert_int_not_equal(lens_load(REF "/fx/canon-anamorphic.fx", NULL, &l, &err), 0);
    assert_non_null(strstr(err.msg, "canon-anamorphic.fx:28: "));
    assert_non_null(strstr(err.msg, "not rotationally symmetric"));
    /* Extra columns after the housing radius ("- 0.326" included) are ignored. */
    load_ok(REF "/fx/wideangle.fx", &l);
    assert_int_equal(l.nsurf, 26);
    near(l.surf[0].semi_diameter, 20, 0);
    near(l.surf[10].semi_diameter, 10, 0);
    assert_int_equal(l.stop, 17);
    lens_free(&l);
    /* Commented-out prescriptions and trailing "# 240.0" comments. */
    load_ok(REF "/fx/fisheye.fx", &l);
    assert_int_equal(l.nsurf, 24);
    near(l.surf[0].radius, 143.47, 0);
    near(l.surf[10].semi_diameter, 16.5, 0);
    lens_free(&l);
    /* #!aspheric on surfaces 7, 8, 10, 11. */
    load_ok(REF "/fx/fisheye-aspherical.fx", &l);
    near(l.surf[6].asphere[0], -1.5313e-5, 0);
    near(l.surf[6].asphere[3], 8.7528e-12, 0);
    near(l.surf[10].asphere[1], -1.3527e-5, 0);
    assert_false(lens_surface_is_aspheric(&l.surf[5]));
    lens_free(&l);
    /* Catalog names beat the placeholder 1.5/50. */
    load_ok(REF "/fx/lensbaby.fx", &l);
    assert_string_equal(l.surf[0].medium.name, "N-SSK8");
    assert_string_equal(l.surf[1].medium.name, "N-SF10");
    paraxial_data p;
    assert_int_equal(paraxial_compute(&l, GLASS_D_LINE, &p, &err), 0);
    near(p.efl, 120, 0.5); /* Edmund #NT32-921: EFL 120 mm */
    lens_free(&l);
}

static void test_fx_errors(void **state)
{
    (void)state;
    lens_t l;
    lens_err err;
    const char *p = write_file("e.fx", "# c\n30 5 glassy 10\n1e5 2 iris 8\n-50 40 air 10\n");
    assert_int_not_equal(lens_load(p, NULL, &l, &err), 0);
    assert_non_null(strstr(err.msg, "e.fx:2: "));
    p = write_file("e2.fx", "30 5 abbe 1.5 50 10\n-50 40 air 10\n");
    assert_int_not_equal(lens_load(p, NULL, &l, &err), 0);
    assert_non_null(strstr(err.msg, "no aperture stop"));
    p = write_file("e3.fx", "30 5 abbe 1.5 50 10 #!aspheric=0,x\n1e5 2 iris 8\n");
    assert_int_not_equal(lens_load(p, NULL, &l, &err), 0);
    assert_non_null(strstr(err.msg, "e3.fx:1: "));
    p = write_file("e4.fx", "#!scale -1\n30 5 abbe 1.5 50 10\n1e5 2 iris 8\n");
    assert_int_not_equal(lens_load(p, NULL, &l, &err), 0);
    assert_non_null(strstr(err.msg, "e4.fx:1: "));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pbrt_dgauss),
        cmocka_unit_test(test_pbrt_wide_shift),
        cmocka_unit_test(test_pbrt_errors),
        cmocka_unit_test(test_fx_fisheye_ii),
        cmocka_unit_test(test_fx_scale),
        cmocka_unit_test(test_fx_scale_asphere),
        cmocka_unit_test(test_fx_traps),
        cmocka_unit_test(test_fx_errors),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
