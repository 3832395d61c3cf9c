/* Unbiasedness of the polynomial path (issue 4): one large uniform emitter in front of
 * the 50 mm double Gauss, rendered
 *   A: with a system fitted by render_fit and line-pupil sampling, and
 *   B: independently, with exact tracing and directions drawn uniformly over the rear
 *      element's disk with their own density,
 * must agree within three standard errors (from the samples) in every region. Also:
 * the effects a grey scene calls for, and the cache round trip. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "fixture_lenses.h"
#include "sparselens/glass.h"
#include "sparselens/render.h"
#include "sparselens/render_effects.h"
#include "sparselens/render_lens.h"
#include "sparselens/scene.h"

static void load(scene_t *s, const char *text)
{
    lens_err err = {{0}};
    if (scene_parse(text, "t.scene", s, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
}

static void test_poly_vs_exact_rear(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    scene_t s;
    load(&s, "camera a.lens\nresolution 12 8\nmode grey\ntransmittance on\n"
             "plane 0 0 1000 0 0 -1 emit 1\n");
    lens_err err = {{0}};
    render_effects e;
    assert_int_equal(render_effects_decide(&s, &lens, 36, 24, &e, &err), 0);
    assert_false(e.dispersion);    /* a grey scene needs no lambda */
    assert_true(e.transmittance);  /* the scene asks for it */
    double fit_s;
    poly_system *sys = render_fit(&lens, &e, 0, &fit_s, &err);
    if (!sys) print_error("%s\n", err.msg);
    assert_non_null(sys);
    assert_int_equal(poly_input_index(sys, "lambda"), -1);

    render_camera cp, ce;
    render_lens_ctx *lp = render_lens_poly(sys, &lens, 36, 24, &cp, &err);
    render_lens_ctx *le = render_lens_exact(&lens, 36, 24, &ce, &err);
    assert_non_null(lp);
    assert_non_null(le);
    render_sampler pupil, rear;
    /* the line pupil as lens-render builds it: from the exact lens */
    assert_int_equal(render_sampler_lens(&pupil, &lens, GLASS_D_LINE, GLASS_D_LINE, hypot(18, 12), 0,
                                         &err), 0);
    render_sampler_rear(&rear, &ce);
    const char *san = getenv("SANITIZE");
    long spp = san && *san ? 256 : 1024;
    render_job a = {.scene = &s, .cam = &cp, .sampler = &pupil, .use_eta = 1, .spp = spp};
    render_job b = {.scene = &s, .cam = &ce, .sampler = &rear, .use_eta = 1, .spp = spp};
    float ia[12 * 8 * 3], va[12 * 8 * 3], ib[12 * 8 * 3], vb[12 * 8 * 3];
    render_stats sa, sb;
    assert_int_equal(render_image(&a, ia, va, &sa, &err), 0);
    assert_int_equal(render_image(&b, ib, vb, &sb, &err), 0);
    int misses = 0;
    for (int ry = 0; ry < 4; ry++)
        for (int rx = 0; rx < 6; rx++) { /* 2x2-pixel regions */
            double ma = 0, mb = 0, v = 0;
            for (int y = 2 * ry; y < 2 * ry + 2; y++)
                for (int x = 2 * rx; x < 2 * rx + 2; x++) {
                    size_t i = 3 * ((size_t)y * 12 + x);
                    ma += ia[i], mb += ib[i], v += va[i] + vb[i];
                }
            if (fabs(ma - mb) > 3 * sqrt(v)) {
                print_error("region %d,%d: poly %g exact %g (se of the difference %g)\n", rx, ry,
                            ma / 4, mb / 4, sqrt(v) / 4);
                misses++;
            }
        }
    double pa = sa.passed_rays / sa.camera_rays, pb = sb.passed_rays / sb.camera_rays;
    print_message("camera rays passing: line pupil %.1f%%, rear element %.1f%%\n", 100 * pa,
                  100 * pb);
    /* 24 regions at three standard errors: one miss may be chance, two are not */
    assert_true(misses <= 1);
    assert_true(pa > pb);
    render_sampler_free(&pupil);
    render_sampler_free(&rear);
    render_lens_free(lp);
    render_lens_free(le);
    poly_free(sys);
    scene_free(&s);
    lens_free(&lens);
}

/* A system goes into the cache under its key and comes back from it. */
static void test_cache(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    scene_t s;
    load(&s, "camera a.lens\nresolution 24 16\nmode rgb\nplane 0 0 1000 0 0 -1 emit 1\n");
    lens_err err = {{0}};
    render_effects e, g;
    assert_int_equal(render_effects_decide(&s, &lens, 36, 24, &e, &err), 0);
    /* colour alone does not call for lambda: the double Gauss's glasses are bare indices */
    assert_false(render_lens_disperses(&lens));
    assert_false(e.dispersion);
    /* a tenth of a 1.5 mm pixel over the efl */
    assert_true(fabs(e.tolerance - 0.1 * 1.5 / e.efl) < 1e-12);
    g = e;
    g.dispersion = 1;
    char k1[17], k2[17];
    render_effects_key(&lens, &e, k1);
    render_effects_key(&lens, &g, k2);
    assert_string_not_equal(k1, k2);
    /* every effect on: the full system itself, so no second fit for the comparison */
    g.dispersion = g.transmittance = g.vignetting = 1;
    char dir[] = "/tmp/render-cache-XXXXXX";
    assert_non_null(mkdtemp(dir));
    FILE *log = tmpfile();
    poly_system *a = render_effects_system(&lens, &g, dir, 0, log, &err);
    assert_non_null(a);
    poly_system *b = render_effects_system(&lens, &g, dir, 0, log, &err);
    assert_non_null(b);
    assert_int_equal(poly_ninputs(a), 5);
    rewind(log);
    char line[512];
    int cached = 0;
    while (fgets(line, sizeof line, log)) cached += strstr(line, "system: cached") != NULL;
    assert_true(cached >= 1);
    fclose(log);
    double in[5] = {3, -2, -0.05, 0.04, 0.55}, oa[16], ob[16]; /* x y u v lambda */
    assert_int_equal(poly_eval(a, in, oa), poly_eval(b, in, ob));
    assert_true(fabs(oa[0] - ob[0]) < 1e-12);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    assert_int_equal(system(cmd), 0);
    poly_free(a);
    poly_free(b);
    scene_free(&s);
    lens_free(&lens);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_poly_vs_exact_rear),
        cmocka_unit_test(test_cache),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
