/* Object-space ray aiming in two steps (aim_object_prepare, aim_object_to) and the bound
 * on the traces one ray may take: the bound must never cost a ray that can be aimed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/aim.h"
#include "sparselens/trace.h"
#include "trace/trace_core.h" /* trace_path: to the stop with the surfaces unclipped, as aiming traces */

static int load(const char *name, lens_t *L)
{
    char path[256];
    snprintf(path, sizeof path, "lenses/%s.lens", name);
    lens_err err;
    return lens_load(path, NULL, L, &err);
}

/* Stop points on 12 rings out to 1.2 times the stop radius: the outer rings and, on the
 * wide-open lenses below, part of the inner ones are points no ray reaches. */
enum { RINGS = 12, SPOKES = 16 };

/* For each field: with aim_object_to's bound and with none, the same stop points are
 * aimed and the rays are equal bit for bit; some points fail (so the bound is used),
 * and every aimed ray crosses the stop where asked. */
static void check_lens(const char *name, const double *fields, int nf, int *failed_total)
{
    lens_t L;
    assert_int_equal(load(name, &L), 0);
    double n[64];
    lens_err e;
    assert_true(L.nsurf <= 64);
    assert_int_equal(lens_indices(&L, GLASS_D_LINE, n, &e), 0);
    double stop = L.surf[L.stop].semi_diameter;
    for (int f = 0; f < nf; f++) {
        double a = fields[f] * M_PI / 180, dir[3] = {0, sin(a), cos(a)};
        aim_object_start st;
        assert_int_equal(aim_object_prepare(&L, n, dir, NULL, &st), 0);
        for (int i = 1; i <= RINGS; i++)
            for (int k = 0; k < SPOKES; k++) {
                double rho = 1.2 * stop * i / RINGS, phi = 2 * M_PI * k / SPOKES;
                double sx = rho * cos(phi), sy = rho * sin(phi);
                lens_ray bounded, free_;
                int rb = aim_object_to(&st, sx, sy, &bounded);
                int rf = aim_object_to_within(&st, sx, sy, 0, &free_);
                assert_int_equal(rb, rf);
                if (rb != 0) {
                    ++*failed_total;
                    continue;
                }
                assert_memory_equal(&bounded, &free_, sizeof bounded);
                lens_ray t = bounded;
                assert_int_equal(trace_path(&L, n, &t, 0, L.stop, 0, 0).status, TRACE_PASSED);
                assert_true(hypot(t.o[0] - sx, t.o[1] - sy) < 1e-8 * (1 + stop));
            }
    }
    lens_free(&L);
}

static void test_bound_loses_no_ray(void **state)
{
    (void)state;
    setenv("SPARSELENS_GLASS_CATALOG", "lenses/glass.catalog", 1);
    int failed = 0;
    const double fisheye[] = {0, 68, 97}, tele[] = {0, 2.5};
    check_lens("fisheye-ii", fisheye, 3, &failed);
    check_lens("kreitzer-tele", tele, 2, &failed);
    assert_true(failed > 0); /* unreachable points were asked for */
}

/* A very small bound gives up on points that can be aimed: the bound is what decides,
 * so the test above would see a bound set too low. */
static void test_tiny_bound_gives_up(void **state)
{
    (void)state;
    setenv("SPARSELENS_GLASS_CATALOG", "lenses/glass.catalog", 1);
    lens_t L;
    assert_int_equal(load("fisheye-ii", &L), 0);
    double n[64];
    lens_err e;
    assert_int_equal(lens_indices(&L, GLASS_D_LINE, n, &e), 0);
    double dir[3] = {0, 0, 1};
    aim_object_start st;
    assert_int_equal(aim_object_prepare(&L, n, dir, NULL, &st), 0);
    lens_ray r;
    double sx = 0.5 * L.surf[L.stop].semi_diameter;
    assert_int_equal(aim_object_to(&st, sx, 0, &r), 0);
    assert_int_equal(aim_object_to_within(&st, sx, 0, 3, &r), -1);
    lens_free(&L);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bound_loses_no_ray),
        cmocka_unit_test(test_tiny_bound_gives_up),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
