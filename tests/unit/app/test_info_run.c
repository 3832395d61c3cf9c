/* lens-info's job without a process: refocusing against Gaussian imaging through the
 * thick lens's ABCD matrix, the notes it replaces, the sensor it takes from the options,
 * and the field of view of a bare stop against its geometry (the chief ray goes straight
 * from the sensor point through the stop centre). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "fixture_lenses.h"
#include "sparselens/info_run.h"

static void near(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.12g, want %.12g (tol %g)", got, want, tol);
}

static void refocus_follows_gaussian_imaging(void **state)
{
    (void)state;
    const double n = 1.5168, r1 = 50, r2 = -80, d = 6, object = 1000;
    lens_t l;
    lens_init(&l);
    fixture_add(&l, r1, d, n, 10, 1);
    fixture_add(&l, r2, 90, 1.0, 10, 0);
    snprintf(l.notes, sizeof l.notes, "focus set for infinity\nskipped a coating");
    lens_err err;
    assert_int_equal(lens_finish(&l, &err), 0);

    info_cli o;
    info_cli_default(&o);
    o.focus = object;
    o.sensor = (cli_size){10, 8};
    assert_int_equal(info_prepare(&o, &l, &err), 1); /* printed as a lens */

    /* vertex-to-vertex matrix (y, n u): refraction, glass, refraction */
    double p1 = (n - 1) / r1, p2 = (1 - n) / r2;
    double A = 1 - d / n * p1, B = d / n;
    double C = -p1 - p2 + p1 * p2 * d / n, D = 1 - d / n * p2;
    /* the object `object` in front: image distance behind the last vertex */
    double image = -(A * object + B) / (C * object + D);
    near(l.surf[1].thickness, image, 1e-9 * image);
    assert_true(l.sensor_w == 10 && l.sensor_h == 8);
    assert_null(strstr(l.notes, "focus set for infinity"));
    assert_non_null(strstr(l.notes, "skipped a coating"));
    assert_non_null(strstr(l.notes, "refocused by lens-info --focus 1000"));

    info_report rep;
    o.focus = NAN;
    assert_int_equal(info_run(&o, &l, &rep, &err), 0);
    near(rep.p.focus_distance, object, 1e-6 * object);
    lens_free(&l);
}

static void bare_stop_field_of_view(void **state)
{
    (void)state;
    const double distance = 20, w = 36, h = 24;
    lens_t l;
    lens_init(&l);
    fixture_add(&l, INFINITY, distance, 1.0, 5, 1);
    lens_err err;
    assert_int_equal(lens_finish(&l, &err), 0);

    info_cli o;
    info_cli_default(&o);
    info_report rep;
    assert_int_equal(info_prepare(&o, &l, &err), 0); /* printed as keys */
    assert_int_equal(info_run(&o, &l, &rep, &err), 0);
    assert_false(rep.have_sensor);
    assert_true(isnan(rep.field_of_view_deg));

    l.sensor_w = w, l.sensor_h = h;
    assert_int_equal(info_run(&o, &l, &rep, &err), 0);
    assert_true(rep.have_sensor);
    double r = 0.5 * hypot(w, h);
    near(rep.sensor_radius, r, 1e-12);
    near(rep.image_circle_radius, r, 1e-9);
    near(rep.field_of_view_deg, 2 * atan(r / distance) * 180 / M_PI, 1e-6);
    assert_true(rep.p.afocal); /* no power: the command warns */
    lens_free(&l);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(refocus_follows_gaussian_imaging),
        cmocka_unit_test(bare_stop_field_of_view),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
