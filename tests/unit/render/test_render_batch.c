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
 * than two of the maps' chunks. */
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_batch_maps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
