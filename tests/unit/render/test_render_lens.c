/* The renderer through a real lens (pbrt's 50 mm double Gauss, built in C by the
 * tracer's fixture), traced exactly:
 *  - relative illumination: the rendered irradiance of a uniform emitter across the
 *    field against a deterministic quadrature of the same integral (P_a T_r cos^4 over
 *    a fine (u, v) grid), which also shows how far it falls below cos^4 (vignetting);
 *  - bokeh: an out-of-focus emitter gives a disk of the first-order size, from the exit
 *    pupil and the paraxial image distance (paraxial.c). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "fixture_lenses.h"
#include "sparselens/glass.h"
#include "sparselens/paraxial.h"
#include "sparselens/render.h"
#include "sparselens/render_lens.h"
#include "sparselens/scene.h"
#include "sparselens/trace.h"

static void load(scene_t *s, const char *text)
{
    lens_err err = {{0}};
    if (scene_parse(text, "t.scene", s, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
}

/* integral of P_a T_r cos^4 du dv at sensor point (x, 0): midpoint rule on a grid over
 * a window that holds the rear element's cone with room to spare */
static double quadrature(const lens_t *lens, const double *n, double x, int grid)
{
    const lens_surface *rear = &lens->surf[lens->nsurf - 1];
    double h = rear->thickness, w = 2 * rear->semi_diameter / h, uc = -x / h;
    double cell = 2 * w / grid, sum = 0;
    for (int i = 0; i < grid; i++)
        for (int j = 0; j < grid; j++) {
            double u = uc - w + (i + 0.5) * cell, v = -w + (j + 0.5) * cell;
            double in[4] = {x, 0, u, v}, out[4];
            trace_result r = trace_sample(lens, n, TRACE_TO_OUTER, in, out);
            if (r.status != TRACE_PASSED) continue;
            double c2 = 1 / (1 + u * u + v * v);
            sum += r.transmittance * c2 * c2;
        }
    return sum * cell * cell;
}

static void test_relative_illumination(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    scene_t s;
    load(&s, "camera a.lens\nresolution 12 1\nplane 0 0 1000 0 0 -1 emit 1\n");
    render_camera cam;
    lens_err err = {{0}};
    render_lens_ctx *lc = render_lens_exact(&lens, 36, 0.5, &cam, &err);
    assert_non_null(lc);
    render_sampler smp;
    assert_int_equal(render_sampler_pupil(&smp, &cam, GLASS_D_LINE, 18.1, 24, &err), 0);
    const char *san = getenv("SANITIZE");
    int fast = san && *san;
    render_job job = {.scene = &s, .cam = &cam, .sampler = &smp, .use_eta = 1,
                      .spp = fast ? 1024 : 4096};
    float img[12 * 3], var[12 * 3];
    render_stats st;
    assert_int_equal(render_image(&job, img, var, &st, &err), 0);
    double n[32];
    assert_int_equal(lens_indices(&lens, GLASS_D_LINE, n, &err), 0);
    double e0 = 0;
    int grid = fast ? 60 : 120;
    for (int px = 6; px < 12; px++) {
        /* the pixel's mean by two points across its width (y stays near 0) */
        double x0 = (px / 12.0 - 0.5) * 36, q = 0;
        for (int k = 0; k < 2; k++) q += quadrature(&lens, n, x0 + (k + 0.5) * 1.5, grid) / 2;
        if (px == 6) e0 = q;
        double got = img[3 * px], se = sqrt(var[3 * px]);
        double xc = x0 + 1.5, c = cos(atan(xc / 50.0));
        print_message("x %5.2f mm: render %.5f +- %.5f, quadrature %.5f, relative %.3f, cos^4 %.3f\n",
                      xc, got, se, q, q / e0, c * c * c * c);
        /* the grid's own error at the pupil's edge is about a cell: 2% */
        assert_true(fabs(got - q) < 3 * se + 0.02 * q);
    }
    /* the double Gauss vignettes: at the edge it falls well below cos^4 (about 0.71) */
    double xe = 16.5, ce = cos(atan(xe / 50.0));
    assert_true(img[3 * 11] / img[3 * 6] < ce * ce * ce * ce);
    render_sampler_free(&smp);
    render_lens_free(lc);
    scene_free(&s);
    lens_free(&lens);
}

static void test_bokeh_dgauss(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0); /* focused at infinity */
    paraxial_data p;
    lens_err err = {{0}};
    assert_int_equal(paraxial_compute(&lens, GLASS_D_LINE, &p, &err), 0);
    double dist = 1000, t_img, t_sensor = lens.surf[lens.nsurf - 1].thickness;
    assert_int_equal(paraxial_focus_thickness(&lens, GLASS_D_LINE, dist, &t_img, &err), 0);
    /* the cone from the exit pupil (radius D/2 at z_xp after the last surface) to the
     * image point, cut by the sensor plane */
    double expect = p.exit_pupil_diameter / 2 * fabs(t_img - t_sensor) /
                    fabs(t_img - p.exit_pupil_z);
    scene_t s;
    char text[256];
    snprintf(text, sizeof text, "camera a.lens\nresolution 48 48\nsphere 0 0 %g 4 emit 1\n", dist);
    load(&s, text);
    render_camera cam;
    render_lens_ctx *lc = render_lens_exact(&lens, 4, 4, &cam, &err);
    assert_non_null(lc);
    render_sampler smp;
    assert_int_equal(render_sampler_pupil(&smp, &cam, GLASS_D_LINE, 2.9, 4, &err), 0);
    const char *san = getenv("SANITIZE");
    render_job job = {.scene = &s, .cam = &cam, .sampler = &smp, .use_eta = 0,
                      .spp = san && *san ? 128 : 256};
    float *img = malloc(48 * 48 * 3 * sizeof *img);
    assert_int_equal(render_image(&job, img, NULL, NULL, &err), 0);
    double tot = 0, centre = 0;
    int nc = 0;
    for (int y = 0; y < 48; y++)
        for (int x = 0; x < 48; x++) {
            double v = img[3 * (y * 48 + x)];
            tot += v;
            /* the flat top: the blur disk (7.3 px) less the sphere's picture (2.4 px) */
            if (hypot(x + 0.5 - 24, y + 0.5 - 24) < 4) centre += v, nc++;
        }
    double radius = sqrt(tot / (centre / nc) / M_PI) * 4.0 / 48;
    print_message("bokeh radius %.4f mm, first-order cone %.4f mm\n", radius, expect);
    assert_true(fabs(radius - expect) < 0.06 * expect);
    free(img);
    render_sampler_free(&smp);
    render_lens_free(lc);
    scene_free(&s);
    lens_free(&lens);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_relative_illumination),
        cmocka_unit_test(test_bokeh_dgauss),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
