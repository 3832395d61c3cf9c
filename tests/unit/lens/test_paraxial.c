/* First-order optics against closed forms: the thick-lens (lensmaker's) equation,
 * Gaussian imaging, and a two-lens system by the separated-thin-lens formulas. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "fixture_lenses.h"
#include "sparselens/paraxial.h"

static void near(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.12g, want %.12g (tol %g)", got, want, tol);
}

static void test_thick_singlet_lensmaker(void **state)
{
    (void)state;
    const double n = 1.5168, r1 = 50, r2 = -80, d = 6, sd = 10;
    lens_t l;
    lens_init(&l);
    fixture_add(&l, r1, d, n, sd, 1);
    fixture_add(&l, r2, 90, 1.0, sd, 0);
    lens_err err;
    assert_int_equal(lens_finish(&l, &err), 0);
    paraxial_data p;
    assert_int_equal(paraxial_compute(&l, GLASS_D_LINE, &p, &err), 0);
    double phi = (n - 1) * (1 / r1 - 1 / r2 + (n - 1) * d / (n * r1 * r2));
    double f = 1 / phi;
    near(p.efl, f, 1e-9);
    /* Back focal distance of a thick lens: f (1 - (n-1) d / (n r1)). */
    near(p.bfl, f * (1 - (n - 1) * d / (n * r1)), 1e-9);
    /* Front focal distance: -f (1 + (n-1) d / (n r2)). */
    near(p.ffl, -f * (1 + (n - 1) * d / (n * r2)), 1e-9);
    /* Stop on the first surface: entrance pupil there, diameter 2 sd. */
    near(p.entrance_pupil_z, 0, 1e-12);
    near(p.entrance_pupil_diameter, 2 * sd, 1e-12);
    near(p.fnumber, f / (2 * sd), 1e-9);
    near(p.total_track, d + 90, 1e-12);
    lens_free(&l);
}

static void test_two_thin_lenses(void **state)
{
    (void)state;
    /* Thin lenses as equi-convex singlets of negligible thickness; the stop at the first.
     * Apertures small enough that the faces do not cross (lens_finish refuses that). */
    const double n = 1.5, f1 = 100, f2 = 50, sep = 30, sd = 0.2;
    const double r1 = 2 * (n - 1) * f1, r2 = 2 * (n - 1) * f2, eps = 1e-6;
    lens_t l;
    lens_init(&l);
    fixture_add(&l, r1, eps, n, sd, 1);
    fixture_add(&l, -r1, sep, 1.0, sd, 0);
    fixture_add(&l, r2, eps, n, sd, 0);
    fixture_add(&l, -r2, 40, 1.0, sd, 0);
    lens_err err;
    assert_int_equal(lens_finish(&l, &err), 0);
    paraxial_data p;
    assert_int_equal(paraxial_compute(&l, GLASS_D_LINE, &p, &err), 0);
    double f = 1 / (1 / f1 + 1 / f2 - sep / (f1 * f2));
    near(p.efl, f, 1e-5);
    near(p.bfl, f * (1 - sep / f1), 1e-5);
    near(p.ffl, -f * (1 - sep / f2), 1e-5);
    /* Exit pupil: the stop (lens 1) imaged by lens 2 from sep in front of it. */
    double s_img = 1 / (1 / f2 - 1 / sep);
    near(p.exit_pupil_z, s_img, 1e-4);
    near(p.exit_pupil_diameter, 2 * sd * fabs(s_img / sep), 1e-4);
    lens_free(&l);
}

static void test_focus_distance_gaussian(void **state)
{
    (void)state;
    /* A thin lens of focal length f focused at distance d: the sensor at 1/(1/f - 1/d). */
    const double n = 1.5, f = 50, r = 2 * (n - 1) * f, d = 1000;
    lens_t l;
    lens_init(&l);
    fixture_add(&l, r, 1e-7, n, 0.2, 1); /* faces that do not cross: sd^2 / r within 1e-3 mm */
    fixture_add(&l, -r, 50, 1.0, 0.2, 0);
    lens_err err;
    assert_int_equal(lens_finish(&l, &err), 0);
    double t;
    assert_int_equal(paraxial_focus_thickness(&l, GLASS_D_LINE, d, &t, &err), 0);
    near(t, 1 / (1 / f - 1 / d), 1e-4);
    assert_int_equal(paraxial_focus_thickness(&l, GLASS_D_LINE, INFINITY, &t, &err), 0);
    near(t, f, 1e-5);
    l.surf[1].thickness = 1 / (1 / f - 1 / d);
    paraxial_data p;
    assert_int_equal(paraxial_compute(&l, GLASS_D_LINE, &p, &err), 0);
    near(p.focus_distance, d, 1e-3);
    /* Stopping down halves the stop radius for twice the f-number. */
    double fn = p.fnumber;
    assert_int_equal(lens_set_fnumber(&l, 2 * fn, &err), 0);
    near(l.surf[0].semi_diameter, 0.1, 1e-12);
    assert_int_not_equal(lens_set_fnumber(&l, fn / 2, &err), 0);
    lens_free(&l);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_thick_singlet_lensmaker),
        cmocka_unit_test(test_two_thin_lenses),
        cmocka_unit_test(test_focus_distance_gaussian),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
