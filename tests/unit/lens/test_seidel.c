/* Seidel sums against closed forms: a thin lens with the stop at it, object at infinity,
 * against Welford's thin-lens formulas in the shape factor B (Aberrations of Optical
 * Systems, ch. 7); and the plano-hyperbolic singlet, which images the axis perfectly, so
 * its spherical aberration (the sphere's and the conic's together) sums to zero. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>

#include "fixture_lenses.h"
#include "sparselens/glass.h"
#include "sparselens/seidel.h"

static void near_rel(double got, double want, double scale, double tol, const char *what)
{
    printf("  %-6s %.9g  closed form %.9g\n", what, got, want);
    assert_true(fabs(got - want) <= tol * scale);
}

/* Power K = (n - 1)(c1 - c2) = 0.01 (f = 100 mm), a 0.02 mm thick lens of 1 mm
 * semi-diameter behind a stop of 0.5 mm on its front vertex; the chief ray at 5 deg. */
static void thin_lens_gives_welfords_formulas(void **state)
{
    (void)state;
    const double n = 1.5, K = 0.01, field = 5, shapes[] = {-0.5, 0, 0.7, 2, 4};
    for (size_t k = 0; k < sizeof shapes / sizeof *shapes; k++) {
        double B = shapes[k], c1 = K / (n - 1) * (B + 1) / 2, c2 = K / (n - 1) * (B - 1) / 2;
        fixture_row rows[] = {{0, 0, 0, 0, 0.5, 1}, {1 / c1, 0.02, n, 0, 1, 0}, {1 / c2, 100, 0, 0, 1, 0}};
        lens_t lens;
        assert_int_equal(fixture_build(&lens, "thin", rows, 3), 0);
        seidel_data s;
        lens_err err;
        assert_int_equal(seidel_compute(&lens, GLASS_D_LINE, field, &s, &err), 0);
        double y = s.y0, H = s.H, C = -1; /* object at infinity */
        double SI = pow(y, 4) * pow(K, 3) / 4 *
                    (pow(n / (n - 1), 2) + (n + 2) / (n * pow(n - 1, 2)) * pow(B + 2 * (n * n - 1) / (n + 2) * C, 2) -
                     n / (n + 2) * C * C);
        double SII = -y * y * K * K * H / 2 * ((n + 1) / (n * (n - 1)) * B + (2 * n + 1) / n * C);
        printf("shape B = %g (y %g, H %g):\n", B, y, H);
        /* the lens's thickness, 2e-4 of its focal length, sets the tolerance */
        near_rel(s.sum[0], SI, fabs(SI), 2e-3, "S_I");
        near_rel(s.sum[1], SII, fabs(H * y * y * K * K), 2e-3, "S_II");
        near_rel(s.sum[2], H * H * K, H * H * K, 2e-3, "S_III");
        near_rel(s.sum[3], H * H * K / n, H * H * K, 1e-9, "S_IV");
        near_rel(s.sum[4], 0, H * H * K * fabs(H / (y * y * K)), 2e-3, "S_V");
        seidel_free(&s);
        lens_free(&lens);
    }
}

static void hyperbolic_singlet_has_no_spherical_aberration(void **state)
{
    (void)state;
    static const fixture_row rows[] = {{0, 0, 0, 0, 5, 1}, {0, 5, 1.5, 0, 10, 0}, {-50, 100, 0, 0, 10, 0}};
    lens_t lens;
    assert_int_equal(fixture_build(&lens, "hyperbolic", rows, 3), 0);
    lens_err err;
    lens.surf[2].conic = -2.25;
    assert_int_equal(lens_finish(&lens, &err), 0);
    seidel_data s;
    assert_int_equal(seidel_compute(&lens, GLASS_D_LINE, 1, &s, &err), 0);
    /* the sphere alone: A = n y c = -0.15, D = u' = -0.05, S_I = -A^2 y D = 0.005625 */
    printf("sphere's S_I %.9g, with the conic %.9g\n", s.surf[2].S[0] - 8 * (1 - 1.5) * 2.25e-6 * 625,
           s.surf[2].S[0]);
    assert_true(fabs(s.sum[0]) < 1e-12);
    lens.surf[2].conic = 0;
    seidel_free(&s);
    assert_int_equal(seidel_compute(&lens, GLASS_D_LINE, 1, &s, &err), 0);
    assert_true(fabs(s.sum[0] - 0.005625) < 1e-12);
    seidel_free(&s);
    lens_free(&lens);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(thin_lens_gives_welfords_formulas),
        cmocka_unit_test(hyperbolic_singlet_has_no_spherical_aberration),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
