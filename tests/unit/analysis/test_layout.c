/* The layout drawing: element outlines on their surfaces' sags, and rays drawn surface by
 * surface that land where the exact tracer puts them. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "fixture_lenses.h"
#include "sparselens/layout.h"
#include "sparselens/ray_bundle.h"

/* Where an outline point lies: on surface i or i + 1 of its element (at a height within
 * that surface's rim), or on the element's edge (|y| at the wider rim, z between). */
static int on_element(const lens_t *lens, size_t i, double z, double y)
{
    for (size_t k = i; k <= i + 1; k++)
        if (fabs(y) <= lens->surf[k].semi_diameter + 1e-12 &&
            fabs(lens->vertex_z[k] + lens_sag(&lens->surf[k], y * y) - z) < 1e-9)
            return 1;
    double h = fmax(lens->surf[i].semi_diameter, lens->surf[i + 1].semi_diameter);
    double za = lens->vertex_z[i] + lens_sag(&lens->surf[i], fmin(h, lens->surf[i].semi_diameter) *
                                                                 fmin(h, lens->surf[i].semi_diameter));
    double zb = lens->vertex_z[i + 1] + lens_sag(&lens->surf[i + 1], lens->surf[i + 1].semi_diameter *
                                                                         lens->surf[i + 1].semi_diameter);
    return fabs(fabs(y) - h) < 1e-12 && z >= fmin(za, zb) - 1e-9 && z <= fmax(za, zb) + 1e-9;
}

static void outlines_and_rays(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    /* the sensor moved off the file's plane: the rays end on the plane drawn */
    imaging im = {.lens = &lens, .object_distance = INFINITY, .sensor_shift = 0.3};
    const double field[2] = {0, 12};
    layout_drawing d;
    lens_err err;
    assert_int_equal(layout_build(&im, NULL, NULL, field, 2, GLASS_D_LINE, 5, 1, &d, &err), 0);
    int glass = 0, elements = 0, landed = 0;
    for (size_t i = 0; i + 1 < lens.nsurf; i++)
        glass += lens.surf[i].medium.kind != GLASS_AIR;
    double zs = lens_total_track(&lens) + im.sensor_shift;
    /* the exact tracer's sensor points for the same rays */
    double pupil[10], s[2][20];
    int ok[2][5];
    for (int i = 0; i < 5; i++)
        pupil[2 * i] = 0, pupil[2 * i + 1] = -1 + 0.5 * i;
    for (int f = 0; f < 2; f++) {
        ray_bundle b;
        assert_int_equal(bundle_aim(&im, field[f], GLASS_D_LINE, pupil, 5, &b, &err), 0);
        bundle_image(&im, &b, NULL, s[f], ok[f]);
        bundle_free(&b);
    }
    int seen[2] = {0, 0};
    for (int i = 0; i < d.nlines; i++) {
        const layout_line *l = &d.line[i];
        if (l->kind == LAYOUT_ELEMENT) {
            elements++;
            /* the first point is the front surface's bottom rim */
            double y = l->zy[1], z = l->zy[0];
            int k = 0;
            while (k < (int)lens.nsurf && fabs(lens.vertex_z[k] + lens_sag(&lens.surf[k], y * y) - z) > 1e-12)
                k++;
            assert_true(k + 1 < (int)lens.nsurf);
            assert_true(fabs(fabs(y) - lens.surf[k].semi_diameter) < 1e-12);
            /* every point on the element's two surfaces or its edge, both vertices drawn */
            int vertices = 0;
            for (int p = 0; p < l->n; p++) {
                double pz = l->zy[2 * p], py = l->zy[2 * p + 1];
                assert_true(on_element(&lens, (size_t)k, pz, py));
                vertices += py == 0 && (pz == lens.vertex_z[k] || pz == lens.vertex_z[k + 1]);
            }
            assert_int_equal(vertices, 2);
        }
        if (l->kind == LAYOUT_SENSOR)
            assert_true(l->zy[0] == zs && l->zy[2] == zs);
        if (l->kind == LAYOUT_STOP) {
            const lens_surface *st = &lens.surf[lens.stop];
            assert_true(fabs(fabs(l->zy[1]) - st->semi_diameter) < 1e-12);
            assert_true(fabs(l->zy[0] - lens.vertex_z[lens.stop] - lens_sag(st, st->semi_diameter * st->semi_diameter)) < 1e-12);
        }
        if (l->kind == LAYOUT_RAY) {
            int f = l->field, r = seen[f]++;
            double z = l->zy[2 * l->n - 2], y = l->zy[2 * l->n - 1];
            assert_int_equal(fabs(z - zs) < 1e-12, ok[f][r]);
            if (ok[f][r]) {
                assert_true(fabs(y - s[f][4 * r + 1]) < 1e-9);
                landed++;
            }
        }
    }
    assert_int_equal(elements, glass);
    assert_int_equal(landed, d.passed);
    assert_true(landed >= 5); /* the rims are vignetted in this lens, the rest lands */
    layout_free(&d);
    lens_free(&lens);
}

/* 1 when the exact lens images the ray of stop point (0, py): bundle_image's own test,
 * not the layout's ray_path walk. */
static int stop_point_passes(const imaging *im, double field, double py)
{
    double p[2] = {0, py}, s[4];
    int ok = 0;
    ray_bundle b;
    lens_err err;
    assert_int_equal(bundle_aim(im, field, GLASS_D_LINE, p, 1, &b, &err), 0);
    bundle_image(im, &b, NULL, s, &ok);
    bundle_free(&b);
    return ok;
}

/* By default the rays fill the part of the stop's meridian that reaches the sensor: on
 * dgauss.50mm at 16 and 23 degrees vignetting stops the rim rays, so the fans must be
 * narrower than the stop, every drawn ray must land, and the edges must be where a
 * brute-force scan of 1001 stop points finds the last passing ray. */
static void rays_fill_the_passing_bundle(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    imaging im = {.lens = &lens, .object_distance = INFINITY};
    const double field[3] = {0, 16, 23};
    layout_drawing d;
    lens_err err;
    assert_int_equal(layout_build(&im, NULL, NULL, field, 3, GLASS_D_LINE, 9, 0, &d, &err), 0);
    assert_int_equal(d.rays, 27);
    assert_int_equal(d.passed, 27);
    for (int f = 0; f < 3; f++) {
        int lo = -1, hi = -1;
        for (int i = 0; i <= 1000; i++) {
            double py = -1 + 2e-3 * i;
            if (stop_point_passes(&im, field[f], py)) {
                if (lo < 0 || hi < i - 1) /* a new run: keep the one around the chief ray */
                    if (lo < 0 || py <= 0)
                        lo = i;
                if (hi == i - 1 || hi < 0 || py <= 0)
                    hi = i;
            }
        }
        assert_true(lo >= 0);
        double ref_lo = -1 + 2e-3 * lo, ref_hi = -1 + 2e-3 * hi;
        print_message("field %g: span [%.7f, %.7f], scan [%.3f, %.3f]\n", field[f], d.span[f][0], d.span[f][1],
                      ref_lo, ref_hi);
        assert_true(fabs(d.span[f][0] - ref_lo) <= 2.1e-3 && fabs(d.span[f][1] - ref_hi) <= 2.1e-3);
        /* the ends are the last passing rays: a hair beyond is stopped */
        for (int e = 0; e < 2; e++)
            if (fabs(d.span[f][e]) < 1 - 1e-6) {
                double out = d.span[f][e] + (e ? 2e-6 : -2e-6);
                assert_true(stop_point_passes(&im, field[f], d.span[f][e]));
                assert_false(stop_point_passes(&im, field[f], out));
            }
    }
    /* on axis the bundle is symmetric (an element's rim, not the stop, trims it to 0.993) */
    assert_true(fabs(d.span[0][0] + d.span[0][1]) < 1e-6 && d.span[0][1] > 0.99);
    assert_true(d.span[2][1] - d.span[2][0] < 1.6);             /* the full field is cut */
    layout_free(&d);
    /* the whole stop: the same fields lose rays to vignetting */
    assert_int_equal(layout_build(&im, NULL, NULL, field, 3, GLASS_D_LINE, 9, 1, &d, &err), 0);
    assert_true(d.passed < d.rays);
    assert_true(d.span[2][0] == -1 && d.span[2][1] == 1);
    layout_free(&d);
    lens_free(&lens);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(outlines_and_rays),
        cmocka_unit_test(rays_fill_the_passing_bundle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
