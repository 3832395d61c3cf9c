/* The polynomial camera's batch maps against its one-ray maps: map_batch (lens-render's
 * eq13 path) against map, and outer_batch (the full estimator's) against outer with the
 * Jacobian, on the double Gauss through lens-render's own system with its transmittance
 * and rim outputs, with and without six blades. The batch maps read only the outputs
 * they use (poly_eval_batch_outputs): a row place taken for another output (the
 * transmittance's, the stop hit's) or a chunk boundary crossed wrongly changes a ray, a
 * weight or a pass flag here. The one-ray poly_eval may run in vectors (poly.h: the
 * batch values to 1e-12 relative, the pass flag from them), so values must agree to
 * 1e-9 and pass flags on all but one ray in 500 (a pass circle's very edge); the
 * defects guarded move values by far more and flip dozens of flags. 1100 rays: more
 * than two of the maps' chunks. And the front surface's rays in AVX-512 lanes against
 * ray_from_outer. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "fixture_lenses.h"
#include "splitmix.h"
#include "sparselens/glass.h"
#include "sparselens/render.h"
#include "sparselens/render_effects.h"
#include "sparselens/render_lens.h"
#include "sparselens/scene.h"
#include "sparselens/trace.h"
#include "render/render_lens_simd.h"

#define N 1100
#define SW 36.0
#define SH 24.0

/* a and b agree to rounding */
static int near(const double *a, const double *b, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!(fabs(a[i] - b[i]) <= 1e-9 * (1 + fabs(a[i])))) return 0;
    return 1;
}

/* Camera samples over the sensor, directions from the line pupil (as render_image
 * draws them); returns how many have a direction. */
static int samples(const render_sampler *smp, double *in)
{
    uint64_t st = 11;
    int drawn = 0;
    for (int k = 0; k < N; k++) {
        double *q = in + 5 * k;
        q[0] = (splitmix_uniform(&st) - 0.5) * SW, q[1] = (splitmix_uniform(&st) - 0.5) * SH, q[4] = GLASS_D_LINE;
        drawn += render_sampler_sample_2d(smp, q[0], q[1], splitmix_uniform(&st), splitmix_uniform(&st), q + 2, q + 3) > 0;
    }
    return drawn;
}

/* map_batch and outer_batch against map and outer, ray by ray; returns the rays that
 * pass. */
static int compare_maps(const render_camera *cam, const double *in)
{
    static double org[N * 3], dir[N * 3], eta[N], o4[N * 4], jac[N * 16], eta4[N];
    static unsigned char pass[N], pass4[N];
    cam->map_batch(cam->ctx, N, in, org, dir, eta, pass);
    cam->outer_batch(cam->ctx, N, in, o4, jac, eta4, pass4);
    int passed = 0, flips = 0;
    for (int k = 0; k < N; k++) {
        double o[3], d[3], e, oo[4], J[16], e4;
        int p = cam->map(cam->ctx, in + 5 * k, o, d, &e);
        int p4 = cam->outer(cam->ctx, in + 5 * k, oo, J, &e4);
        flips += (pass[k] != p) + (pass4[k] != p4);
        passed += pass[k];
        if (p && pass[k])
            assert_true(near(o, org + 3 * k, 3) && near(d, dir + 3 * k, 3) && near(&e, eta + k, 1));
        if (p4 && pass4[k])
            assert_true(near(oo, o4 + 4 * k, 4) && near(J, jac + 16 * k, 16) &&
                        near(&e4, eta4 + k, 1));
    }
    if (flips > 2 * N / 500) fail_msg("%d pass flags differ between batch and one ray", flips);
    return passed;
}

static void test_batch_maps(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse("camera a.lens\nresolution 6 4\nmode grey\ntransmittance on\n"
                                 "vignetting on\nplane 0 0 1000 0 0 -1 emit 1\n", "t.scene",
                                 &s, &err), 0);
    render_effects e;
    assert_int_equal(render_effects_decide(&s, &lens, SW, SH, &e, &err), 0);
    double fit_s;
    poly_system *sys = render_fit(&lens, &e, 0, &fit_s, &err);
    assert_non_null(sys);
    assert_true(poly_output_index(sys, "out_eta") >= 0 && poly_noutputs(sys) > 7);
    render_camera cam;
    render_lens_ctx *lc = render_lens_poly(sys, &lens, SW, SH, &cam, &err);
    assert_non_null(lc);
    render_sampler smp;
    assert_int_equal(render_sampler_lens(&smp, &lens, GLASS_D_LINE, GLASS_D_LINE, hypot(18, 12), 0,
                                         &err), 0);
    static double in[N * 5];
    assert_true(samples(&smp, in) > N * 9 / 10);
    int round = compare_maps(&cam, in);
    assert_int_equal(render_lens_set_blades(lc, 6, 0.3, &err), 0);
    int bladed = compare_maps(&cam, in);
    print_message("batch maps: %d of %d rays pass, %d through six blades\n", round, N, bladed);
    /* the blades must cut rays, or the test would not see their outputs' place */
    assert_true(round > N / 2 && bladed < round);
    render_sampler_free(&smp);
    render_lens_free(lc);
    poly_free(sys);
    scene_free(&s);
    lens_free(&lens);
}

/* The front surface's rays eight at a time (render_simd_front, the batch map's last
 * step) against the library's ray_from_outer on the double Gauss's spherical front: the
 * same rays to rounding, status 1 exactly where u^2 + v^2 > 1 and 2 where the point is off
 * the surface's sphere (ray_from_outer: off the surface, -1) or not finite. */
static void test_front_lanes(void **state)
{
    (void)state;
#if RENDER_LENS_SIMD
    if (!render_lens_simd_ok()) return;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    const lens_surface *f = &lens.surf[0];
    assert_true(f->conic == 0 && isfinite(f->radius));
    enum { M = 200 };
    double X[4 * M], O[3 * M], D[3 * M], c = 1.0 / f->radius, R = fabs(f->radius);
    unsigned char st[M];
    uint64_t seed = 5;
    for (int i = 0; i < M; i++) {
        double r = i % 10 == 9 ? R * (1 + 0.2 * splitmix_uniform(&seed)) /* off the sphere */
                               : 0.99 * R * sqrt(splitmix_uniform(&seed));
        double q = i % 7 == 6 ? 1 + 0.1 * splitmix_uniform(&seed) /* no direction */
                              : 0.9 * sqrt(splitmix_uniform(&seed));
        double a = 2 * M_PI * splitmix_uniform(&seed);
        double b = 2 * M_PI * splitmix_uniform(&seed);
        X[i] = r * cos(a), X[M + i] = r * sin(a), X[2 * M + i] = q * cos(b), X[3 * M + i] = q * sin(b);
    }
    X[M - 1] = INFINITY;
    render_simd_front(c, c * c, lens.vertex_z[0], M, M, X, O, D, st);
    int counts[3] = {0, 0, 0};
    for (int i = 0; i < M; i++) {
        double p[4] = {X[i], X[M + i], X[2 * M + i], X[3 * M + i]};
        double h2 = p[0] * p[0] + p[1] * p[1], w2 = 1 - p[2] * p[2] - p[3] * p[3];
        lens_ray ref;
        int off = !(h2 < R * R) || !isfinite(p[0]);
        counts[st[i]]++;
        assert_int_equal(st[i], off ? 2 : w2 < 0 ? 1 : 0);
        if (st[i]) continue;
        assert_int_equal(ray_from_outer(&lens, p, &ref), 0);
        for (int k = 0; k < 3; k++) {
            assert_true(fabs(O[k * M + i] - ref.o[k]) < 1e-12 * (1 + fabs(ref.o[k])));
            assert_true(fabs(D[k * M + i] - ref.d[k]) < 1e-14);
        }
    }
    assert_true(counts[0] > M / 2 && counts[1] > 5 && counts[2] > 5);
    lens_free(&lens);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_batch_maps), cmocka_unit_test(test_front_lanes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
