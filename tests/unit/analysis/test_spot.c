/* Spot diagrams through a perfect polynomial system (closed forms), pupil patterns,
 * and the pictures read back. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sparselens/exr_io.h"
#include "fixture_lenses.h"
#include "sparselens/image.h"
#include "sparselens/poly_solve.h"
#include "sparselens/spot_run.h"

static const double F = 50.0; /* focal length of the perfect system */
static const double A = 5.0;  /* stop radius, on the flat front face */

/* A flat window with the stop on its front face: only the geometry the system needs
 * (where object rays meet the front surface). */
static void window(lens_t *l)
{
    assert_int_equal(fixture_singlet(l, 0, 0, 2, 1.5, 0, A, F), 0);
}

/* The ideal lens on the front plane, to first order in every variable:
 * out_x = x + F u, out_y = y + F v (the ray walks F from sensor to lens),
 * out_u = -x / F, out_v = -y / F (every ray from a sensor point leaves parallel to the
 * one through the centre). Every ray of one object direction meets one sensor point. */
static poly_system *perfect_system(void)
{
    const char *in[5] = {"x", "y", "u", "v", "lambda"};
    const char *out[4] = {"out_x", "out_y", "out_u", "out_v"};
    poly_system *s = poly_new("perfect", 5, in, 4, out);
    assert_non_null(s);
    int part = poly_add_part(s, 0, INFINITY);
    assert_true(part >= 0);
    int e[5];
#define TERM(o, i, c)                                                                    \
    do {                                                                                 \
        memset(e, 0, sizeof e);                                                          \
        e[i] = 1;                                                                        \
        assert_int_equal(poly_add_term(s, part, o, e, c), 0);                            \
    } while (0)
    TERM(0, 0, 1.0);
    TERM(0, 2, F);
    TERM(1, 1, 1.0);
    TERM(1, 3, F);
    TERM(2, 0, -1.0 / F);
    TERM(3, 1, -1.0 / F);
#undef TERM
    return s;
}

static void perfect_system_spot_is_a_point(void **state)
{
    (void)state;
    lens_t l;
    window(&l);
    poly_system *sys = perfect_system();
    lens_err err;
    assert_int_equal(poly_solve_check(sys, &err), 0);
    imaging im = {.lens = &l, .sys = sys, .object_distance = INFINITY};
    const double fields[3] = {0, 5, 12};
    for (int i = 0; i < 3; i++) {
        spot sp;
        assert_int_equal(spot_trace(&im, fields[i], GLASS_D_LINE, PUPIL_HEXAPOLAR, 61, 1, &sp, &err), 0);
        assert_int_equal(sp.rays, 61);
        assert_int_equal(sp.passed, 61);
        assert_true(sp.rms_chief < 1e-9);
        assert_true(sp.max_centroid < 1e-9);
        /* the image of direction (0, sin t, cos t) is F sin t */
        assert_true(fabs(sp.centroid[1] - F * sin(fields[i] * M_PI / 180)) < 1e-9);
        spot_free(&sp);
    }
    poly_free(sys);
    lens_free(&l);
}

static void defocus_gives_the_geometric_cone(void **state)
{
    (void)state;
    lens_t l;
    window(&l);
    poly_system *sys = perfect_system();
    lens_err err;
    const double dz = 0.8;
    imaging im = {.lens = &l, .sys = sys, .object_distance = INFINITY, .sensor_shift = dz};
    spot sp;
    assert_int_equal(spot_trace(&im, 0, GLASS_D_LINE, PUPIL_HEXAPOLAR, 127, 1, &sp, &err), 0);
    /* the cone of half-width A / F, cut dz behind its apex */
    assert_true(fabs(sp.max_centroid - dz * A / F) < 1e-8);
    assert_true(fabs(sp.max_chief - dz * A / F) < 1e-8);
    /* and back at the apex: the best focus is found at -dz */
    double back = spot_best_shift(&sp, 1);
    assert_true(fabs(back + dz) < 1e-9);
    spot_shift(&sp, back);
    spot_stats(&sp);
    assert_true(sp.rms_centroid < 1e-9);
    spot_free(&sp);
    poly_free(sys);
    lens_free(&l);
}

static void pupil_patterns(void **state)
{
    (void)state;
    double xy[2 * 2000];
    /* hexapolar: 1 + 3 R (R + 1) points, rings at k / R */
    size_t n = pupil_points(PUPIL_HEXAPOLAR, 37, 0, xy, 1000);
    assert_int_equal(n, 37);
    double rmax = 0, sx = 0, sy = 0;
    for (size_t i = 0; i < n; i++) {
        rmax = fmax(rmax, hypot(xy[2 * i], xy[2 * i + 1]));
        sx += xy[2 * i], sy += xy[2 * i + 1];
    }
    assert_true(fabs(rmax - 1) < 1e-12);
    assert_true(fabs(sx) < 1e-12 && fabs(sy) < 1e-12);
    for (int p = PUPIL_GRID; p <= PUPIL_RANDOM; p++) {
        n = pupil_points((pupil_pattern)p, 500, 7, xy, 2000);
        assert_true(n > 400 && n < 600);
        for (size_t i = 0; i < n; i++)
            assert_true(hypot(xy[2 * i], xy[2 * i + 1]) <= 1);
    }
    /* random is reproducible and uniform in area: half the points inside r = 0.7071 */
    double again[2 * 2000];
    n = pupil_points(PUPIL_RANDOM, 2000, 7, xy, 2000);
    assert_int_equal(pupil_points(PUPIL_RANDOM, 2000, 7, again, 2000), n);
    assert_memory_equal(xy, again, sizeof(double) * 2 * n);
    size_t inner = 0;
    for (size_t i = 0; i < n; i++)
        inner += hypot(xy[2 * i], xy[2 * i + 1]) < sqrt(0.5);
    assert_true(fabs((double)inner / (double)n - 0.5) < 0.05);
}

static void pictures_read_back(void **state)
{
    (void)state;
    lens_t l;
    assert_int_equal(fixture_dgauss50(&l), 0);
    const double fields[2] = {0, 10}, lambda[3] = {GLASS_F_LINE, GLASS_D_LINE, GLASS_C_LINE};
    spot_request rq = {.im = {{.lens = &l, .object_distance = INFINITY}},
                       .model_names = {"lens"}, .nmodels = 1, .field = fields, .nfields = 2,
                       .lambda = lambda, .nl = 3, .primary = 1, .focus = FOCUS_FILE,
                       .pattern = PUPIL_HEXAPOLAR, .rays = 100, .seed = 1};
    spot_report rep;
    lens_err err;
    assert_int_equal(spot_run(&rq, &rep, &err), 0);
    spot_figure fig = {.nmodels = 1, .nfields = 2, .nl = 3, .model_names = rq.model_names,
                       .spots = rep.spots, .title = "test"};
    char dir[] = "/tmp/test_spot_XXXXXX", png[128], exr[128];
    assert_non_null(mkdtemp(dir));
    snprintf(png, sizeof png, "%s/s.png", dir);
    snprintf(exr, sizeof exr, "%s/s.exr", dir);
    assert_int_equal(spot_write_png(&fig, png, &err), 0);
    int w, h;
    long nb;
    assert_int_equal(img_png_info(png, &w, &h, &nb, &err), 0);
    assert_true(w >= 2 * 300 && h > 300);
    assert_true(nb > 2000);
    double um;
    int panel;
    assert_int_equal(spot_write_exr(&fig, exr, &um, &panel, &err), 0);
    exr_image img;
    assert_int_equal(exr_read_float(exr, &img, &err), 0);
    assert_int_equal(img.width, 2 * panel);
    assert_int_equal(img.height, panel);
    const float *d = exr_image_channel(&img, "density");
    assert_non_null(d);
    assert_non_null(exr_image_channel(&img, "lambda_588nm"));
    /* a probability density: it integrates to the fraction of rays that pass */
    double sum = 0;
    for (int y = 0; y < panel; y++)
        for (int x = 0; x < panel; x++) /* the first panel: field 0 */
            sum += d[y * img.width + x] * um * um;
    double passed = 0;
    for (int l2 = 0; l2 < 3; l2++)
        passed += (double)rep.spots[l2].passed / (double)rep.spots[l2].rays / 3;
    assert_true(fabs(sum - passed) < 1e-3);
    exr_image_free(&img);
    unlink(png);
    unlink(exr);
    rmdir(dir);
    spot_report_free(&rep);
    lens_free(&l);
}

static void field_past_the_lens_is_an_error(void **state)
{
    (void)state;
    lens_t l;
    assert_int_equal(fixture_dgauss50(&l), 0);
    imaging im = {.lens = &l, .object_distance = INFINITY};
    spot sp;
    lens_err err;
    assert_int_not_equal(spot_trace(&im, 80, GLASS_D_LINE, PUPIL_HEXAPOLAR, 10, 1, &sp, &err), 0);
    assert_non_null(strstr(err.msg, "field 80 deg"));
    double lam[4];
    assert_int_equal(wavelengths_parse("F,d,C", lam, 4, &err), 3);
    assert_true(lam[1] == GLASS_D_LINE);
    assert_int_equal(wavelengths_parse("0.55,e", lam, 4, &err), 2);
    assert_int_equal(wavelengths_parse("Q", lam, 4, &err), -1);
    assert_non_null(strstr(err.msg, "unknown wavelength 'Q'"));
    assert_int_equal(wavelengths_parse("", lam, 4, &err), -1);
    assert_int_equal(wavelengths_parse("d,,C", lam, 4, &err), -1);
    assert_int_equal(wavelengths_parse("5", lam, 4, &err), -1);
    lens_free(&l);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(perfect_system_spot_is_a_point),
        cmocka_unit_test(defocus_gives_the_geometric_cone),
        cmocka_unit_test(pupil_patterns),
        cmocka_unit_test(pictures_read_back),
        cmocka_unit_test(field_past_the_lens_is_an_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
