/* lens-distort's library: distortion against closed forms and a direct chief-ray
 * trace, symmetry of the grid map, relative illumination of a thin lens. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/distort.h"
#include "fixture_lenses.h"

/* A thin biconvex lens with the stop on it, sensor in the paraxial focal plane. */
static void thin_lens(lens_t *l)
{
    assert_int_equal(fixture_singlet(l, 50, -50, 0.03, 1.5, 0, 1.0, 50), 0);
    l->surf[1].thickness = fixture_bfl(l);
    lens_err err;
    assert_int_equal(lens_finish(l, &err), 0);
}

static void thin_lens_has_no_distortion(void **state)
{
    (void)state;
    lens_t l;
    thin_lens(&l);
    imaging im = {.lens = &l, .object_distance = INFINITY};
    double field[4] = {0, 1, 2, 3};
    distort_row rows[4];
    lens_err err;
    assert_int_equal(distort_curve(&im, GLASS_D_LINE, field, 4, 0, rows, &err), 0);
    double f = fixture_efl(&l);
    for (int i = 0; i < 4; i++) {
        /* ideal height is f tan(theta) with the independently computed focal length */
        assert_true(fabs(rows[i].h_ideal - f * tan(field[i] * M_PI / 180)) < 1e-9);
        assert_true(fabs(rows[i].dist_pct) < 0.01);
        assert_true(fabs(rows[i].x_real) < 1e-12);
    }
    lens_free(&l);
}

static void thin_lens_illumination_is_cos4(void **state)
{
    (void)state;
    lens_t l;
    thin_lens(&l);
    /* no vignetting: every other aperture is the stop's size and the field is small */
    imaging im = {.lens = &l, .object_distance = INFINITY};
    double field[3] = {0, 5, 10};
    distort_row rows[3];
    lens_err err;
    assert_int_equal(distort_curve(&im, GLASS_D_LINE, field, 3, 16, rows, &err), 0);
    for (int i = 0; i < 3; i++) {
        double c = cos(field[i] * M_PI / 180);
        /* the grid's cells on the pupil's edge: about a tenth of a percent */
        assert_true(fabs(rows[i].rel_illum - c * c * c * c) < 0.005);
    }
    lens_free(&l);
}

/* The same thin lens focused on an object 1000 mm away: the image height is the
 * thin-lens magnification f / (D - f) times the object height (no distortion), and
 * the illumination falls as cos^4 of the chief ray's angle. */
static void thin_lens_finite_object(void **state)
{
    (void)state;
    lens_t l;
    thin_lens(&l);
    const double D = 1000;
    imaging im = {.lens = &l, .object_distance = D};
    lens_err err;
    double shift;
    assert_int_equal(imaging_paraxial_shift(&l, D, GLASS_D_LINE, &shift, &err), 0);
    im.sensor_shift = shift;
    double field[3] = {0, 100, 250};
    distort_row rows[3];
    assert_int_equal(distort_curve(&im, GLASS_D_LINE, field, 3, 48, rows, &err), 0);
    double f = fixture_efl(&l), m = f / (D - f);
    for (int i = 0; i < 3; i++) {
        /* the lens is 0.03 mm thick: its principal planes sit within 0.02 mm of the stop */
        assert_true(fabs(rows[i].h_ideal - m * field[i]) < 2e-5 * m * field[i] + 1e-12);
        assert_true(fabs(rows[i].dist_pct) < 0.01);
        double c = cos(atan(field[i] / D));
        assert_true(fabs(rows[i].rel_illum - c * c * c * c) < 0.01);
    }
    lens_free(&l);
}

/* Chief ray found here without ray aiming: the object ray of direction d that meets
 * the stop plane at y = 0, by bisection on its height in front of the lens, traced
 * through a copy of the lens cut at the stop. */
static double direct_chief_height(const lens_t *l, double deg)
{
    lens_t front;
    assert_int_equal(lens_copy(&front, l), 0);
    front.nsurf = (size_t)l->stop + 1;
    front.surf[l->stop].thickness = 0;
    lens_err err;
    if (lens_finish(&front, &err) != 0)
        fail_msg("%s", err.msg);
    double n[64], nf[64];
    assert_int_equal(lens_indices(l, GLASS_D_LINE, n, &err), 0);
    assert_int_equal(lens_indices(&front, GLASS_D_LINE, nf, &err), 0);
    double a = deg * M_PI / 180, d[3] = {0, sin(a), cos(a)};
    /* y at the stop as a function of the height b where the ray would cross z = 0:
     * scan for a sign change between passing rays, then bisect */
    double sd = l->surf[0].semi_diameter, lo = NAN, hi = NAN, prev_b = NAN, prev_y = NAN;
    for (int k = 0; k <= 4000 && isnan(lo); k++) {
        double b = -3 * sd + 6 * sd * k / 4000;
        lens_ray r = {{0, b - 40 * d[1], -40 * d[2]}, {d[0], d[1], d[2]}};
        if (trace_to_sensor(&front, nf, &r).status != TRACE_PASSED) {
            prev_b = NAN;
            continue;
        }
        if (!isnan(prev_b) && (prev_y <= 0) != (r.o[1] <= 0))
            lo = prev_b, hi = b;
        prev_b = b, prev_y = r.o[1];
    }
    assert_false(isnan(lo));
    for (int it = 0; it < 100; it++) {
        double m = 0.5 * (lo + hi);
        lens_ray r = {{0, m - 40 * d[1], -40 * d[2]}, {d[0], d[1], d[2]}};
        assert_int_equal(trace_to_sensor(&front, nf, &r).status, TRACE_PASSED);
        if ((r.o[1] <= 0) == (prev_y <= 0))
            hi = m;
        else
            lo = m;
    }
    double b = 0.5 * (lo + hi);
    lens_ray r = {{0, b - 40 * d[1], -40 * d[2]}, {d[0], d[1], d[2]}};
    trace_result res = trace_to_sensor(l, n, &r);
    assert_int_equal(res.status, TRACE_PASSED);
    lens_free(&front);
    return r.o[1];
}

static void dgauss_distortion_as_chief_rays_say(void **state)
{
    (void)state;
    lens_t l;
    assert_int_equal(fixture_dgauss50(&l), 0);
    imaging im = {.lens = &l, .object_distance = INFINITY};
    double field[3] = {5, 10, 14};
    distort_row rows[3];
    lens_err err;
    assert_int_equal(distort_curve(&im, GLASS_D_LINE, field, 3, 0, rows, &err), 0);
    double f = fixture_efl(&l);
    for (int i = 0; i < 3; i++) {
        double h = direct_chief_height(&l, field[i]);
        double want = 100 * (h - f * tan(field[i] * M_PI / 180)) / (f * tan(field[i] * M_PI / 180));
        assert_true(fabs(rows[i].h_real - h) < 1e-6);
        assert_true(fabs(rows[i].dist_pct - want) < 1e-4);
        /* the double Gauss has a little barrel distortion, growing with the field */
        assert_true(rows[i].dist_pct < 0 && rows[i].dist_pct > -3);
        if (i > 0)
            assert_true(rows[i].dist_pct < rows[i - 1].dist_pct);
    }
    lens_free(&l);
}

static void fisheye_distortion_as_chief_rays_say(void **state)
{
    (void)state;
    lens_t l;
    assert_int_equal(fixture_fisheye_ii(&l), 0);
    imaging im = {.lens = &l, .object_distance = INFINITY};
    double field[3] = {20, 45, 70};
    distort_row rows[3];
    lens_err err;
    assert_int_equal(distort_curve(&im, GLASS_D_LINE, field, 3, 0, rows, &err), 0);
    double f = fixture_efl(&l);
    for (int i = 0; i < 3; i++) {
        double h = direct_chief_height(&l, field[i]);
        double t = field[i] * M_PI / 180;
        assert_true(fabs(rows[i].h_real - h) < 1e-6);
        /* strongly barrel against f tan(theta), far closer to the fisheye mappings */
        double rect = 100 * (h - f * tan(t)) / (f * tan(t));
        assert_true(fabs(rows[i].dist_pct - rect) < 1e-4);
        assert_true(rows[i].dist_pct < -5 * i);
        double equisolid = 100 * (h - 2 * f * sin(t / 2)) / (2 * f * sin(t / 2));
        assert_true(fabs(rows[i].map_pct[PROJ_EQUISOLID] - equisolid) < 1e-4);
        assert_true(fabs(rows[i].map_pct[PROJ_EQUISOLID]) < fabs(rows[i].dist_pct));
    }
    double rms;
    proj_kind best = distort_best_mapping(rows, 3, &rms);
    assert_int_not_equal(best, PROJ_RECTILINEAR);
    lens_free(&l);
}

/* Two models compared on the fields both image. Rows by hand: fields 10, 20, 30 with
 * equisolid distortion 1, 2, 3 (lens) and 1, 2, - (system: it cannot image 30). Over
 * the common fields both RMS are sqrt((1 + 4) / 2); the lens alone over its three fields
 * would be sqrt(14 / 3). */
static void test_best_mappings_common_fields(void **st)
{
    (void)st;
    distort_row rows[6];
    memset(rows, 0, sizeof rows);
    for (int m = 0; m < 2; m++)
        for (int i = 0; i < 3; i++) {
            distort_row *r = &rows[m * 3 + i];
            r->field = 10 * (i + 1);
            for (int k = 0; k < PROJ_COUNT; k++)
                r->map_pct[k] = 50; /* every other mapping worse */
            r->map_pct[PROJ_EQUISOLID] = i + 1;
        }
    snprintf(rows[5].why, sizeof rows[5].why, "no chief ray");
    proj_kind best[2];
    double rms[2];
    assert_int_equal(distort_best_mappings(rows, 2, 3, best, rms), 1);
    for (int m = 0; m < 2; m++) {
        assert_int_equal(best[m], PROJ_EQUISOLID);
        assert_true(fabs(rms[m] - sqrt(2.5)) < 1e-12);
    }
    assert_int_equal(distort_best_mappings(rows, 1, 3, best, rms), 0); /* the lens alone */
    assert_true(fabs(rms[0] - sqrt(14.0 / 3)) < 1e-12);
}

/* Forward brute force, independent of lens-distort's integral from the sensor: the
 * irradiance of a uniform sky around the chief ray's point of field th0, as the power of
 * collimated beams (directions th0 +- 3 deg, each beam a grid over its cross-section,
 * the whole sky by rotational symmetry: 2 pi sin(theta) dtheta) landing under a smooth
 * radial window cos^2(pi (r - h0) / (2 w)), over the window's area integral. */
static double sky_irradiance(const imaging *im, const double *n, double th0)
{
    const double w = 0.1, range = 3;
    const int nth = 40, coarse = 240, fine = 150;
    double s[4], eta, h0 = 0;
    lens_err err;
    if (th0 > 0) {
        assert_int_equal(imaging_chief(im, n, GLASS_D_LINE, th0, s, &err), 0);
        h0 = hypot(s[0], s[1]);
    }
    double ext = 0, power = 0, tlo = fmax(0, th0 - range), dt = (th0 + range - tlo) / nth;
    for (size_t i = 0; i < im->lens->nsurf; i++)
        ext = fmax(ext, 1.5 * im->lens->surf[i].semi_diameter);
    for (int it = 0; it < nth; it++) {
        double th = tlo + (it + 0.5) * dt;
        lens_ray chief;
        if (imaging_object_ray(im, n, th, 0, 0, &chief) != 0)
            continue;
        const double *d = chief.d;
        double e2[3] = {0, d[2], -d[1]}; /* d x (1, 0, 0) */
#define BEAM_RAY(r, a, b)                                                                    \
    for (int k = 0; k < 3; k++)                                                             \
        r.o[k] = chief.o[k] - 100 * d[k] + (k == 0 ? (a) : 0) + (b) * e2[k], r.d[k] = d[k]
        /* the beam's passing cross-section, then a fine grid over it */
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, c = 2 * ext / coarse, sum = 0;
        for (int i = 0; i < coarse; i++)
            for (int j = 0; j < coarse; j++) {
                double a = -ext + (i + 0.5) * c, b = -ext + (j + 0.5) * c;
                lens_ray r;
                BEAM_RAY(r, a, b);
                if (imaging_trace(im, n, GLASS_D_LINE, &r, NULL, s, &eta))
                    lo[0] = fmin(lo[0], a - 2 * c), hi[0] = fmax(hi[0], a + 2 * c),
                    lo[1] = fmin(lo[1], b - 2 * c), hi[1] = fmax(hi[1], b + 2 * c);
            }
        if (!(lo[0] < hi[0]))
            continue;
        double ca = (hi[0] - lo[0]) / fine, cb = (hi[1] - lo[1]) / fine;
        for (int i = 0; i < fine; i++)
            for (int j = 0; j < fine; j++) {
                lens_ray r;
                BEAM_RAY(r, lo[0] + (i + 0.5) * ca, lo[1] + (j + 0.5) * cb);
                if (imaging_trace(im, n, GLASS_D_LINE, &r, NULL, s, &eta)) {
                    double t = (hypot(s[0], s[1]) - h0) / w;
                    if (fabs(t) < 1)
                        sum += eta * cos(M_PI_2 * t) * cos(M_PI_2 * t);
                }
            }
#undef BEAM_RAY
        power += 2 * M_PI * sin(th * M_PI / 180) * dt * M_PI / 180 * sum * ca * cb;
    }
    double area = 0, r0 = fmax(0, h0 - w);
    for (int k = 0; k < 4000; k++) {
        double r = r0 + (k + 0.5) * (h0 + w - r0) / 4000, t = (r - h0) / w;
        area += cos(M_PI_2 * t) * cos(M_PI_2 * t) * 2 * M_PI * r * (h0 + w - r0) / 4000;
    }
    return power / area;
}

/* The fisheye's relative illumination is the irradiance a uniform sky gives on the
 * sensor: within 1% of the forward brute force at 60 and 90 degrees. The older figure,
 * the flux of the field's beam over the image area the chief-ray heights give, assumed
 * the beam lands where its chief ray does; with this lens's pupil aberration it came
 * out 3.5% low at 60 degrees and 16% low at 90 (0.214 against 0.255). */
static void fisheye_illumination_is_the_sky_irradiance(void **state)
{
    (void)state;
    lens_t l;
    assert_int_equal(fixture_fisheye_ii(&l), 0);
    imaging im = {.lens = &l, .object_distance = INFINITY};
    double field[3] = {0, 60, 90}, n[64];
    distort_row rows[3];
    lens_err err;
    assert_int_equal(imaging_indices(&im, GLASS_D_LINE, n, &err), 0);
    assert_int_equal(distort_curve(&im, GLASS_D_LINE, field, 3, 32, rows, &err), 0);
    double e0 = sky_irradiance(&im, n, 0);
    for (int i = 1; i < 3; i++) {
        double ri = sky_irradiance(&im, n, field[i]) / e0;
        print_message("field %g: relative illumination %.5f, brute force %.5f\n", field[i], rows[i].rel_illum, ri);
        assert_true(fabs(rows[i].rel_illum - ri) < 0.01 * ri);
    }
    lens_free(&l);
}

static void symmetric_lens_grid_is_radial(void **state)
{
    (void)state;
    lens_t l;
    assert_int_equal(fixture_dgauss50(&l), 0);
    imaging im = {.lens = &l, .object_distance = INFINITY};
    const int n = 7;
    double *pts = malloc(sizeof(double) * 4 * n * n);
    double f = fixture_efl(&l);
    int good = distort_grid(&im, GLASS_D_LINE, PROJ_RECTILINEAR, f, 12, 8, n, n, pts);
    assert_int_equal(good, n * n);
    double maxd = 0;
    for (int i = 0; i < n * n; i++) {
        const double *p = pts + 4 * i;
        double dx = p[2] - p[0], dy = p[3] - p[1], r = hypot(p[0], p[1]);
        maxd = fmax(maxd, hypot(dx, dy));
        /* displacement along the radius: the cross product vanishes */
        assert_true(fabs(p[0] * dy - p[1] * dx) <= 1e-9 * (1 + r));
        /* barrel: inwards */
        assert_true(dx * p[0] + dy * p[1] <= 1e-12);
    }
    assert_true(maxd > 0.01); /* there is something to see */
    free(pts);
    lens_free(&l);
}

/* OpenCV's fisheye model describes the fisheye to a small fraction of a pixel, with k1
 * near the equisolid projection's -1/24 (2 f sin(t/2) = f t (1 - t^2/24 + ...)), which
 * the lens follows within a few percent; Brown-Conrady cannot follow it. */
static void opencv_models_of_the_fisheye(void **state)
{
    (void)state;
    lens_t l;
    assert_int_equal(fixture_fisheye_ii(&l), 0);
    imaging im = {.lens = &l, .object_distance = INFINITY};
    const int n = 13;
    double *pts = malloc(sizeof(double) * 4 * n * n), f = fixture_efl(&l);
    assert_true(distort_grid(&im, GLASS_D_LINE, PROJ_EQUISOLID, f, 11.8, 7.85, n, n, pts) > 100);
    cv_camera_fit fe, br;
    lens_err err;
    assert_int_equal(distort_opencv(&im, GLASS_D_LINE, 1, PROJ_EQUISOLID, pts, n * n, f, 11.8, 7.85,
                                    2000, 1330, 85, &fe, &err), 0);
    assert_true(fe.rms < 0.05);
    assert_true(fabs(fe.k[0] + 1.0 / 24) < 0.01);
    assert_true(fabs(fe.cx - 1000) < 1e-9 && fabs(fe.cy - 665) < 1e-9);
    assert_int_equal(distort_opencv(&im, GLASS_D_LINE, 0, PROJ_EQUISOLID, pts, n * n, f, 11.8, 7.85,
                                    2000, 1330, 80, &br, &err), 0);
    assert_true(br.rms > 20 * fe.rms);
    free(pts);
    lens_free(&l);
}

static void bad_fields(void **state)
{
    (void)state;
    lens_t l;
    assert_int_equal(fixture_dgauss50(&l), 0);
    imaging im = {.lens = &l, .object_distance = INFINITY};
    double field[2] = {0, 70};
    distort_row rows[2];
    lens_err err;
    /* 70 degrees is past what the double Gauss images: that row is nan and says why,
     * the axis row is computed all the same */
    assert_int_equal(distort_curve(&im, GLASS_D_LINE, field, 2, 0, rows, &err), 0);
    assert_string_equal(rows[0].why, "");
    assert_true(rows[0].h_real == 0);
    assert_non_null(strstr(rows[1].why, "field 70"));
    assert_true(isnan(rows[1].h_real) && isnan(rows[1].dist_pct));
    lens_free(&l);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_best_mappings_common_fields),
        cmocka_unit_test(thin_lens_has_no_distortion),
        cmocka_unit_test(thin_lens_illumination_is_cos4),
        cmocka_unit_test(thin_lens_finite_object),
        cmocka_unit_test(dgauss_distortion_as_chief_rays_say),
        cmocka_unit_test(fisheye_distortion_as_chief_rays_say),
        cmocka_unit_test(fisheye_illumination_is_the_sky_irradiance),
        cmocka_unit_test(symmetric_lens_grid_is_radial),
        cmocka_unit_test(opencv_models_of_the_fisheye),
        cmocka_unit_test(bad_fields),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
