/* Scene format (man 5 lens-scene) and scene geometry: parsing, FILE:LINE errors,
 * intersections, and next-event estimation against a closed-form irradiance. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sparselens/scene.h"

static const char *good =
    "# a test scene\n"
    "camera lenses/dgauss50.lens\n"
    "sensor 36 24\n"
    "resolution 96 64   # pixels\n"
    "focus 2000\n"
    "fstop 2.8\n"
    "mode rgb\n"
    "spp 32\n"
    "seed 7\n"
    "transmittance off\n"
    "plane 0 -100 0  0 1 0  checker 0.2 0.8 50\n"
    "sphere 0 0 1500 200 albedo 0.9 0.5 0.1\n"
    "disk 0 1000 1000 0 -1 0 300 emit 10\n"
    "sphere 100 100 3000 2 emit 1e4 2e4 3e4\n";

static void test_parse_good(void **state)
{
    (void)state;
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse(good, "dir/a.scene", &s, &err), 0);
    assert_string_equal(s.camera, "dir/lenses/dgauss50.lens"); /* relative to the scene */
    assert_false(s.camera_is_poly);
    assert_true(s.sensor_w == 36 && s.sensor_h == 24);
    assert_int_equal(s.width, 96);
    assert_int_equal(s.height, 64);
    assert_true(s.focus == 2000 && s.fstop == 2.8);
    assert_int_equal(s.mode, SCENE_RGB);
    assert_int_equal(s.spp, 32);
    assert_int_equal(s.seed, 7);
    assert_int_equal(s.transmittance, EFFECT_OFF);
    assert_int_equal(s.vignetting, EFFECT_AUTO);
    assert_int_equal(s.nobj, 4);
    assert_int_equal(s.obj[0].kind, OBJ_PLANE);
    assert_int_equal(s.obj[0].tex.kind, TEX_CHECKER);
    assert_true(s.obj[1].tex.a[2] == 0.1);
    assert_int_equal(scene_emitter_count(&s), 2);
    assert_true(s.obj[3].emit[1] == 2e4);
    assert_int_equal(s.obj[3].line, 14);
    scene_free(&s);
}

/* Every error names the file and the line of the offending statement. */
static void expect_err(const char *text, const char *where, const char *what)
{
    scene_t s;
    lens_err err = {{0}};
    assert_int_not_equal(scene_parse(text, "x.scene", &s, &err), 0);
    if (!strstr(err.msg, where) || !strstr(err.msg, what)) {
        print_error("message '%s' lacks '%s' or '%s'\n", err.msg, where, what);
        fail();
    }
}

static void test_parse_errors(void **state)
{
    (void)state;
    expect_err("camera a.lens\nsensor 36\nplane 0 0 1 0 0 1\n", "x.scene:2:", "two numbers");
    expect_err("camera a.lens\nresolution 10.5 3\nplane 0 0 1 0 0 1\n", "x.scene:2:", "whole");
    expect_err("camera a.lens\n\n\nbogus 1\n", "x.scene:4:", "unknown statement");
    expect_err("camera a.lens\nplane 0 0 1 0 0 0\n", "x.scene:2:", "normal");
    expect_err("camera a.lens\nsphere 0 0 1 -2\n", "x.scene:2:", "radius");
    expect_err("camera a.lens\nsphere 0 0 1 2 emit 1 2\n", "x.scene:2:", "three");
    expect_err("camera a.lens\nsphere 0 0 1 2 shiny\n", "x.scene:2:", "unknown modifier");
    expect_err("camera a.lens\nmode hdr\nsphere 0 0 1 2\n", "x.scene:2:", "grey, rgb");
    expect_err("camera a.lens\nspp 0\nsphere 0 0 1 2\n", "x.scene:2:", ">= 1");
    expect_err("camera a.lens\nfocus nan\nsphere 0 0 1 2\n", "x.scene:2:", "number");
    expect_err("camera a.lens\nsphere 0 0 1 2 image nope.ppm 10\n", "x.scene:2:", "nope.ppm");
    expect_err("sphere 0 0 1 2\n", "x.scene", "camera");
    expect_err("camera a.lens\n", "x.scene", "no objects");
}

static void test_intersect(void **state)
{
    (void)state;
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse("camera a.lens\n"
                                 "sphere 0 0 100 10\n"
                                 "disk 0 0 50 0 0 -1 5\n"
                                 "plane 0 0 200 0 0 -1\n",
                                 "t.scene", &s, &err), 0);
    double o[3] = {0, 0, 0}, d[3] = {0, 0, 1};
    scene_hit h;
    assert_true(scene_intersect(&s, o, d, 1e-6, INFINITY, &h));
    assert_int_equal(h.obj, 1); /* the disk in front of the sphere */
    assert_true(fabs(h.t - 50) < 1e-12);
    assert_true(h.n[2] == -1);
    double o2[3] = {6, 0, 0};   /* beside the disk, into the sphere at x = 6 */
    assert_true(scene_intersect(&s, o2, d, 1e-6, INFINITY, &h));
    assert_int_equal(h.obj, 0);
    assert_true(fabs(h.t - (100 - 8)) < 1e-9); /* sqrt(10^2 - 6^2) = 8 */
    assert_true(fabs(h.n[0] - 0.6) < 1e-12 && fabs(h.n[2] + 0.8) < 1e-12);
    double o3[3] = {20, 0, 0};
    assert_true(scene_intersect(&s, o3, d, 1e-6, INFINITY, &h));
    assert_int_equal(h.obj, 2);
    assert_true(fabs(h.t - 200) < 1e-9);
    double a[3] = {0, 0, 0}, b[3] = {0, 0, 40}, c[3] = {0, 0, 60};
    assert_true(scene_visible(&s, a, b));
    assert_false(scene_visible(&s, a, c));
    scene_free(&s);
}

/* A diffuse floor lit by an emitter disk straight above: the irradiance under the
 * centre of a Lambertian disk of radiance L, radius R at height h is
 * E = pi L R^2 / (h^2 + R^2), so the reflected radiance is albedo E / pi. */
static void test_direct_light(void **state)
{
    (void)state;
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse("camera a.lens\n"
                                 "plane 0 0 0 0 1 0 albedo 0.5\n"
                                 "disk 0 30 0 0 -1 0 40 emit 2\n",
                                 "t.scene", &s, &err), 0);
    double p[3] = {0, 0, 0}, n[3] = {0, 1, 0}, rgb[3], sum = 0, sum2 = 0;
    int N = 20000;
    unsigned long long st = 12345;
    for (int i = 0; i < N; i++) {
        double u[2];
        for (int k = 0; k < 2; k++) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            u[k] = (st >> 11) * 0x1.0p-53;
        }
        scene_direct(&s, 0, p, n, u, rgb);
        sum += rgb[0];
        sum2 += rgb[0] * rgb[0];
    }
    double mean = sum / N, se = sqrt((sum2 / N - mean * mean) / N);
    double expect = 0.5 * 2 * 40 * 40 / (30.0 * 30 + 40 * 40);
    assert_true(fabs(mean - expect) < 4 * se + 1e-12);
    assert_true(se < 0.01 * expect);
    scene_free(&s);
}

/* Channel c of object 0's albedo at p. */
static double albedo(const scene_t *s, const double p[3], int c)
{
    double rgb[3];
    scene_albedo(s, 0, p, rgb);
    return rgb[c];
}

static void test_checker(void **state)
{
    (void)state;
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse("camera a.lens\nplane 0 0 100 0 0 -1 checker 0.1 0.9 10\n",
                                 "t.scene", &s, &err), 0);
    double p1[3] = {5, 5, 105}, p2[3] = {15, 5, 105};
    double a = albedo(&s, p1, 0), b = albedo(&s, p2, 0);
    assert_true((a == 0.1 && b == 0.9) || (a == 0.9 && b == 0.1));
    /* the plane lies on a cell face: a hit a rounding error either side of it keeps
     * its colour */
    double p3[3] = {5, 5, nextafter(100, 0)}, p4[3] = {5, 5, nextafter(100, 200)};
    assert_true(albedo(&s, p3, 0) == albedo(&s, p4, 0));
    scene_free(&s);
}

/* An image texture (binary PPM) on a plane facing the camera: left pixel red, right
 * pixel blue, upright as drawn. */
static void test_image_texture(void **state)
{
    (void)state;
    char dir[] = "/tmp/scene-tex-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char ppm[256], scn[256];
    snprintf(ppm, sizeof ppm, "%s/t.ppm", dir);
    snprintf(scn, sizeof scn, "%s/t.scene", dir);
    FILE *f = fopen(ppm, "wb");
    assert_non_null(f);
    fprintf(f, "P6\n# two pixels\n2 1\n255\n");
    unsigned char px[6] = {255, 0, 0, 0, 0, 255};
    fwrite(px, 1, 6, f);
    fclose(f);
    f = fopen(scn, "w");
    assert_non_null(f);
    fprintf(f, "camera a.lens\nplane 0 0 100 0 0 -1 image t.ppm 20\n");
    fclose(f);
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_load(scn, &s, &err), 0);
    double left[3] = {-5, 0, 100}, right[3] = {5, 0, 100};
    assert_true(albedo(&s, left, 0) == 1 && albedo(&s, left, 2) == 0);
    assert_true(albedo(&s, right, 0) == 0 && albedo(&s, right, 2) == 1);
    scene_free(&s);
    remove(ppm);
    remove(scn);
    remove(dir);
}

/* scene_intersect_emitter is scene_intersect kept only where the nearest hit emits:
 * rays from inside a box of emitters and blockers, in every direction. */
static void test_intersect_emitter(void **state)
{
    (void)state;
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse("camera a.lens\n"
                                 "plane 0 -100 0  0 1 0  albedo 0.5\n"
                                 "plane 0 100 0  0 -1 0  emit 1\n"
                                 "sphere 30 0 60 20 albedo 0.8\n"
                                 "sphere 30 0 120 25 emit 5\n"
                                 "disk -40 50 80 0 -1 0 30 emit 3\n"
                                 "sphere -40 -20 70 10 albedo 0.3\n",
                                 "t.scene", &s, &err), 0);
    uint64_t st = 3;
    int emitting = 0;
    for (int i = 0; i < 20000; i++) {
        double d[3], o[3] = {0, 0, 0};
        for (;;) {
            for (int k = 0; k < 3; k++) {
                st = st * 6364136223846793005ull + 1442695040888963407ull;
                d[k] = (double)(st >> 11) * 0x1.0p-52 - 1;
            }
            double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            if (l > 0.1 && l <= 1) {
                for (int k = 0; k < 3; k++) d[k] /= l;
                break;
            }
        }
        scene_hit a, b;
        int ha = scene_intersect(&s, o, d, 1e-6, INFINITY, &a);
        int want = ha && scene_is_emitter(&s.obj[a.obj]);
        int hb = scene_intersect_emitter(&s, o, d, 1e-6, &b);
        assert_int_equal(hb, want);
        if (hb) {
            assert_int_equal(b.obj, a.obj);
            assert_true(b.t == a.t && b.p[0] == a.p[0] && b.n[1] == a.n[1]);
            emitting++;
        }
    }
    assert_true(emitting > 4000 && emitting < 16000); /* both outcomes are common */
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_good),   cmocka_unit_test(test_parse_errors),
        cmocka_unit_test(test_intersect),    cmocka_unit_test(test_direct_light),
        cmocka_unit_test(test_checker),      cmocka_unit_test(test_image_texture),
        cmocka_unit_test(test_intersect_emitter),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
