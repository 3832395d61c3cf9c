/* Field curves, focal shift and ray fans against closed forms: the Seidel field
 * curvatures of a thin lens with its stop at the lens, the longitudinal colour of a
 * thin singlet from its Abbe number, and the symmetries of ray fans. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "fixture_lenses.h"
#include "sparselens/field_run.h"
#include "sparselens/ray_bundle.h"
#include "sparselens/ray_fan.h"

/* A thin equiconvex singlet, f = 100 mm at n = 1.5 (r = +-100, 0.1 mm thick), the stop
 * on its front face, the sensor at its paraxial focus. vd 0: no dispersion. */
static void thin_singlet(lens_t *l, double nd, double vd)
{
    assert_int_equal(fixture_singlet(l, 100, -100, 0.1, nd, vd, 2, 100), 0);
    l->surf[1].thickness = fixture_bfl(l);
    lens_err err;
    assert_int_equal(lens_finish(l, &err), 0);
}

/* Third order, stop at a thin lens, object at infinity, image height h, n' = 1:
 * sagittal focus -h^2 (n + 1) / (2 n f), tangential -h^2 (3 n + 1) / (2 n f),
 * Petzval -h^2 / (2 n f) (towards the lens). */
static void thin_lens_field_curvature_is_seidel(void **state)
{
    (void)state;
    const double n = 1.5;
    lens_t lens;
    thin_singlet(&lens, n, 0);
    double f = fixture_efl(&lens);
    imaging im = {.lens = &lens, .object_distance = INFINITY};
    lens_err err;
    for (int k = 1; k <= 2; k++) {
        double theta = 1.5 * k, h = f * tan(theta * M_PI / 180);
        field_focus ff;
        assert_int_equal(field_focus_trace(&im, theta, GLASS_D_LINE, 0.01, &ff, &err), 0);
        double s = -h * h * (n + 1) / (2 * n * f), t = -h * h * (3 * n + 1) / (2 * n * f);
        double p = 0.5 * (3 * ff.z_sag - ff.z_tan), pe = -h * h / (2 * n * f);
        printf("field %g deg: sagittal %.6f (Seidel %.6f), tangential %.6f (%.6f), Petzval %.6f (%.6f) mm\n",
               theta, ff.z_sag, s, ff.z_tan, t, p, pe);
        assert_true(fabs(ff.z_sag / s - 1) < 0.01);
        assert_true(fabs(ff.z_tan / t - 1) < 0.01);
        assert_true(fabs(p / pe - 1) < 0.01);
    }
    lens_free(&lens);
}

/* A thin singlet's focal length goes as 1 / (n - 1): from the F to the C line its focus
 * moves by f (nF - nC) (nd - 1) / ((nF - 1)(nC - 1)), which is f / Vd to first order. */
static void thin_singlet_colour_is_f_over_v(void **state)
{
    (void)state;
    const double nd = 1.5168, vd = 64.17;
    lens_t lens;
    thin_singlet(&lens, nd, vd);
    double f = fixture_efl(&lens);
    imaging im = {.lens = &lens, .object_distance = INFINITY};
    lens_err err;
    double lam[2] = {GLASS_F_LINE, GLASS_C_LINE}, shift[2], seconds = 0;
    assert_int_equal(field_focal_shift(&im, lam, 2, GLASS_D_LINE, 0.01, shift, &seconds, &err), 0);
    double nF = glass_index_unchecked(&lens.surf[0].medium, GLASS_F_LINE);
    double nC = glass_index_unchecked(&lens.surf[0].medium, GLASS_C_LINE);
    double lca = shift[1] - shift[0], thin = f * (nF - nC) * (nd - 1) / ((nF - 1) * (nC - 1));
    printf("F to C focal shift %.6f mm: thin lens %.6f, f/V %.6f\n", lca, thin, f / vd);
    assert_true(fabs(lca / thin - 1) < 2e-3);
    assert_true(fabs(lca / (f / vd) - 1) < 0.01);
    lens_free(&lens);
}

/* On the axis the tangential and sagittal fans are the same odd curve; off axis the
 * sagittal fan's ex is odd and its ey even (the meridional plane is a mirror). */
static void fans_have_the_lens_symmetries(void **state)
{
    (void)state;
    lens_t lens;
    assert_int_equal(fixture_dgauss50(&lens), 0);
    imaging im = {.lens = &lens, .object_distance = INFINITY};
    lens_err err;
    for (int k = 0; k < 2; k++) {
        double field = 10.0 * k, chief[4];
        assert_int_equal(bundle_chief(&im, field, GLASS_D_LINE, chief, &err), 0);
        ray_fan fan;
        assert_int_equal(ray_fan_trace(&im, field, GLASS_D_LINE, chief, chief, 11, &fan, &err), 0);
        double big = 0;
        for (int i = 0; i < 11; i++) {
            const double *tx = fan.ex, *ty = fan.ey, *sx = fan.ex + 11, *sy = fan.ey + 11;
            int j = 10 - i;
            big = fmax(big, fabs(ty[i]));
            /* a ray vignetted on one side is vignetted on the other */
            assert_int_equal(isnan(sx[i]), isnan(sx[j]));
            if (isnan(sx[i]) || isnan(ty[i]) || isnan(ty[j]))
                continue;
            assert_true(fabs(sx[i] + sx[j]) < 1e-9);
            assert_true(fabs(sy[i] - sy[j]) < 1e-9);
            assert_true(fabs(tx[i]) < 1e-12);
            if (k == 0) {
                assert_true(fabs(ty[i] + ty[j]) < 1e-9);
                assert_true(fabs(ty[i] - sx[i]) < 1e-9);
            }
        }
        assert_true(fabs(fan.ey[5]) < 1e-12); /* the chief ray itself */
        assert_true(big > 1e-3);              /* and the lens is not perfect */
        ray_fan_free(&fan);
    }
    lens_free(&lens);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(thin_lens_field_curvature_is_seidel),
        cmocka_unit_test(thin_singlet_colour_is_f_over_v),
        cmocka_unit_test(fans_have_the_lens_symmetries),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
