/* Ideal projections through GeographicLib against their closed forms. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>

#include "sparselens/projection.h"

static void closed_forms(void **state)
{
    (void)state;
    const double f = 25.0;
    for (int i = 0; i <= 178; i += 2) {
        double t = i * M_PI / 180;
        double want[PROJ_COUNT] = {i < 90 ? f * tan(t) : NAN, f * t, 2 * f * sin(t / 2),
                                   2 * f * tan(t / 2), i <= 90 ? f * sin(t) : NAN};
        for (int k = 0; k < PROJ_COUNT; k++) {
            double r = proj_radius((proj_kind)k, f, t);
            if (isnan(want[k])) {
                assert_true(isnan(r));
                continue;
            }
            /* relative 1e-12 of the radius, absolute 1e-12 mm near the axis */
            assert_true(fabs(r - want[k]) <= 1e-12 * (1 + fabs(want[k])));
        }
    }
}

static void angle_between_directions(void **state)
{
    (void)state;
    /* dot product gives the angle independently */
    double dirs[][3] = {{0, 0, 1}, {1, 0, 0}, {0.3, -0.4, 0.5}, {-0.2, 0.9, -0.7}, {0, 0, -1},
                        {1e-9, 0, 1}};
    for (size_t i = 0; i < 6; i++)
        for (size_t j = 0; j < 6; j++) {
            double *a = dirs[i], *b = dirs[j];
            double na = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            double nb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
            double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2],
                   cz = a[0] * b[1] - a[1] * b[0];
            double want = atan2(sqrt(cx * cx + cy * cy + cz * cz) / (na * nb),
                                (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (na * nb));
            assert_true(fabs(proj_angle(a, b) - want) < 1e-12);
        }
}

static void points_keep_azimuth(void **state)
{
    (void)state;
    /* A direction (x, y, z) in front of the lens maps rectilinearly to f (x/z, y/z). */
    const double f = 10;
    double d[][3] = {{0.1, 0.2, 1}, {-0.5, 0.05, 1}, {0.7, -0.7, 1}, {0, 0, 1}};
    for (int i = 0; i < 4; i++) {
        double xy[2];
        assert_int_equal(proj_point(PROJ_RECTILINEAR, f, d[i], xy), 0);
        assert_true(fabs(xy[0] - f * d[i][0] / d[i][2]) < 1e-11);
        assert_true(fabs(xy[1] - f * d[i][1] / d[i][2]) < 1e-11);
        /* equidistant: radius f theta along the same azimuth */
        assert_int_equal(proj_point(PROJ_EQUIDISTANT, f, d[i], xy), 0);
        double rho = hypot(d[i][0], d[i][1]), th = atan2(rho, d[i][2]);
        if (rho > 0) {
            assert_true(fabs(xy[0] - f * th * d[i][0] / rho) < 1e-11);
            assert_true(fabs(xy[1] - f * th * d[i][1] / rho) < 1e-11);
        }
    }
    /* Behind the lens: no gnomonic image, but an equidistant one past 90 degrees. */
    double back[3] = {1, 0, -0.2}, xy[2];
    assert_int_equal(proj_point(PROJ_RECTILINEAR, f, back, xy), -1);
    assert_int_equal(proj_point(PROJ_EQUIDISTANT, f, back, xy), 0);
    assert_true(fabs(xy[0] - f * atan2(1, -0.2)) < 1e-11);
}

static void inverse_round_trip(void **state)
{
    (void)state;
    for (int k = 0; k < PROJ_COUNT; k++)
        for (int i = 1; i < 90; i += 7) {
            double t = i * M_PI / 180, r = proj_radius((proj_kind)k, 7.0, t);
            assert_true(fabs(proj_theta((proj_kind)k, 7.0, r) - t) < 1e-12);
        }
}

static void names(void **state)
{
    (void)state;
    proj_kind k;
    for (int i = 0; i < PROJ_COUNT; i++) {
        assert_int_equal(proj_parse(proj_name((proj_kind)i), &k), 0);
        assert_int_equal(k, i);
    }
    assert_int_equal(proj_parse("fisheye", &k), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(closed_forms),
        cmocka_unit_test(angle_between_directions),
        cmocka_unit_test(points_keep_azimuth),
        cmocka_unit_test(inverse_round_trip),
        cmocka_unit_test(names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
