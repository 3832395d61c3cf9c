/* The camera-ray estimator (render.c) on lenses whose answers are known in closed form:
 *  - a bare circular aperture in front of the sensor: the irradiance from a uniform
 *    emitter is the view factor of a disk (cos^4 falloff and the aperture's size);
 *  - an ideal thin lens: an out-of-focus point gives a disk of the first-order size.
 * Plus: the ray weight against a finite-difference solid angle (the derivation check of
 * Eq. 13), line-pupil against rear-element sampling within three standard errors per
 * region, and the error falling as 1/sqrt(spp). Sample counts are small (sanitizers). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sparselens/render.h"
#include "sparselens/scene.h"

/* --- analytic lenses (lens frame: front at z = 0, sensor at z = h) --- */
typedef struct {
    double h;     /* sensor to the lens plane */
    double R;     /* aperture radius */
    double f;     /* focal length; INFINITY for a bare aperture */
} thin_lens;

static int thin_map(void *ctx, const double in[5], double org[3], double dir[3], double *eta)
{
    const thin_lens *L = ctx;
    double px = in[0] + L->h * in[2], py = in[1] + L->h * in[3];
    if (px * px + py * py > L->R * L->R) return 0;
    /* slopes dx/d(-z): a thin lens bends every ray by -height/f */
    double su = in[2] - px / L->f, sv = in[3] - py / L->f;
    double n = sqrt(su * su + sv * sv + 1);
    org[0] = px, org[1] = py, org[2] = 0;
    dir[0] = su / n, dir[1] = sv / n, dir[2] = -1 / n;
    *eta = 1;
    return 1;
}

static render_camera camera_of(thin_lens *L, double sw, double sh)
{
    render_camera c = {.map = thin_map, .ctx = L, .sensor_w = sw, .sensor_h = sh,
                       .rear_dist = L->h, .rear_radius = L->R};
    return c;
}

static int is_sanitized(void)
{
    const char *s = getenv("SANITIZE");
    return s && *s;
}

/* View factor of a disk (radius R, distance h, parallel) from a point offset by d:
 * E / L = pi/2 (1 - (h^2 + d^2 - R^2) / sqrt((h^2 + d^2 + R^2)^2 - 4 R^2 d^2)). */
static double disk_irradiance(double h, double R, double d)
{
    double a = h * h + d * d;
    return M_PI / 2 * (1 - (a - R * R) / sqrt((a + R * R) * (a + R * R) - 4 * R * R * d * d));
}

/* The pixel mean of the closed form: a fine quadrature over the pixel. */
static double pixel_irradiance(double h, double R, double x0, double x1, double y0, double y1)
{
    double s = 0;
    int n = 16;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double x = x0 + (i + 0.5) / n * (x1 - x0), y = y0 + (j + 0.5) / n * (y1 - y0);
            s += disk_irradiance(h, R, hypot(x, y));
        }
    return s / (n * n);
}

static void load(scene_t *s, const char *text)
{
    lens_err err = {{0}};
    if (scene_parse(text, "t.scene", s, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
}

/* Derivation check: cos(theta) dw = cos^4(theta) du dv, so the weight of a ray drawn with
 * density p(u, v) must equal cos(theta) times the solid angle of a small (du, dv) cell
 * (measured here from the cell's corner directions) divided by p du dv. */
static void test_weight_solid_angle(void **state)
{
    (void)state;
    double pts[][2] = {{0, 0}, {0.3, -0.2}, {1.2, 0.7}, {-2.5, 0.1}};
    for (size_t k = 0; k < sizeof pts / sizeof pts[0]; k++) {
        double u = pts[k][0], v = pts[k][1], e = 1e-4;
        double c[4][3];
        for (int i = 0; i < 4; i++) {
            double uu = u + ((i & 1) ? e : -e) / 2, vv = v + ((i & 2) ? e : -e) / 2;
            double n = sqrt(uu * uu + vv * vv + 1);
            c[i][0] = uu / n, c[i][1] = vv / n, c[i][2] = -1 / n;
        }
        /* the spherical quad's area ~ |(c1 - c0) x (c2 - c0)| */
        double a[3], b[3], x[3];
        for (int i = 0; i < 3; i++) a[i] = c[1][i] - c[0][i], b[i] = c[2][i] - c[0][i];
        x[0] = a[1] * b[2] - a[2] * b[1];
        x[1] = a[2] * b[0] - a[0] * b[2];
        x[2] = a[0] * b[1] - a[1] * b[0];
        double dw = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        double cos_t = 1 / sqrt(1 + u * u + v * v);
        double pdf = 0.37;
        double expect = cos_t * dw / (pdf * e * e);
        double got = render_ray_weight(u, v, pdf, 1);
        assert_true(fabs(got / expect - 1) < 1e-3);
    }
}

/* A uniform emitter seen through a bare aperture: every pixel must match the closed-form
 * view factor within three of its standard errors (computed from the samples). */
static void check_aperture(render_sampling kind, const char *mode)
{
    thin_lens L = {.h = 20, .R = 6, .f = INFINITY};
    scene_t s;
    char text[160];
    snprintf(text, sizeof text, "camera a.lens\nresolution 8 4\nmode %s\nplane 0 0 50 0 0 -1 emit 1\n",
             mode);
    load(&s, text);
    render_camera cam = camera_of(&L, 32, 16);
    render_sampler smp;
    lens_err err = {{0}};
    if (kind == RENDER_SAMPLE_REAR) render_sampler_rear(&smp, &cam);
    else assert_int_equal(render_sampler_pupil(&smp, &cam, 0.55, hypot(16, 8), 16, &err), 0);
    render_job job = {.scene = &s, .cam = &cam, .sampler = &smp, .use_eta = 1,
                      .spp = is_sanitized() ? 64 : 256, .threads = 2};
    if (s.mode != SCENE_GREY) job.spp += 1; /* not a multiple of 3: uneven bands */
    float img[8 * 4 * 3], var[8 * 4 * 3];
    render_stats st;
    assert_int_equal(render_image(&job, img, var, &st, &err), 0);
    int worst = 0;
    for (int py = 0; py < 4; py++)
        for (int px = 0; px < 8; px++) {
            double x0 = (px / 8.0 - 0.5) * 32, y0 = (py / 4.0 - 0.5) * 16;
            double e = pixel_irradiance(L.h, L.R, x0, x0 + 4, y0, y0 + 4);
            for (int c = 0; c < 3; c++) { /* a white emitter: every band alike */
                size_t i = 3 * ((size_t)py * 8 + px) + c;
                double se = sqrt(var[i]);
                if (fabs(img[i] - e) > 3 * se + 1e-6 * e) {
                    print_error("pixel %d,%d channel %d: %g vs closed form %g (se %g)\n", px, py, c,
                                img[i], e, se);
                    worst++;
                }
            }
        }
    /* 32 pixels (96 values in colour) at 3 sigma: more than one or two misses is a bias */
    assert_true(worst <= (s.mode == SCENE_GREY ? 1 : 2));
    if (kind == RENDER_SAMPLE_REAR) assert_true(st.passed_rays == st.camera_rays);
    render_sampler_free(&smp);
    scene_free(&s);
}

static void test_aperture_rear(void **state)
{
    (void)state;
    check_aperture(RENDER_SAMPLE_REAR, "grey");
}

/* The band weights of the rgb and spectral modes: a white emitter gives each channel
 * the grey closed form. */
static void test_aperture_colour_modes(void **state)
{
    (void)state;
    check_aperture(RENDER_SAMPLE_PUPIL, "rgb");
    check_aperture(RENDER_SAMPLE_PUPIL, "spectral");
}

static void test_aperture_pupil(void **state)
{
    (void)state;
    check_aperture(RENDER_SAMPLE_PUPIL, "grey");
}

/* Unbiasedness of the line pupil against the independent rear-element estimator: a
 * textured scene through a thin lens with a small aperture behind a larger rear
 * element, compared per 4x4 region within three standard errors. */
static void test_pupil_vs_rear(void **state)
{
    (void)state;
    thin_lens L = {.h = 52, .R = 5, .f = 50};
    scene_t s;
    load(&s, "camera a.lens\nresolution 16 16\n"
             "plane 0 0 1300 0 0 -1 checker 0.2 0.9 40\n"
             "disk 300 -200 500 -0.3 0.2 -1 100 emit 3\n"
             "sphere 0 0 800 60 albedo 0.7\n"
             "disk -200 300 900 0 -1 0 200 emit 5\n");
    /* the rear-element disk is larger than the aperture, as in a real lens */
    render_camera cam = camera_of(&L, 24, 24);
    cam.rear_radius = 9;
    render_sampler rear, pupil;
    lens_err err = {{0}};
    render_sampler_rear(&rear, &cam);
    assert_int_equal(render_sampler_pupil(&pupil, &cam, 0.55, hypot(12, 12), 12, &err), 0);
    long spp = is_sanitized() ? 32 : 128;
    render_job a = {.scene = &s, .cam = &cam, .sampler = &pupil, .use_eta = 1, .spp = spp};
    render_job b = a;
    b.sampler = &rear;
    float ia[16 * 16 * 3], va[16 * 16 * 3], ib[16 * 16 * 3], vb[16 * 16 * 3];
    render_stats sa, sb;
    assert_int_equal(render_image(&a, ia, va, &sa, &err), 0);
    assert_int_equal(render_image(&b, ib, vb, &sb, &err), 0);
    int misses = 0;
    for (int ry = 0; ry < 4; ry++)
        for (int rx = 0; rx < 4; rx++) {
            double ma = 0, mb = 0, v = 0;
            for (int y = 4 * ry; y < 4 * ry + 4; y++)
                for (int x = 4 * rx; x < 4 * rx + 4; x++) {
                    size_t i = 3 * ((size_t)y * 16 + x);
                    ma += ia[i], mb += ib[i], v += va[i] + vb[i];
                }
            if (fabs(ma - mb) > 3 * sqrt(v)) {
                print_error("region %d,%d: pupil %g rear %g (se %g)\n", rx, ry, ma / 16, mb / 16,
                            sqrt(v) / 16);
                misses++;
            }
        }
    assert_true(misses <= 1);
    /* and the line pupil wastes far fewer rays: the aperture is (5/9)^2 of the rear disk */
    double pass_a = sa.passed_rays / sa.camera_rays, pass_b = sb.passed_rays / sb.camera_rays;
    assert_true(pass_b < 0.45);
    assert_true(pass_a > 1.5 * pass_b);
    render_sampler_free(&rear);
    render_sampler_free(&pupil);
    scene_free(&s);
}

/* A point-like emitter out of focus through an ideal thin lens: its image is a disk of
 * diameter 2 R |i - i'| / i', i' = 1 / (1/f - 1/o) (first-order optics). */
static void test_bokeh_thin_lens(void **state)
{
    (void)state;
    double f = 50, o_focus = 2000, o_point = 600, R = 12.5; /* f/2 */
    double i = 1 / (1 / f - 1 / o_focus), ip = 1 / (1 / f - 1 / o_point);
    double expect = R * fabs(i - ip) / ip; /* blur radius on the sensor, mm */
    thin_lens L = {.h = i, .R = R, .f = f};
    scene_t s;
    /* a small sphere rather than a point, so that camera rays find it: the image is then
     * the blur disk convolved with the sphere's small picture, whose energy over its
     * flat centre's level is still pi times the blur radius squared */
    load(&s, "camera a.lens\nresolution 48 48\nsphere 0 0 600 3 emit 1\n");
    render_camera cam = camera_of(&L, 6, 6);
    render_sampler smp;
    lens_err err = {{0}};
    assert_int_equal(render_sampler_pupil(&smp, &cam, 0.55, hypot(3, 3), 8, &err), 0);
    render_job job = {.scene = &s, .cam = &cam, .sampler = &smp, .use_eta = 1,
                      .spp = 256};
    float *img = malloc(48 * 48 * 3 * sizeof *img);
    render_stats st;
    assert_int_equal(render_image(&job, img, NULL, &st, &err), 0);
    /* the disk's area from its energy and its (flat) level: E_total / E_centre */
    double tot = 0, centre = 0;
    for (int y = 0; y < 48; y++)
        for (int x = 0; x < 48; x++) {
            tot += img[3 * (y * 48 + x)];
            if (hypot(x + 0.5 - 24, y + 0.5 - 24) < 2.5) centre += img[3 * (y * 48 + x)];
        }
    int ncentre = 0;
    for (int y = 0; y < 48; y++)
        for (int x = 0; x < 48; x++) ncentre += hypot(x + 0.5 - 24, y + 0.5 - 24) < 2.5;
    double pix = 6.0 / 48, level = centre / ncentre;
    double radius = sqrt(tot / level / M_PI) * pix;
    print_message("bokeh radius %.4f mm, first-order %.4f mm\n", radius, expect);
    assert_true(fabs(radius - expect) < 0.04 * expect);
    free(img);
    render_sampler_free(&smp);
    scene_free(&s);
}

/* The RMS error against a high-sample reference falls as 1/sqrt(spp): the fitted slope
 * of log error against log spp is -1/2 within 0.15. */
static void test_convergence(void **state)
{
    (void)state;
    thin_lens L = {.h = 52, .R = 8, .f = 50};
    scene_t s;
    load(&s, "camera a.lens\nresolution 12 12\n"
             "plane 0 0 1300 0 0 -1 checker 0.2 0.9 30\n"
             "disk 100 200 700 0 -0.5 -1 250 emit 4\n");
    render_camera cam = camera_of(&L, 24, 24);
    render_sampler smp;
    lens_err err = {{0}};
    assert_int_equal(render_sampler_pupil(&smp, &cam, 0.55, hypot(12, 12), 8, &err), 0);
    int n = 12 * 12 * 3;
    float *ref = malloc(n * sizeof *ref), *img = malloc(n * sizeof *img);
    int san = is_sanitized();
    render_job job = {.scene = &s, .cam = &cam, .sampler = &smp, .use_eta = 1,
                      .spp = san ? 1024 : 4096};
    s.seed = 99;
    assert_int_equal(render_image(&job, ref, NULL, NULL, &err), 0);
    double lx[3], ly[3];
    long spps[3] = {4, 16, 64};
    for (int k = 0; k < 3; k++) {
        /* average the squared error over seeds to steady the estimate */
        double e2 = 0;
        int seeds = 6;
        for (int sd = 0; sd < seeds; sd++) {
            s.seed = 1000 + sd;
            job.spp = spps[k];
            assert_int_equal(render_image(&job, img, NULL, NULL, &err), 0);
            for (int i = 0; i < n; i++) e2 += (img[i] - ref[i]) * (double)(img[i] - ref[i]);
        }
        lx[k] = log((double)spps[k]);
        ly[k] = 0.5 * log(e2 / (seeds * n));
    }
    double mx = (lx[0] + lx[1] + lx[2]) / 3, my = (ly[0] + ly[1] + ly[2]) / 3, sxy = 0, sxx = 0;
    for (int k = 0; k < 3; k++) sxy += (lx[k] - mx) * (ly[k] - my), sxx += (lx[k] - mx) * (lx[k] - mx);
    double slope = sxy / sxx;
    print_message("error slope against spp: %.3f\n", slope);
    assert_true(fabs(slope + 0.5) < 0.15);
    free(ref);
    free(img);
    render_sampler_free(&smp);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_weight_solid_angle), cmocka_unit_test(test_aperture_rear),
        cmocka_unit_test(test_aperture_pupil),     cmocka_unit_test(test_aperture_colour_modes),
        cmocka_unit_test(test_pupil_vs_rear),
        cmocka_unit_test(test_bokeh_thin_lens),    cmocka_unit_test(test_convergence),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
