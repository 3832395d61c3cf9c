/* Drawing, PNG round trip, and the OpenCV camera-model fits against mappings made
 * with known coefficients (the models' formulas written out here, independently). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "sparselens/image.h"

static void png_round_trip(void **state)
{
    (void)state;
    const double white[3] = {1, 1, 1}, red[3] = {1, 0, 0};
    img_canvas *c = img_new(320, 200, white);
    assert_non_null(c);
    assert_int_equal(img_width(c), 320);
    assert_int_equal(img_height(c), 200);
    char dir[] = "/tmp/test_image_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[256];
    snprintf(path, sizeof path, "%s/blank.png", dir);
    lens_err err;
    assert_int_equal(img_write_png(c, path, &err), 0);
    int w, h;
    long nb;
    assert_int_equal(img_png_info(path, &w, &h, &nb, &err), 0);
    assert_int_equal(w, 320);
    assert_int_equal(h, 200);
    assert_int_equal(nb, 0);
    img_line(c, 10, 10, 300, 190, red, 2);
    img_circle(c, 160, 100, 40, red, 1);
    img_dot(c, 50, 150, 3, red, 1);
    img_text(c, 20, 40, "spot 10 um", 14, red);
    img_line(c, NAN, 0, 1, 1, red, 1); /* ignored, not a crash */
    assert_int_equal(img_write_png(c, path, &err), 0);
    assert_int_equal(img_png_info(path, &w, &h, &nb, &err), 0);
    assert_true(nb > 500);
    /* a filled dot of radius 3 covers about pi 9 pixels */
    img_canvas *d = img_new(20, 20, white);
    img_dot(d, 10, 10, 3, red, 1);
    assert_int_equal(img_write_png(d, path, &err), 0);
    assert_int_equal(img_png_info(path, &w, &h, &nb, &err), 0);
    assert_true(nb >= 25 && nb <= 60);
    img_free(d);
    img_free(c);
    unlink(path);
    rmdir(dir);
    assert_int_not_equal(img_png_info("/nonexistent/x.png", &w, &h, &nb, &err), 0);
}

/* Views of a planar grid: view v is the plane z = 0 rotated by angle a_v about y and
 * placed 1 unit in front of the camera. */
static void grid_views(int nviews, int n, double *obj, double *cam, size_t *counts)
{
    size_t k = 0;
    for (int v = 0; v < nviews; v++) {
        double a = (v - (nviews - 1) / 2.0) * 0.25, b = v % 2 ? 0.15 : -0.1;
        counts[v] = 0;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++, k++) {
                double X = -0.6 + 1.2 * i / (n - 1), Y = -0.45 + 0.9 * j / (n - 1);
                obj[3 * k] = X, obj[3 * k + 1] = Y, obj[3 * k + 2] = 0;
                /* rotate about y by a, then about x by b, then translate */
                double x1 = cos(a) * X, z1 = -sin(a) * X, y1 = Y;
                double y2 = cos(b) * y1 - sin(b) * z1, z2 = sin(b) * y1 + cos(b) * z1;
                cam[3 * k] = x1, cam[3 * k + 1] = y2, cam[3 * k + 2] = z2 + 1.0;
                counts[v]++;
            }
    }
}

static void brown_recovers_coefficients(void **state)
{
    (void)state;
    const int W = 1600, H = 1200, nv = 3, n = 15;
    const double f = 1000, k1 = -0.21, k2 = 0.06, p1 = 0.0012, p2 = -0.0007, k3 = -0.012;
    double *obj = malloc(sizeof(double) * 3 * nv * n * n);
    double *cam = malloc(sizeof(double) * 3 * nv * n * n);
    double *pix = malloc(sizeof(double) * 2 * nv * n * n);
    size_t counts[3];
    grid_views(nv, n, obj, cam, counts);
    for (int k = 0; k < nv * n * n; k++) {
        double x = cam[3 * k] / cam[3 * k + 2], y = cam[3 * k + 1] / cam[3 * k + 2];
        double r2 = x * x + y * y, rad = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
        double xd = x * rad + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
        double yd = y * rad + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
        pix[2 * k] = f * xd + W / 2.0, pix[2 * k + 1] = f * yd + H / 2.0;
    }
    cv_camera_fit fit;
    lens_err err;
    int rc = cv_fit_brown(W, H, 900, nv, counts, obj, pix, &fit, &err);
    if (rc)
        fprintf(stderr, "%s\n", err.msg);
    assert_int_equal(rc, 0);
    assert_true(fabs(fit.fx - f) < 0.05);
    assert_true(fabs(fit.k[0] - k1) < 1e-4);
    assert_true(fabs(fit.k[1] - k2) < 1e-3);
    assert_true(fabs(fit.k[2] - p1) < 1e-5);
    assert_true(fabs(fit.k[3] - p2) < 1e-5);
    assert_true(fabs(fit.k[4] - k3) < 2e-3);
    assert_true(fit.rms < 0.01);
    free(obj), free(cam), free(pix);
}

static void fisheye_recovers_coefficients(void **state)
{
    (void)state;
    const int W = 1600, H = 1600, nv = 3, n = 15;
    const double f = 500, k[4] = {0.04, -0.012, 0.003, -0.0004};
    double *obj = malloc(sizeof(double) * 3 * nv * n * n);
    double *cam = malloc(sizeof(double) * 3 * nv * n * n);
    double *pix = malloc(sizeof(double) * 2 * nv * n * n);
    size_t counts[3];
    grid_views(nv, n, obj, cam, counts);
    for (int i = 0; i < nv * n * n; i++) {
        double a = cam[3 * i] / cam[3 * i + 2], b = cam[3 * i + 1] / cam[3 * i + 2];
        double r = hypot(a, b), t = atan(r), t2 = t * t;
        double td = t * (1 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
        double s = r > 0 ? td / r : 1;
        pix[2 * i] = f * a * s + W / 2.0, pix[2 * i + 1] = f * b * s + H / 2.0;
    }
    cv_camera_fit fit;
    lens_err err;
    int rc = cv_fit_fisheye(W, H, 450, 0, nv, counts, obj, pix, &fit, &err);
    if (rc)
        fprintf(stderr, "%s\n", err.msg);
    assert_int_equal(rc, 0);
    assert_true(fabs(fit.fx - f) < 0.05);
    assert_true(fabs(fit.k[0] - k[0]) < 1e-3);
    assert_true(fabs(fit.k[1] - k[1]) < 3e-3);
    assert_true(fit.rms < 0.01);
    free(obj), free(cam), free(pix);
}

static void fit_rejects_bad_input(void **state)
{
    (void)state;
    double obj[3 * 4] = {0}, pix[2 * 4] = {0};
    size_t counts[1] = {4};
    cv_camera_fit fit;
    lens_err err;
    assert_int_not_equal(cv_fit_brown(100, 100, 100, 1, counts, obj, pix, &fit, &err), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(png_round_trip),
        cmocka_unit_test(brown_recovers_coefficients),
        cmocka_unit_test(fisheye_recovers_coefficients),
        cmocka_unit_test(fit_rejects_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
