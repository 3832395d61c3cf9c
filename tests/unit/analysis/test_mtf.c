/* Diffraction and geometric MTF against closed forms: the FFT against a direct sum, a
 * perfect circular pupil against 2/pi (acos v - v sqrt(1 - v^2)), a lens that is
 * perfect on its axis (a plano-hyperbolic singlet) traced for real, and defocus (its
 * wavefront RMS, and the geometric MTF of a uniform blur disc, 2 J1(x)/x). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fixture_lenses.h"
#include "sparselens/fft.h"
#include "sparselens/mtf.h"
#include "sparselens/paraxial.h"
#include "sparselens/ray_bundle.h"

static void fft_matches_the_direct_sum(void **state)
{
    (void)state;
    enum { N = 16 };
    double z[2 * N], ref[2 * N];
    for (int i = 0; i < N; i++)
        z[2 * i] = sin(1.3 * i * i + 0.2), z[2 * i + 1] = cos(0.7 * i);
    for (int k = 0; k < N; k++) {
        ref[2 * k] = ref[2 * k + 1] = 0;
        for (int j = 0; j < N; j++) {
            double a = -2 * M_PI * k * j / N;
            ref[2 * k] += z[2 * j] * cos(a) - z[2 * j + 1] * sin(a);
            ref[2 * k + 1] += z[2 * j] * sin(a) + z[2 * j + 1] * cos(a);
        }
    }
    fft_1d(z, N, 1, -1);
    for (int i = 0; i < 2 * N; i++)
        assert_true(fabs(z[i] - ref[i]) < 1e-12);
}

/* Largest |MTF - closed form| of a wavefront over v in [0, 1), both directions. */
static double limit_error(const wavefront *wf, double nu_c)
{
    int m;
    double *otf = mtf_otf(wf, &m), worst = 0;
    assert_non_null(otf);
    for (int k = 0; k <= 50; k++) {
        double v = 0.98 * k / 50, z[2];
        for (int dir = 0; dir < 2; dir++) {
            mtf_otf_at(wf, otf, m, dir, v * nu_c, z);
            worst = fmax(worst, fabs(hypot(z[0], z[1]) - mtf_diffraction_limit(v)));
        }
    }
    free(otf);
    return worst;
}

static void perfect_pupil_gives_the_closed_form(void **state)
{
    (void)state;
    int n = 64;
    double *amp = calloc((size_t)n * n, sizeof *amp), *opd = calloc((size_t)n * n, sizeof *opd);
    assert_non_null(amp);
    assert_non_null(opd);
    /* the disc, each cell weighted by its share inside (64 x 64 samples) */
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int in = 0;
            for (int a = 0; a < 64; a++)
                for (int b = 0; b < 64; b++) {
                    double x = -1 + (i + (a + 0.5) / 64) * 2.0 / n, y = -1 + (j + (b + 0.5) / 64) * 2.0 / n;
                    in += x * x + y * y <= 1;
                }
            amp[j * n + i] = in / 4096.0;
        }
    wavefront wf = {.n = n, .lambda = 0.55, .amp = amp, .opd = opd, .scale = {0.1, 0.1}, .n_image = 1};
    double err = limit_error(&wf, 2 * 0.1 / 0.55e-3);
    printf("perfect pupil: largest |MTF - closed form| %.2g\n", err);
    assert_true(err < 2e-3);
    free(amp);
    free(opd);
}

/* Plano-hyperbolic singlet: flat face to the object, rear face a hyperboloid of
 * eccentricity n (k = -n^2), so collimated light meets in one point behind it: the
 * paraxial focus, 100 mm behind the rear vertex. Stop 5 mm: f/10. */
static void hyperbolic(lens_t *l)
{
    static const fixture_row rows[] = {{0, 0, 0, 0, 5, 1}, {0, 5, 1.5, 0, 10, 0}, {-50, 100, 0, 0, 10, 0}};
    assert_int_equal(fixture_build(l, "hyperbolic", rows, 3), 0);
    l->surf[2].conic = -2.25;
    lens_err err;
    assert_int_equal(lens_finish(l, &err), 0);
}

static void perfect_lens_traced_gives_the_closed_form(void **state)
{
    (void)state;
    lens_t lens;
    hyperbolic(&lens);
    imaging im = {.lens = &lens, .object_distance = INFINITY};
    lens_err err;
    double chief[4];
    assert_int_equal(bundle_chief(&im, 0, GLASS_D_LINE, chief, &err), 0);
    for (int method = 0; method < 2; method++) {
        wavefront wf;
        assert_int_equal(wavefront_trace(&im, 0, GLASS_D_LINE, 64, (wavefront_method)method, chief, &wf, &err), 0);
        double rms = wavefront_rms(&wf) / (GLASS_D_LINE * 1e-3);
        /* the beam's numerical aperture: sin U' of the marginal ray, 5 / sqrt(100^2 + 5^2)
         * to first order; the fitted slope is an average over the pupil */
        double na = fabs(wf.scale[1]), e = limit_error(&wf, 2 * na / (GLASS_D_LINE * 1e-3));
        printf("hyperbolic singlet (%s): rms %.2g waves, NA %.6f, largest |MTF - closed form| %.2g\n",
               method ? "rays" : "path", rms, na, e);
        assert_true(rms < 1e-4);
        assert_true(fabs(na - 0.05) < 2e-4);
        assert_true(e < 2.5e-3);
        wavefront_free(&wf);
    }
    lens_free(&lens);
}

/* Focus inside glass: collimated light from air meets in one point inside a medium of
 * index n behind an ellipsoid of eccentricity 1/n (k = -1/n^2), at n R / (n - 1) from
 * its vertex. The stop (20 mm: f/3.75, where the map from stop to direction is far
 * enough from linear that a least-squares slope misses the marginal ray's NA by 0.6%)
 * sits on the vertex plane. The diffraction limit's cutoff
 * is 2 n sin U' / lambda, with the wavelength in vacuum: inside the medium the wave is
 * shorter, and the MTF reaches higher frequencies than the same cone in air would. */
static void focus_in_a_medium_gives_the_closed_form(void **state)
{
    (void)state;
    const double n = 1.5, R = 50, h = 20, F = n * R / (n - 1), k = -1 / (n * n);
    static const fixture_row rows[] = {{0, 0, 0, 0, 20, 1}, {50, 150, 1.5, 0, 25, 0}};
    lens_t lens;
    assert_int_equal(fixture_build(&lens, "ellipsoid", rows, 2), 0);
    lens.surf[1].conic = k;
    lens_err err;
    assert_int_equal(lens_finish(&lens, &err), 0);
    double c = 1 / R, sag = c * h * h / (1 + sqrt(1 - (1 + k) * c * c * h * h));
    double na = n * h / sqrt(h * h + (F - sag) * (F - sag)), nu_c = 2 * na / (GLASS_D_LINE * 1e-3);
    imaging im = {.lens = &lens, .object_distance = INFINITY};
    double chief[4];
    assert_int_equal(bundle_chief(&im, 0, GLASS_D_LINE, chief, &err), 0);
    for (int method = 0; method < 2; method++) {
        wavefront wf;
        assert_int_equal(wavefront_trace(&im, 0, GLASS_D_LINE, 64, (wavefront_method)method, chief, &wf, &err), 0);
        double rms = wavefront_rms(&wf) / (GLASS_D_LINE * 1e-3), e = limit_error(&wf, nu_c);
        printf("ellipsoid into n = %g (%s): rms %.2g waves, n' %.4f, NA %.6f (marginal ray %.6f), "
               "largest |MTF - closed form| %.2g\n",
               n, method ? "rays" : "path", rms, wf.n_image, wf.n_image * fabs(wf.scale[1]), na, e);
        assert_true(fabs(wf.n_image - n) < 1e-12);
        assert_true(rms < 1e-3);
        assert_true(fabs(wf.n_image * fabs(wf.scale[1]) / na - 1) < 2e-3);
        assert_true(e < 3e-3);
        wavefront_free(&wf);
    }
    lens_free(&lens);
}

/* Moving the sensor by dz adds the defocus wavefront dz (1 - cos U) (n' = 1); its RMS
 * over a uniform disc of sin U <= NA is dz NA^2 / (4 sqrt 3) to leading order. The
 * geometric blur is a uniform disc of radius dz tan U, whose MTF is 2 J1(x) / x,
 * x = 2 pi nu r. */
static void defocus_closed_forms(void **state)
{
    (void)state;
    lens_t lens;
    hyperbolic(&lens);
    imaging im = {.lens = &lens, .object_distance = INFINITY};
    lens_err err;
    double chief[4], dz = 0.2;
    assert_int_equal(bundle_chief(&im, 0, GLASS_D_LINE, chief, &err), 0);
    for (int method = 0; method < 2; method++) {
        wavefront wf;
        assert_int_equal(wavefront_trace(&im, 0, GLASS_D_LINE, 64, (wavefront_method)method, chief, &wf, &err), 0);
        double na = fabs(wf.scale[1]);
        assert_int_equal(wavefront_refocus(&wf, dz), 0);
        double rms = wavefront_rms(&wf), expect = dz * na * na / (4 * sqrt(3));
        printf("defocus %g mm (%s): rms %.6g mm, closed form %.6g mm\n", dz, method ? "rays" : "path", rms, expect);
        assert_true(fabs(rms / expect - 1) < 5e-3);
        /* a defocus W = W020 rho^2 (rms W020 / sqrt 12) over a uniform disc has the peak
         * |int exp(i k W020 t) dt|^2 over t = rho^2 in [0, 1]: Strehl sinc^2(k W020 / 2) */
        double half = M_PI / (GLASS_D_LINE * 1e-3) * rms * sqrt(12), strehl = pow(sin(half) / half, 2);
        printf("  Strehl %.5f, closed form %.5f\n", mtf_strehl(&wf), strehl);
        assert_true(fabs(mtf_strehl(&wf) - strehl) < 2e-3);
        const wavefront *w = &wf;
        double r = dz * na / sqrt(1 - na * na), worst = 0;
        for (int k = 1; k <= 10; k++) {
            double nu = 0.38 * k / r / (2 * M_PI) * 10 / 10, x = 2 * M_PI * nu * r;
            worst = fmax(worst, fabs(mtf_geometric(&w, 1, 1, nu, dz) - fabs(2 * j1(x) / x)));
        }
        printf("  geometric MTF against 2 J1(x)/x: largest difference %.2g\n", worst);
        assert_true(worst < 0.01);
        wavefront_free(&wf);
    }
    lens_free(&lens);
}

/* The two wavefronts of a real, aberrated lens agree: optical path lengths, and the
 * integral of the ray errors (what a fitted system offers). */
static void path_and_rays_agree(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    imaging im = {.lens = &lens, .object_distance = INFINITY};
    lens_err err;
    for (int k = 0; k < 2; k++) {
        double field = 12.0 * k, chief[4];
        assert_int_equal(bundle_chief(&im, field, GLASS_D_LINE, chief, &err), 0);
        wavefront a, b;
        assert_int_equal(wavefront_trace(&im, field, GLASS_D_LINE, 48, WAVEFRONT_PATH, chief, &a, &err), 0);
        assert_int_equal(wavefront_trace(&im, field, GLASS_D_LINE, 48, WAVEFRONT_RAYS, chief, &b, &err), 0);
        assert_int_equal(a.passed, b.passed);
        double d = 0, w = 0, lam = GLASS_D_LINE * 1e-3;
        for (int c = 0; c < 48 * 48; c++)
            if (a.amp[c] > 0)
                d += a.amp[c] * (a.opd[c] - b.opd[c]) * (a.opd[c] - b.opd[c]), w += a.amp[c];
        d = sqrt(d / w) / lam;
        printf("field %g: wavefront rms %.4f waves (path) %.4f (rays), rms difference %.2g waves\n", field,
               wavefront_rms(&a) / lam, wavefront_rms(&b) / lam, d);
        assert_true(wavefront_rms(&a) / lam > 0.1); /* a real aberration to agree on */
        assert_true(d < 0.002);
        wavefront_free(&a);
        wavefront_free(&b);
    }
    lens_free(&lens);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fft_matches_the_direct_sum),
        cmocka_unit_test(perfect_pupil_gives_the_closed_form),
        cmocka_unit_test(perfect_lens_traced_gives_the_closed_form),
        cmocka_unit_test(focus_in_a_medium_gives_the_closed_form),
        cmocka_unit_test(defocus_closed_forms),
        cmocka_unit_test(path_and_rays_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
