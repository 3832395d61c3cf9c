/* Surface intersection and refraction against closed forms and independent references. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "sparselens/intersect.h"
#include "sparselens/refract.h"

static lens_surface surf(double radius, double conic, double sd)
{
    lens_surface s;
    memset(&s, 0, sizeof s);
    s.radius = radius;
    s.conic = conic;
    s.semi_diameter = sd;
    s.medium = glass_air();
    return s;
}

static uint64_t lcg(uint64_t *st)
{
    *st = *st * 6364136223846793005ULL + 1442695040888963407ULL;
    return *st >> 11;
}
static double unif(uint64_t *st) { return (double)lcg(st) / 9007199254740992.0; }

static void unit(double d[3])
{
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    d[0] /= l, d[1] /= l, d[2] /= l;
}

/* Random rays towards a sphere: the hit lies on the sphere, on the ray, on the vertex
 * half, and the normal points from the hit away from the centre of curvature... towards
 * object space. */
static void test_sphere_random(void **state)
{
    (void)state;
    uint64_t st = 1;
    const double radii[] = {20.0, -20.0, 85.0, -7.5};
    for (int k = 0; k < 4; k++) {
        double R = radii[k], sd = 0.95 * fabs(R) < 15 ? 0.95 * fabs(R) : 15;
        lens_surface s = surf(R, 0, sd);
        double vz = 3.0;
        for (int i = 0; i < 2000; i++) {
            double o[3] = {(unif(&st) - 0.5) * 20, (unif(&st) - 0.5) * 20, vz - 10 - unif(&st)};
            double d[3] = {(unif(&st) - 0.5), (unif(&st) - 0.5), 1};
            unit(d);
            double t, p[3], n[3];
            isect_status is = intersect_surface(&s, vz, o, d, INFINITY, &t, p, n);
            if (is != ISECT_HIT)
                continue;
            double cz = vz + R;
            double r2 = p[0] * p[0] + p[1] * p[1] + (p[2] - cz) * (p[2] - cz);
            assert_true(fabs(sqrt(r2) - fabs(R)) < 1e-11 * fabs(R));
            for (int j = 0; j < 3; j++)
                assert_true(fabs(o[j] + t * d[j] - p[j]) < 1e-11);
            /* vertex half: between the vertex plane and the centre plane */
            assert_true((p[2] - vz) / R <= 1.0 + 1e-12);
            /* normal = (p - centre)/R pointing to object space */
            double nn[3] = {(p[0]) / R, (p[1]) / R, (p[2] - cz) / R};
            for (int j = 0; j < 3; j++)
                assert_true(fabs(n[j] - nn[j]) < 1e-12);
        }
    }
}

/* A flat-ish surface with |R| = 1e6: the sag h^2/(2R) + h^4/(8R^3) to 1e-13 mm (a
 * cancelling R - sqrt(R^2 - h^2) is off by ~1e-10 mm here). */
static void test_flat_large_radius(void **state)
{
    (void)state;
    for (int sign = -1; sign <= 1; sign += 2) {
        double R = sign * 1e6;
        lens_surface s = surf(R, 0, 20);
        double h = 10.0;
        double o[3] = {h, 0, -5}, d[3] = {0, 0, 1};
        double t, p[3], n[3];
        assert_int_equal(intersect_surface(&s, 0, o, d, 400, &t, p, n), ISECT_HIT);
        double expect = h * h / (2 * R) + h * h * h * h / (8 * R * R * R);
        assert_true(fabs(p[2] - expect) < 1e-13);
        /* and from the other side, travelling -z */
        double o2[3] = {h, 0, 5}, d2[3] = {0, 0, -1};
        assert_int_equal(intersect_surface(&s, 0, o2, d2, 400, &t, p, n), ISECT_HIT);
        assert_true(fabs(p[2] - expect) < 1e-13);
        /* the normal tilts by h/R */
        assert_true(fabs(n[0] - h / R) < 1e-15);
    }
    lens_surface flat = surf(INFINITY, 0, 20);
    double o[3] = {3, 4, -7}, d[3] = {0.3, 0.1, 1};
    unit(d);
    double t, p[3], n[3];
    assert_int_equal(intersect_surface(&flat, 2.0, o, d, 400, &t, p, n), ISECT_HIT);
    assert_true(fabs(p[2] - 2.0) < 1e-15);
    assert_true(fabs(t - 9.0 / d[2]) < 1e-13);
    assert_true(n[0] == 0 && n[1] == 0 && n[2] == -1);
}

/* A paraboloid (k = -1) hit by rays parallel to the axis: z = c h^2 / 2 exactly; a
 * hyperboloid keeps to its vertex branch. */
static void test_conic(void **state)
{
    (void)state;
    lens_surface par = surf(10.0, -1.0, 30);
    for (double h = 0; h < 30; h += 2.9) {
        double o[3] = {0, h, -50}, d[3] = {0, 0, 1}, t, p[3], n[3];
        assert_int_equal(intersect_surface(&par, 0, o, d, 900, &t, p, n), ISECT_HIT);
        assert_true(fabs(p[2] - h * h / 20.0) < 1e-12 * (1 + h * h));
        /* normal of z = h^2/(2R): (0, h/R, -1) normalised */
        double l = sqrt(h * h / 100.0 + 1);
        assert_true(fabs(n[1] - (h / 10.0) / l) < 1e-13 && fabs(n[2] + 1 / l) < 1e-13);
    }
    lens_surface hyp = surf(10.0, -3.0, 30);
    uint64_t st = 7;
    for (int i = 0; i < 1000; i++) {
        double o[3] = {(unif(&st) - 0.5) * 10, (unif(&st) - 0.5) * 10, -20};
        double d[3] = {(unif(&st) - 0.5), (unif(&st) - 0.5), 1}, t, p[3], n[3];
        unit(d);
        if (intersect_surface(&hyp, 0, o, d, INFINITY, &t, p, n) != ISECT_HIT)
            continue;
        double h2 = p[0] * p[0] + p[1] * p[1];
        double sag = 0.1 * h2 / (1 + sqrt(1 + 2 * 0.01 * h2)); /* (1+k) = -2 */
        assert_true(fabs(p[2] - sag) < 1e-11 * (1 + fabs(sag)));
    }
}

/* Independent sag for the asphere reference. */
static double ref_sag(double c, double k, const double *a, double h2)
{
    double z = c * h2 / (1 + sqrt(1 - (1 + k) * c * c * h2));
    double hp = h2 * h2;
    for (int i = 0; i < 5; i++, hp *= h2)
        z += a[i] * hp;
    return z;
}

static void test_asphere_vs_bisection(void **state)
{
    (void)state;
    lens_surface s = surf(-30.0, -0.7, 12);
    double a[5] = {2e-5, -3e-8, 1e-10, 0, 0};
    memcpy(s.asphere, a, sizeof a);
    double c = 1 / -30.0;
    uint64_t st = 3;
    int hits = 0;
    for (int i = 0; i < 2000; i++) {
        double o[3] = {(unif(&st) - 0.5) * 20, (unif(&st) - 0.5) * 20, 5 + 10 * unif(&st)};
        double d[3] = {(unif(&st) - 0.5) * 0.8, (unif(&st) - 0.5) * 0.8, -1};
        unit(d);
        double t, p[3], n[3];
        isect_status is = intersect_surface(&s, 0, o, d, 144, &t, p, n);
        /* reference: bisection of z(t) - sag(h(t)) between the start and a far point,
         * after a scan for the first sign change. */
        double tlo = 0, thi = NAN, glo = o[2] - ref_sag(c, s.conic, a, o[0] * o[0] + o[1] * o[1]);
        for (int j = 1; j <= 4000; j++) {
            double tt = j * 0.01;
            double x = o[0] + tt * d[0], y = o[1] + tt * d[1];
            double g = o[2] + tt * d[2] - ref_sag(c, s.conic, a, x * x + y * y);
            if (isnan(g))
                break;
            if ((g < 0) != (glo < 0)) {
                thi = tt;
                break;
            }
            tlo = tt;
        }
        if (isnan(thi)) {
            assert_int_not_equal(is, ISECT_HIT);
            continue;
        }
        for (int j = 0; j < 200; j++) {
            double tm = 0.5 * (tlo + thi);
            double x = o[0] + tm * d[0], y = o[1] + tm * d[1];
            double g = o[2] + tm * d[2] - ref_sag(c, s.conic, a, x * x + y * y);
            if ((g < 0) == (glo < 0))
                tlo = tm;
            else
                thi = tm;
        }
        double x = o[0] + tlo * d[0], y = o[1] + tlo * d[1];
        if (x * x + y * y > 144 * (1 - 1e-9)) {
            assert_int_not_equal(is, ISECT_HIT);
            continue;
        }
        assert_int_equal(is, ISECT_HIT);
        assert_true(fabs(t - tlo) < 1e-9);
        assert_true(fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1) < 1e-14);
        hits++;
    }
    assert_true(hits > 500);
    /* a ray parallel to the axis and a ray along it */
    double o[3] = {5, 0, 10}, d[3] = {0, 0, -1}, t, p[3], n[3];
    assert_int_equal(intersect_surface(&s, 0, o, d, 144, &t, p, n), ISECT_HIT);
    assert_true(fabs(p[2] - ref_sag(c, s.conic, a, 25)) < 1e-14);
    double o0[3] = {0, 0, 10};
    assert_int_equal(intersect_surface(&s, 0, o0, d, 144, &t, p, n), ISECT_HIT);
    assert_true(fabs(t - 10) < 1e-14 && n[2] == -1);
}

static void test_miss_and_clip(void **state)
{
    (void)state;
    lens_surface s = surf(10.0, 0, 8);
    double t, p[3], n[3];
    double o[3] = {0, 50, -5}, d[3] = {1, 0, 0};
    assert_int_equal(intersect_surface(&s, 0, o, d, 64, &t, p, n), ISECT_MISS);
    double o2[3] = {9, 0, -5}, d2[3] = {0, 0, 1};
    assert_int_equal(intersect_surface(&s, 0, o2, d2, 64, &t, p, n), ISECT_OUTSIDE);
    assert_int_equal(intersect_surface(&s, 0, o2, d2, INFINITY, &t, p, n), ISECT_HIT);
    /* at the very edge of the clear aperture: inside */
    double o3[3] = {8, 0, -5};
    assert_int_equal(intersect_surface(&s, 0, o3, d2, 64, &t, p, n), ISECT_HIT);
    /* beyond the hemisphere of a sphere: no vertex-branch hit for a ray parallel to the
     * axis outside |R| */
    double o4[3] = {10.5, 0, -5};
    assert_int_equal(intersect_surface(&s, 0, o4, d2, INFINITY, &t, p, n), ISECT_MISS);
    /* a ray that starts behind the surface and moves away: no hit */
    double o5[3] = {0, 0, 5};
    assert_int_equal(intersect_surface(&s, 0, o5, d2, INFINITY, &t, p, n), ISECT_MISS);
}

static void test_fresnel(void **state)
{
    (void)state;
    uint64_t st = 11;
    for (int i = 0; i < 1000; i++) {
        double n1 = 1 + unif(&st), n2 = 1 + unif(&st);
        double sini = unif(&st) * (n1 > n2 ? n2 / n1 : 1.0);
        double sint = n1 * sini / n2;
        double ci = sqrt(1 - sini * sini), ct = sqrt(1 - sint * sint), R, T;
        fresnel_unpolarised(n1, n2, ci, ct, &R, &T);
        assert_true(fabs(R + T - 1) < 1e-13);
        assert_true(R >= 0 && T >= 0 && T <= 1);
    }
    double R, T, n1 = 1.0, n2 = 1.5;
    fresnel_unpolarised(n1, n2, 1, 1, &R, &T);
    double r0 = (n1 - n2) / (n1 + n2);
    assert_true(fabs(R - r0 * r0) < 1e-15 && fabs(T - (1 - r0 * r0)) < 1e-15);
    /* Brewster: p reflectance vanishes, R = rs^2 / 2 */
    double tb = atan(n2 / n1), ci = cos(tb), ct = cos(M_PI / 2 - tb);
    fresnel_unpolarised(n1, n2, ci, ct, &R, &T);
    double rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
    assert_true(fabs(R - 0.5 * rs * rs) < 1e-15);
    /* grazing incidence transmits nothing */
    fresnel_unpolarised(n1, n2, 0, sqrt(1 - 1 / (n2 * n2)), &R, &T);
    assert_true(fabs(R - 1) < 1e-15 && T == 0);
}

static void test_snell_and_tir(void **state)
{
    (void)state;
    uint64_t st = 5;
    for (int i = 0; i < 1000; i++) {
        double nrm[3] = {unif(&st) - 0.5, unif(&st) - 0.5, -1};
        double d[3] = {unif(&st) - 0.5, unif(&st) - 0.5, 1};
        unit(nrm), unit(d);
        double n1 = 1 + unif(&st), n2 = 1 + unif(&st), out[3], T;
        double ci = fabs(d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2]);
        double si = sqrt(1 - ci * ci);
        int rc = refract(d, nrm, n1, n2, out, &T);
        if (n1 * si > n2 * (1 + 1e-12)) {
            assert_int_equal(rc, -1); /* total internal reflection */
            continue;
        }
        if (n1 * si > n2 * (1 - 1e-12))
            continue;
        assert_int_equal(rc, 0);
        double ct = fabs(out[0] * nrm[0] + out[1] * nrm[1] + out[2] * nrm[2]);
        double sn = sqrt(fmax(0, 1 - ct * ct));
        assert_true(fabs(n1 * si - n2 * sn) < 1e-12);
        /* coplanar with d and the normal, and still going forward */
        double cx[3] = {d[1] * nrm[2] - d[2] * nrm[1], d[2] * nrm[0] - d[0] * nrm[2],
                        d[0] * nrm[1] - d[1] * nrm[0]};
        assert_true(fabs(cx[0] * out[0] + cx[1] * out[1] + cx[2] * out[2]) < 1e-12);
        assert_true(out[2] > 0);
        assert_true(T > 0 && T <= 1);
    }
    /* glass to air at 45 degrees with n = 1.5: past the critical angle 41.8 deg */
    double d[3] = {sqrt(0.5), 0, sqrt(0.5)}, nrm[3] = {0, 0, 1}, out[3], T = -1;
    assert_int_equal(refract(d, nrm, 1.5, 1.0, out, &T), -1);
    assert_true(T == -1);
    /* at 40 degrees it passes */
    double d2[3] = {sin(40 * M_PI / 180), 0, cos(40 * M_PI / 180)};
    assert_int_equal(refract(d2, nrm, 1.5, 1.0, out, &T), 0);
    assert_true(fabs(out[0] - 1.5 * sin(40 * M_PI / 180)) < 1e-14);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_random),  cmocka_unit_test(test_flat_large_radius),
        cmocka_unit_test(test_conic),          cmocka_unit_test(test_asphere_vs_bisection),
        cmocka_unit_test(test_miss_and_clip),  cmocka_unit_test(test_fresnel),
        cmocka_unit_test(test_snell_and_tir),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
