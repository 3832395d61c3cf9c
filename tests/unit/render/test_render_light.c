/* The integrator's pieces against independent references:
 *  - the CIE 1931 fit at known values of the tabulated observer, the white balance (a
 *    flat spectrum gives r = g = b = 1) and the round trip r g b -> spectrum -> r g b;
 *  - direct light by MIS (scene_direct_mis) against closed forms: a Lambertian disk
 *    light overhead (E = pi L R^2 / (h^2 + R^2)) and a sphere light (E = pi L (r / d)^2
 *    for a surface facing its centre), and an infinite emitting plane, which only the
 *    BSDF sample finds (E = pi L);
 *  - the low-discrepancy pixel samples: stratified (a 1D dimension has one sample per
 *    stratum; 32 2D samples one per elementary box of area 1/32), and unbiased over
 *    pixels (the mean of many pixels' points is 1/2);
 *  - the camera rays' direction culling against the full intersection loop, and the
 *    block version of the culled search (scene_intersect_camera_many) against it;
 *  - direct light for a block of points at once (scene_direct_mis_many, eight lanes a
 *    step where the processor has AVX-512) against scene_direct_mis point by point, bit
 *    for bit. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "render/render_samples.h"
#include "render/scene_camera_block.h"
#include "render/scene_light_block.h"
#include "render/scene_light_simd.h"
#include "sparselens/render.h"
#include "sparselens/render_spectrum.h"
#include "sparselens/scene.h"

static void test_cie_fit(void **state)
{
    (void)state;
    /* CIE 1931 2-degree table: (nm, xbar, ybar, zbar) */
    static const double tab[][4] = {{450, 0.3362, 0.0380, 1.7721}, {500, 0.0049, 0.3230, 0.2720},
                                    {555, 0.5121, 1.0000, 0.0057}, {600, 1.0622, 0.6310, 0.0008},
                                    {650, 0.2835, 0.1070, 0.0000}};
    for (size_t k = 0; k < sizeof tab / sizeof tab[0]; k++) {
        double xyz[3];
        cie_xyz_bar(tab[k][0] / 1000, xyz);
        for (int c = 0; c < 3; c++) assert_true(fabs(xyz[c] - tab[k][1 + c]) < 0.03 + 0.03 * tab[k][1 + c]);
    }
}

/* The integral of a spectrum against render_rgb_bar, by the midpoint rule. */
static void integrate(const double rgb[3], double out[3])
{
    int n = 6000;
    double h = (RENDER_LAMBDA_MAX - RENDER_LAMBDA_MIN) / n;
    out[0] = out[1] = out[2] = 0;
    for (int i = 0; i < n; i++) {
        double lam = RENDER_LAMBDA_MIN + (i + 0.5) * h, bar[3];
        render_rgb_bar(lam, bar);
        double s = rgb ? render_rgb_spectrum(rgb, lam) : 1;
        for (int c = 0; c < 3; c++) out[c] += s * bar[c] * h;
    }
}

static void test_spectrum_round_trip(void **state)
{
    (void)state;
    double w[3];
    integrate(NULL, w);
    for (int c = 0; c < 3; c++) assert_true(fabs(w[c] - 1) < 1e-4);
    double cols[][3] = {{0.8, 0.3, 0.2}, {0.2, 0.6, 0.8}, {0.5, 0.5, 0.5}, {2000, 1500, 800}};
    for (size_t k = 0; k < 4; k++) {
        double back[3];
        integrate(cols[k], back);
        for (int c = 0; c < 3; c++) assert_true(fabs(back[c] - cols[k][c]) < 1e-3 * cols[k][c]);
    }
    /* a grey stays flat */
    double g[3] = {0.5, 0.5, 0.5};
    assert_true(fabs(render_rgb_spectrum(g, 0.45) - 0.5) < 1e-9);
    assert_true(fabs(render_rgb_spectrum(g, 0.65) - 0.5) < 1e-9);
}

static uint64_t lcg(uint64_t *s)
{
    return *s = *s * 6364136223846793005ull + 1442695040888963407ull;
}

/* Mean and standard error of scene_direct_mis at the origin (normal +y), channel 0. */
static void mis_mean(const char *text, double *mean, double *se)
{
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse(text, "t.scene", &s, &err), 0);
    scene_hit h = {.t = 1, .p = {0, 0, 0}, .n = {0, 1, 0}, .obj = 0};
    uint64_t st = 777;
    int N = 40000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < N; i++) {
        double u[5];
        for (int k = 0; k < 5; k++) u[k] = (lcg(&st) >> 11) * 0x1.0p-53;
        scene_light_terms t;
        scene_direct_mis(&s, &h, u, &t);
        double v = 0;
        for (int k = 0; k < t.n; k++) v += t.w[k] * s.obj[t.emitter[k]].emit[0];
        double alb[3];
        scene_albedo(&s, 0, h.p, alb);
        v *= alb[0];
        sum += v, sum2 += v * v;
    }
    *mean = sum / N;
    *se = sqrt((sum2 / N - *mean * *mean) / N);
    scene_free(&s);
}

static void test_mis_closed_forms(void **state)
{
    (void)state;
    double m, se;
    /* disk, radius 40 at height 30, L = 2: reflected albedo E / pi */
    mis_mean("camera a.lens\nplane 0 0 0 0 1 0 albedo 0.5\ndisk 0 30 0 0 -1 0 40 emit 2\n", &m, &se);
    double expect = 0.5 * 2 * 40 * 40 / (30.0 * 30 + 40 * 40);
    assert_true(fabs(m - expect) < 4 * se);
    assert_true(se < 0.01 * expect);
    /* sphere, radius 5 at distance 50 straight above: E = pi L (r/d)^2 */
    mis_mean("camera a.lens\nplane 0 0 0 0 1 0 albedo 0.5\nsphere 0 50 0 5 emit 3\n", &m, &se);
    expect = 0.5 * 3 * (5.0 / 50) * (5.0 / 50);
    assert_true(fabs(m - expect) < 4 * se);
    assert_true(se < 0.01 * expect); /* solid-angle sampling: nearly noiseless */
    /* an emitting plane overhead: only the BSDF sample sees it, E = pi L */
    mis_mean("camera a.lens\nplane 0 0 0 0 1 0 albedo 0.5\nplane 0 10 0 0 -1 0 emit 2\n", &m, &se);
    assert_true(fabs(m - 0.5 * 2) < 1e-9);
    /* both lights at once: the sum */
    mis_mean("camera a.lens\nplane 0 0 0 0 1 0 albedo 0.5\ndisk 0 30 0 0 -1 0 40 emit 2\n"
             "sphere 60 20 0 5 emit 300\n", &m, &se);
    double d2 = 60.0 * 60 + 20 * 20, cosc = 20 / sqrt(d2);
    expect = 0.5 * 2 * 40 * 40 / (30.0 * 30 + 40 * 40) + 0.5 * 300 * 25 / d2 * cosc;
    assert_true(fabs(m - expect) < 4 * se + 1e-3 * expect);
}

static void test_samples_stratified(void **state)
{
    (void)state;
    int n = 37; /* not a power of two */
    for (uint64_t pix = 0; pix < 20; pix++) {
        uint64_t key = ld_pixel_key(5, pix);
        int hits[37] = {0}, hx[37] = {0}, hy[37] = {0}, cell[4][8] = {{0}};
        for (int k = 0; k < n; k++) {
            double q[2];
            hits[(int)(ld_1d(key, 0, n, k) * n)]++;
            ld_2d(key, 1, n, k, q);
            hx[(int)(q[0] * 32)]++, hy[(int)(q[1] * 32)]++; /* the first 32 fill 32 strata */
        }
        int empty1 = 0, emptyx = 0, emptyy = 0;
        for (int i = 0; i < n; i++) empty1 += !hits[i];
        for (int i = 0; i < 32; i++) emptyx += !hx[i], emptyy += !hy[i];
        /* 32 points of the scrambled (0, 2)-sequence: one in each 1/4 x 1/8 box */
        for (int k = 0; k < 32; k++) {
            double q[2];
            ld_2d(key, 3, 32, k, q);
            cell[(int)(q[0] * 4)][(int)(q[1] * 8)]++;
        }
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 8; j++) assert_int_equal(cell[i][j], 1);
        assert_int_equal(empty1, 0); /* jittered strata: one per stratum */
        assert_int_equal(emptyx + emptyy, 0);
    }
    double sum = 0;
    int pixels = 20000;
    for (int p = 0; p < pixels; p++) {
        double q[2];
        ld_2d(ld_pixel_key(9, (uint64_t)p), 2, 16, 3, q);
        sum += q[0];
    }
    assert_true(fabs(sum / pixels - 0.5) < 4 * sqrt(1.0 / 12 / pixels));
}

/* The block drawer (ld_2d_run, ld_1d_run: four samples at a time in 32-bit lanes, and
 * sixteen in AVX-512 lanes for counts up to 2^16) gives the values of ld_2d_px and
 * ld_1d_px bit for bit: powers of two and others (the permutation's rejection walk), runs
 * that start anywhere and end off a multiple of 4 and of 16, a count past 2^16 (no
 * sixteen-lane step) and one past 2^32 (the lanes cannot hold it: the scalar path). */
static void test_sample_runs(void **state)
{
    (void)state;
    const uint64_t ns[] = {2, 3, 5, 16, 17, 32, 37, 128, 1000, 100000, 5000000000ull};
    double out[9 * 70], r[2];
    long checked = 0;
    for (int pi = 0; pi < 30; pi++) {
        ld_pixel p;
        ld_pixel_init(&p, ld_pixel_key(4, (uint64_t)pi));
        for (int ni = 0; ni < 11; ni++) {
            uint64_t n = ns[ni], count = n < 70 ? n : 70, k0 = n > count ? (uint64_t)pi % (n - count) : 0;
            for (int d = 0; d < LD_DIMS; d++) {
                ld_2d_run(&p, d, n, k0, (int)count, out, 9);
                ld_1d_run(&p, d, n, k0, (int)count, out + 2, 9);
                for (uint64_t c = 0; c < count; c++, checked++) {
                    ld_2d_px(&p, d, n, k0 + c, r);
                    assert_true(r[0] == out[9 * c] && r[1] == out[9 * c + 1]);
                    assert_true(ld_1d_px(&p, d, n, k0 + c) == out[9 * c + 2]);
                }
            }
        }
    }
    assert_true(checked == 30 * 392 * LD_DIMS);
}

/* Direction culling finds exactly the hits of the full loop, for rays from anywhere in
 * the origin ball, over many spheres in every direction (and a plane behind them). */
/* Points on the floor, on spheres and in the air with normals of every sign (n_z >= 0 and
 * < 0 take the frame's two branches; 0 exactly too), uniforms at quadrant edges of the
 * sine and cosine among random ones; emitters of every kind, one sphere holding points
 * (inside: its weight is 2 pi) and one disk facing away from some. 203 points: three
 * steps of 64 and a last partial step of eight lanes. */
static void test_mis_many(void **state)
{
    (void)state;
    scene_t s;
    lens_err err = {{0}};
    const char *text = "camera a.lens\nplane 0 0 0 0 1 0 albedo 0.5\n"
                       "disk 0 300 0 0 -1 0 200 emit 4\ndisk 100 50 0 1 0 0 30 emit 1 2 3\n"
                       "sphere 40 60 30 25 emit 30\nsphere -300 200 4000 8 emit 2000 1500 800\n"
                       "sphere 0 0 0 1000 albedo 0.2\nplane 0 0 5000 0 0 -1 emit 0.5\n"
                       "sphere 0 20 0 10 albedo 0.7\n";
    assert_int_equal(scene_parse(text, "t.scene", &s, &err), 0);
    enum { M = 203 };
    scene_hit h[M];
    double u[5 * M];
    uint64_t st = 4242;
    static const double edge[] = {0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 0.999999999};
    for (int i = 0; i < M; i++) {
        double r[8];
        for (int k = 0; k < 8; k++) r[k] = (lcg(&st) >> 11) * 0x1.0p-53;
        h[i].t = 1, h[i].obj = 0;
        h[i].p[0] = 400 * r[0] - 200, h[i].p[1] = i % 3 ? 0 : 100 * r[1], h[i].p[2] = 400 * r[2] - 200;
        if (i % 5 == 0) h[i].p[0] = 40, h[i].p[1] = 60, h[i].p[2] = 30 + 20 * r[1]; /* in a sphere */
        double n[3] = {r[3] - 0.5, r[4] - 0.5, i % 7 == 0 ? 0 : r[5] - 0.5}, l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; k++) h[i].n[k] = n[k] / l;
        if (i % 4 == 0) h[i].n[0] = 0, h[i].n[1] = 1, h[i].n[2] = 0;
        for (int k = 0; k < 5; k++) u[5 * i + k] = (lcg(&st) >> 11) * 0x1.0p-53;
        if (i % 2) u[5 * i + 4] = edge[i / 2 % 9];
        if (i % 11 == 0) u[5 * i + 3] = i % 22 ? 0 : 1;
    }
    scene_light_terms many[M];
    scene_direct_mis_many(&s, M, h, u, many);
    int terms = 0;
    for (int i = 0; i < M; i++) {
        scene_light_terms one;
        scene_direct_mis(&s, &h[i], u + 5 * i, &one);
        assert_int_equal(many[i].n, one.n);
        for (int k = 0; k < one.n; k++) {
            assert_int_equal(many[i].emitter[k], one.emitter[k]);
            assert_memory_equal(&many[i].w[k], &one.w[k], sizeof one.w[k]);
        }
        terms += one.n;
    }
    assert_true(terms > M / 2); /* light found: the comparison compares something */
    printf("direct light of %d points at once: %d terms, bit for bit (%s)\n", M, terms,
           scene_simd_ok() ? "AVX-512 lanes" : "no AVX-512: point by point");
    scene_free(&s);
    /* no emitter at all: no term, as point by point */
    assert_int_equal(scene_parse("camera a.lens\nplane 0 0 0 0 1 0 albedo 0.5\n", "t.scene", &s, &err), 0);
    scene_direct_mis_many(&s, 9, h, u, many);
    for (int i = 0; i < 9; i++) assert_int_equal(many[i].n, 0);
    scene_free(&s);
}

static void test_cull_exact(void **state)
{
    (void)state;
    char text[20000];
    int len = snprintf(text, sizeof text, "camera a.lens\nplane 0 0 3000 0 0 -1 albedo 0.5\n"
                                          "disk 100 0 800 0.6 0 -0.8 300 albedo 0.3\n");
    uint64_t st = 99;
    for (int k = 0; k < 120; k++) {
        double th = acos(1 - 1.1 * ((lcg(&st) >> 11) * 0x1.0p-53)), ph = 2 * M_PI * ((lcg(&st) >> 11) * 0x1.0p-53);
        double r = 100 + 900 * ((lcg(&st) >> 11) * 0x1.0p-53), rad = 2 + 30 * ((lcg(&st) >> 11) * 0x1.0p-53);
        len += snprintf(text + len, sizeof text - len, "sphere %.6f %.6f %.6f %.6f emit 1\n",
                        r * sin(th) * cos(ph), r * sin(th) * sin(ph), r * cos(th), rad);
    }
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse(text, "t.scene", &s, &err), 0);
    double rho = 25;
    scene_cull *c = scene_cull_new(&s, rho);
    assert_non_null(c);
    int hits = 0, nb = 0;
    enum { NB = 1000 };
    double O[3 * NB], D[3 * NB];
    for (int i = 0; i < 200000; i++) {
        double *o = O + 3 * nb, *d = D + 3 * nb, n;
        do {
            for (int k = 0; k < 3; k++) o[k] = rho * (2 * ((lcg(&st) >> 11) * 0x1.0p-53) - 1);
        } while (o[0] * o[0] + o[1] * o[1] + o[2] * o[2] > rho * rho);
        for (int k = 0; k < 3; k++) d[k] = 2 * ((lcg(&st) >> 11) * 0x1.0p-53) - 1;
        n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int k = 0; k < 3; k++) d[k] /= n;
        scene_hit a, b;
        int ha = scene_intersect(&s, o, d, 1e-6, INFINITY, &a);
        int hb = scene_intersect_camera(&s, c, o, d, 1e-6, &b);
        assert_int_equal(ha, hb);
        if (ha) {
            assert_int_equal(a.obj, b.obj);
            assert_true(a.t == b.t);
            hits += a.obj > 1;
        }
        if (++nb < NB) continue;
        /* the block version (eight rays a step where it can) gives the same records */
        scene_hit many[NB];
        unsigned char ok[NB];
        scene_intersect_camera_many(&s, c, NB, O, D, 1e-6, many, ok);
        for (int k = 0; k < NB; k++) {
            scene_hit one;
            assert_int_equal(ok[k], scene_intersect_camera(&s, c, O + 3 * k, D + 3 * k, 1e-6, &one));
            if (!ok[k]) continue;
            assert_int_equal(many[k].obj, one.obj);
            assert_memory_equal(&many[k].t, &one.t, sizeof one.t);
            assert_memory_equal(many[k].p, one.p, sizeof one.p);
            assert_memory_equal(many[k].n, one.n, sizeof one.n);
        }
        nb = 0;
    }
    assert_true(hits > 1000); /* the spheres were met, not only the plane and the disk */
    scene_cull_free(c);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cie_fit), cmocka_unit_test(test_spectrum_round_trip),
        cmocka_unit_test(test_mis_closed_forms), cmocka_unit_test(test_samples_stratified),
        cmocka_unit_test(test_sample_runs),
        cmocka_unit_test(test_cull_exact), cmocka_unit_test(test_mis_many),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
