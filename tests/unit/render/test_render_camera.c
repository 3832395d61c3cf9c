/* The camera-ray API (camera.h) and the self-contained camera module:
 *  - lens_camera_rays, exact and polynomial, against render_image of a uniform emitter
 *    (radiance 1 in front of the lens: a pixel is the mean weight of its rays), per
 *    region within three standard errors, and its rays start on the front element;
 *  - the module lens_camera_emit writes, compiled by cc and loaded, renders the same
 *    uniform emitter through the same fitted system and six blades, with its own
 *    (coarser) line pupil, through its batch function NAME_rays: per pixel within three
 *    standard errors of lens_camera_rays through the system and the same blades; its
 *    NAME_ray gives the same rays one at a time; and the blades take the hexagon's share
 *    of the circle's light on the axis (through the API);
 *  - an aperture of blades: the light it passes near the axis, a hexagon's share of the
 *    circle. */
#include <dlfcn.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "fixture_lenses.h"
#include "splitmix.h"
#include "sparselens/camera.h"
#include "sparselens/glass.h"
#include "sparselens/render.h"
#include "sparselens/render_effects.h"
#include "sparselens/render_lens.h"
#include "sparselens/scene.h"

#define W 6
#define H 4
#define SW 36.0
#define SH 24.0

typedef double (*ray_fn)(double, double, double, double, double, double *, double *);
typedef size_t (*rays_fn)(size_t, const double *, double *);

/* Mean and variance of the mean of the weight per pixel, n samples each, through the
 * API (c) or the module's batch function (fn). */
static void weights(const lens_camera *c, rays_fn fn, long n, double *mean, double *var)
{
    uint64_t st = 42;
    double *s = malloc(n * LENS_CAMERA_SAMPLE * sizeof *s), *r = malloc(n * LENS_CAMERA_RAY * sizeof *r);
    assert_non_null(s);
    assert_non_null(r);
    for (int py = 0; py < H; py++)
        for (int px = 0; px < W; px++) {
            for (long k = 0; k < n; k++) {
                double *q = s + LENS_CAMERA_SAMPLE * k;
                q[0] = (px + splitmix_uniform(&st)) / W;
                q[1] = (py + splitmix_uniform(&st)) / H;
                q[2] = GLASS_D_LINE;
                q[3] = splitmix_uniform(&st), q[4] = splitmix_uniform(&st);
            }
            if (c) lens_camera_rays(c, (size_t)n, s, r);
            else fn((size_t)n, s, r);
            double sum = 0, sum2 = 0;
            for (long k = 0; k < n; k++) {
                double *ray = r + LENS_CAMERA_RAY * k, w = ray[6];
                if (w > 0) {
                    assert_true(fabs(ray[3] * ray[3] + ray[4] * ray[4] + ray[5] * ray[5] - 1) < 1e-12);
                    if (!(ray[5] > 0)) w = 0; /* the emitter is in front */
                }
                sum += w, sum2 += w * w;
            }
            double m = sum / n;
            mean[py * W + px] = m;
            var[py * W + px] = (sum2 / n - m * m) / n;
        }
    free(s);
    free(r);
}

/* render_image of the uniform emitter: pixel means and their variances. */
static void rendered(const render_camera *cam, const render_sampler *smp, long spp, double *mean,
                     double *var)
{
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse("camera a.lens\nresolution 6 4\nmode grey\n"
                                 "plane 0 0 1000 0 0 -1 emit 1\n", "t.scene", &s, &err), 0);
    render_job job = {.scene = &s, .cam = cam, .sampler = smp, .use_eta = 1, .spp = spp,
                      .achromatic = 1};
    float img[W * H * 3], v[W * H * 3];
    assert_int_equal(render_image(&job, img, v, NULL, &err), 0);
    for (int i = 0; i < W * H; i++) mean[i] = img[3 * i], var[i] = v[3 * i];
    scene_free(&s);
}

static int compare(const char *what, const double *ma, const double *va, const double *mb,
                   const double *vb)
{
    int misses = 0;
    for (int i = 0; i < W * H; i++)
        if (fabs(ma[i] - mb[i]) > 3 * sqrt(va[i] + vb[i]) + 1e-9) {
            print_error("%s: pixel %d: %g against %g (se %g)\n", what, i, ma[i], mb[i],
                        sqrt(va[i] + vb[i]));
            misses++;
        }
    return misses;
}

static long samples(void)
{
    const char *san = getenv("SANITIZE");
    return san && *san ? 1500 : 6000;
}

static void test_api_exact(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    lens_err err = {{0}};
    lens_camera *c = lens_camera_new(&lens, NULL, SW, SH, GLASS_D_LINE, GLASS_D_LINE, &err);
    assert_non_null(c);
    double ma[W * H], va[W * H], mb[W * H], vb[W * H];
    weights(c, NULL, samples(), ma, va);
    render_camera cam;
    render_lens_ctx *lc = render_lens_exact(&lens, SW, SH, &cam, &err);
    render_sampler smp;
    assert_int_equal(render_sampler_lens(&smp, &lens, GLASS_D_LINE, GLASS_D_LINE, hypot(18, 12), 0,
                                         &err), 0);
    rendered(&cam, &smp, samples(), mb, vb);
    assert_true(compare("api", ma, va, mb, vb) <= 1);
    /* a ray starts on the front element: z (scene) = -(sag) at its height */
    double q[LENS_CAMERA_SAMPLE] = {0.7, 0.2, GLASS_D_LINE, 0.3, 0.6}, r[LENS_CAMERA_RAY];
    assert_int_equal(lens_camera_rays(c, 1, q, r), 1);
    double h2 = r[0] * r[0] + r[1] * r[1];
    assert_true(fabs(-r[2] - lens_sag(&lens.surf[0], h2)) < 1e-9);
    render_sampler_free(&smp);
    render_lens_free(lc);
    lens_camera_free(c);
    lens_free(&lens);
}

/* The centre pixels' share of the round stop's light through the blades. */
static double centre_share(const double *m6, const double *m0)
{
    int centre[4] = {W + 2, W + 3, 2 * W + 2, 2 * W + 3};
    double a = 0, b = 0;
    for (int k = 0; k < 4; k++) a += m6[centre[k]], b += m0[centre[k]];
    return a / b;
}

/* The module's NAME_ray, one sample at a time, gives NAME_rays's rays. */
static void scalar_matches_batch(ray_fn one, rays_fn many)
{
    enum { N = 300 };
    double s[N * LENS_CAMERA_SAMPLE], r[N * LENS_CAMERA_RAY];
    uint64_t st = 7;
    for (int k = 0; k < N * LENS_CAMERA_SAMPLE; k++) s[k] = splitmix_uniform(&st);
    for (int k = 0; k < N; k++) s[k * LENS_CAMERA_SAMPLE + 2] = GLASS_D_LINE;
    size_t passed = many(N, s, r), passed1 = 0;
    for (int k = 0; k < N; k++) {
        const double *q = s + k * LENS_CAMERA_SAMPLE, *ray = r + k * LENS_CAMERA_RAY;
        double org[3], dir[3], w = one(q[0], q[1], q[2], q[3], q[4], org, dir);
        assert_true(fabs(w - ray[6]) <= 1e-12 * fabs(w));
        if (w > 0) {
            passed1++;
            for (int j = 0; j < 3; j++)
                assert_true(fabs(org[j] - ray[j]) < 1e-9 && fabs(dir[j] - ray[3 + j]) < 1e-12);
        }
    }
    assert_int_equal(passed, passed1);
    assert_true(passed > N / 2);
}

static void test_module(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse("camera a.lens\nresolution 6 4\nmode grey\ntransmittance on\n"
                                 "plane 0 0 1000 0 0 -1 emit 1\n", "t.scene", &s, &err), 0);
    render_effects e;
    assert_int_equal(render_effects_decide(&s, &lens, SW, SH, &e, &err), 0);
    double fit_s, rot = 0.3;
    poly_system *sys = render_fit(&lens, &e, 0, &fit_s, &err);
    assert_non_null(sys);
    char dir[] = "/tmp/camera-module-XXXXXX", src[128], so[128], cmd[512];
    assert_non_null(mkdtemp(dir));
    snprintf(src, sizeof src, "%s/cam.c", dir);
    snprintf(so, sizeof so, "%s/cam.so", dir);
    FILE *f = fopen(src, "w");
    assert_non_null(f);
    assert_int_equal(lens_camera_emit(f, &lens, sys, SW, SH, 6, rot, "dg", &err), 0);
    fclose(f);
    snprintf(cmd, sizeof cmd, "cc -std=c11 -O2 -Wall -Wextra -Werror -shared -fPIC -o %s %s -lm", so, src);
    assert_int_equal(system(cmd), 0);
    void *h = dlopen(so, RTLD_NOW);
    assert_non_null(h);
    ray_fn one = (ray_fn)dlsym(h, "dg_ray");
    rays_fn many = (rays_fn)dlsym(h, "dg_rays");
    assert_non_null(one);
    assert_non_null(many);
    scalar_matches_batch(one, many);
    double ma[W * H], va[W * H], mb[W * H], vb[W * H], m0[W * H], v0[W * H];
    weights(NULL, many, samples(), ma, va);
    lens_camera *c = lens_camera_new(&lens, sys, SW, SH, GLASS_D_LINE, GLASS_D_LINE, &err);
    assert_non_null(c);
    weights(c, NULL, samples(), m0, v0);
    assert_int_equal(lens_camera_set_blades(c, 6, rot, &err), 0);
    weights(c, NULL, samples(), mb, vb);
    assert_true(compare("module", ma, va, mb, vb) <= 1);
    /* the blades cut the light the test compares, far beyond its noise (a module
     * without them fails above); at f/2 other rims clip the axial beam too, so less
     * than the hexagon's 17% of the circle (test_blades: stopped down, 17%) */
    double share = centre_share(mb, m0);
    print_message("module and API with blades: %.4f of the round stop's light on the axis\n",
                  share);
    assert_true(share > 0.8 && share < 0.94);
    dlclose(h);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    assert_int_equal(system(cmd), 0);
    lens_camera_free(c);
    poly_free(sys);
    scene_free(&s);
    lens_free(&lens);
}

/* An aperture of six blades passes the hexagon inscribed in the stop's circle: behind a
 * uniform emitter, the pixels near the axis (where the stop is evenly filled) lose the
 * share of the circle outside it, 1 - (6 / 2 pi) sin(2 pi / 6) = 17.3%. */
static void test_blades(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    lens_err err = {{0}};
    /* stopped down, so that the stop alone limits the beam near the axis */
    assert_int_equal(render_lens_setup(&lens, NAN, 8, &err), 0);
    render_camera cam;
    render_lens_ctx *lc = render_lens_exact(&lens, SW, SH, &cam, &err);
    render_sampler smp;
    assert_int_equal(render_sampler_lens(&smp, &lens, GLASS_D_LINE, GLASS_D_LINE, hypot(18, 12), 0,
                                         &err), 0);
    double m0[W * H], v0[W * H], m6[W * H], v6[W * H];
    rendered(&cam, &smp, samples(), m0, v0);
    assert_int_equal(render_lens_set_blades(lc, 6, 0.3, &err), 0);
    rendered(&cam, &smp, samples(), m6, v6);
    double share = centre_share(m6, m0), expect = 6 / (2 * M_PI) * sin(2 * M_PI / 6);
    print_message("blades: %.4f of the round stop's light, hexagon/circle %.4f\n", share, expect);
    assert_true(fabs(share - expect) < 0.015);
    assert_int_equal(render_lens_set_blades(lc, 2, 0, &err), -1);
    render_sampler_free(&smp);
    render_lens_free(lc);
    lens_free(&lens);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_api_exact),
        cmocka_unit_test(test_module),
        cmocka_unit_test(test_blades),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
