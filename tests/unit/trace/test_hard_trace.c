/* Hard numerical cases of the exact tracer, each with its own expectation:
 *  - a fisheye past 180 degrees (lenses/fisheye-aspherical.lens, 181): chief rays past
 *    90 degrees from the axis stay representable in the outer-pupil frame, and tracing
 *    them back from the object side lands on the sensor point they started from;
 *  - the outer-pupil frame's singular points: the axis (exactly zero by symmetry) and
 *    the rim of a full hemisphere (normal along y: flagged, never a silent nan);
 *  - total internal reflection at a spherical, conic, aspheric surface, predicted from
 *    the sag slope in closed form (n sin(theta) > 1), and its absence in a flat plate
 *    even at grazing incidence, where the transmittance follows Fresnel's equations;
 *  - rays that touch a clear aperture's edge, one ulp-ish either side;
 *  - |R| equal to the semi-diameter (a hemisphere) and |R| = 1e6;
 *  - an asphere with large high-order coefficients, against a bisection reference;
 *  - wavelengths at the band edges of a catalog glass and of the nd/Vd model, and the
 *    lens's most dispersive glass (nd 2.003, Vd 19.3);
 *  - the batch tracer gives bit-identical output with 1 and 2 threads.
 * Lines "hard-metric LENS CASE VALUE" go to stdout for reports/robustness.md. */
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
#include "sparselens/intersect.h"
#include "sparselens/trace.h"

static int sanitized(void) { return getenv("SANITIZE") && *getenv("SANITIZE"); }

static void metric(const char *lens, const char *what, double v)
{
    printf("hard-metric %s %s %.3g\n", lens, what, v);
}

static void load(const char *path, lens_t *L)
{
    lens_err err;
    if (lens_load(path, NULL, L, &err) != 0)
        fail_msg("%s", err.msg);
}

/* Stop-plane x of the sensor ray (x, 0, u, 0), or nan if it does not reach the stop. */
static double stop_x(const lens_t *L, const double *n, double x, double u)
{
    lens_ray r;
    double in[4] = {x, 0, u, 0};
    ray_from_sensor(L, in, &r);
    trace_result res = trace_to_object(L, n, &r, L->stop);
    return res.status == TRACE_PASSED ? r.o[0] : NAN;
}

/* The chief ray from sensor point (x, 0): u with stop_x = 0, by a scan for a sign change
 * among rays that reach the stop, then bisection. Independent of the library's aiming. */
static int chief_u(const lens_t *L, const double *n, double x, double *u)
{
    const int steps = 4000;
    double pu = NAN, px = NAN;
    for (int i = 0; i <= steps; i++) {
        double uu = -4 + 8.0 * i / steps, sx = stop_x(L, n, x, uu);
        if (isfinite(sx) && isfinite(px) && (sx > 0) != (px > 0)) {
            double a = pu, b = uu, fa = px;
            for (int k = 0; k < 200 && b - a > 1e-16; k++) {
                double m = 0.5 * (a + b), fm = stop_x(L, n, x, m);
                if (!isfinite(fm))
                    return -1;
                if ((fm > 0) == (fa > 0))
                    a = m, fa = fm;
                else
                    b = m;
            }
            *u = 0.5 * (a + b);
            return 0;
        }
        pu = uu;
        px = sx;
    }
    return -1;
}

static void test_fisheye_past_180(void **state)
{
    (void)state;
    lens_t L;
    load("lenses/fisheye-aspherical.lens", &L);
    double n[64];
    lens_err e;
    assert_int_equal(lens_indices(&L, GLASS_D_LINE, n, &e), 0);
    double max_angle = 0, max_back = 0, max_frame = 0, prev_angle = 0, r90 = NAN;
    int nfield = sanitized() ? 22 : 44, beyond = 0; /* steps of 0.7 or 0.35 mm */
    for (int i = 1; i <= nfield; i++) {
        double x = 15.4 * i / nfield, u;
        if (chief_u(&L, n, x, &u) != 0)
            continue;
        double in[4] = {x, 0, u, 0}, out[4];
        trace_result res = trace_sample(&L, n, TRACE_TO_OUTER, in, out);
        if (res.status != TRACE_PASSED)
            continue; /* vignetted at the rim: the chief ray may clip */
        for (int k = 0; k < 4; k++)
            assert_true(isfinite(out[k]));
        assert_true(out[2] * out[2] + out[3] * out[3] < 1);
        lens_ray r;
        assert_int_equal(ray_from_outer(&L, out, &r), 0);
        double angle = acos(-r.d[2]) * 180 / M_PI;
        /* a fisheye's mapping from field angle to image height is monotonic */
        assert_true(angle > prev_angle);
        prev_angle = angle;
        if (angle > max_angle)
            max_angle = angle;
        if (angle > 90.5 && isnan(r90))
            r90 = x;
        beyond += angle > 90;
        /* the frame round trip */
        double again[4];
        ray_to_outer(&L, &r, again);
        for (int k = 0; k < 4; k++)
            max_frame = fmax(max_frame, fabs(again[k] - out[k]));
        /* back from the object side: reverse the outgoing ray and trace to the sensor */
        for (int k = 0; k < 3; k++)
            r.d[k] = -r.d[k];
        res = trace_to_sensor(&L, n, &r);
        assert_int_equal(res.status, TRACE_PASSED);
        max_back = fmax(max_back, hypot(r.o[0] - x, r.o[1]));
    }
    metric("fisheye-aspherical", "max_chief_angle_deg", max_angle);
    metric("fisheye-aspherical", "reverse_trace_err_mm", max_back);
    metric("fisheye-aspherical", "outer_frame_roundtrip", max_frame);
    metric("fisheye-aspherical", "sensor_radius_past_90.5deg_mm", r90);
    /* the lens is specified 181 degrees: within its image circle (15.4 mm) the chief
     * rays reach past 90.5 degrees from the axis */
    assert_true(max_angle > 90.5);
    assert_true(beyond >= 1);
    assert_true(max_back < 1e-8);
    assert_true(max_frame < 1e-12);
    /* on the axis the frame is regular and every output is zero by symmetry */
    double axis[4] = {0, 0, 0, 0}, out[4];
    trace_result res = trace_sample(&L, n, TRACE_TO_OUTER, axis, out);
    assert_int_equal(res.status, TRACE_PASSED);
    assert_true(out[0] == 0 && out[1] == 0 && out[2] == 0 && out[3] == 0);
    lens_free(&L);
}

/* A singlet whose front is a full hemisphere (R = semi-diameter, less 1e-12 mm: with
 * R = sd exactly, c^2 h^2 rounds to 1 + 2^-52 and lens_finish refuses the lens): the outer frame is
 * singular where the normal is (0, +-1, 0). Near it the frame round trip holds; at it
 * ray_from_outer refuses, and traced rays there are flagged. */
static void test_hemisphere_rim(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_singlet(&L, 10, INFINITY, 12, 1.5, 0, 10 - 1e-12, 30), 0);
    double worst = 0;
    for (int k = 2; k <= 15; k++) {
        double y = 10 * (1 - pow(10, -k));
        double in[4] = {0.0, y, 0.3, -0.2}, out[4];
        lens_ray r;
        if (ray_from_outer(&L, in, &r) != 0)
            continue;
        for (int j = 0; j < 3; j++)
            assert_true(isfinite(r.o[j]) && isfinite(r.d[j]));
        ray_to_outer(&L, &r, out);
        /* the frame's error grows like 1/|n_xz|, i.e. like 1/sqrt(1 - y/R) */
        double tol = 1e-13 / sqrt(pow(10, -k));
        for (int j = 0; j < 4; j++) {
            if (isfinite(out[j]))
                worst = fmax(worst, fabs(out[j] - in[j]) * sqrt(pow(10, -k)));
            assert_true(!isfinite(out[j]) || fabs(out[j] - in[j]) < fmax(tol, 1e-12));
        }
    }
    metric("hemisphere", "frame_roundtrip_scaled", worst);
    double rim[4] = {0, 10, 0, 0};
    lens_ray r;
    int rc = ray_from_outer(&L, rim, &r);
    if (rc == 0) /* accepted only if the frame it built is finite */
        for (int j = 0; j < 3; j++)
            assert_true(isfinite(r.d[j]));
    /* sensor rays towards the rim: passed and finite, or flagged with nan outputs */
    double n[4];
    lens_err e;
    assert_int_equal(lens_indices(&L, 0.55, n, &e), 0);
    for (int i = 0; i <= 200; i++) {
        double in[4] = {0, 9.0 + i * 0.005, 0, 0}, out[4];
        trace_result res = trace_sample(&L, n, TRACE_TO_OUTER, in, out);
        if (res.status == TRACE_PASSED)
            assert_true(isfinite(out[0]) && isfinite(out[2]) && isfinite(out[3]));
        else
            assert_true(isnan(out[0]) && isnan(out[2]));
    }
    lens_free(&L);
}

/* Unpolarised Fresnel transmittance, written out here from the textbook amplitude
 * coefficients (independent of src/trace/refract.c). */
static double fresnel_T(double n1, double n2, double ci)
{
    double si = sqrt(fmax(0, 1 - ci * ci)), st = n1 / n2 * si;
    if (st >= 1)
        return 0;
    double ct = sqrt(1 - st * st);
    double rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
    double rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct);
    return 1 - 0.5 * (rs * rs + rp * rp);
}

/* A plate of n = 1.8 with a flat front; the back is a sphere, a conic or an asphere.
 * A ray parallel to the axis at height h enters undeviated and meets the back at the
 * angle theta with tan(theta) = |dz/dh| there, so TIR happens iff 1.8 sin(theta) > 1. */
static void test_tir_every_surface_type(void **state)
{
    (void)state;
    const double nglass = 1.8;
    for (int type = 0; type < 3; type++) {
        lens_t L;
        assert_int_equal(fixture_singlet(&L, INFINITY, -12, 8, nglass, 0, 9.5, 20), 0);
        lens_surface *b = &L.surf[1];
        if (type == 1)
            b->conic = -0.6;
        if (type == 2)
            b->asphere[0] = -2e-4;
        lens_err e;
        assert_int_equal(lens_finish(&L, &e), 0);
        double n[4];
        assert_int_equal(lens_indices(&L, 0.55, n, &e), 0);
        int tir = 0, pass = 0;
        double min_T_near = 1;
        for (int i = 0; i <= 400; i++) {
            double h = 9.4 * i / 400;
            double s = lens_sag_slope(b, h * h) * 2 * h; /* dz/dh */
            double sin_t = fabs(s) / sqrt(1 + s * s);
            double margin = nglass * sin_t - 1;
            lens_ray r = {{0, h, -1}, {0, 0, 1}};
            trace_result res = trace_to_sensor(&L, n, &r);
            if (fabs(margin) < 1e-9)
                continue;
            if (margin > 0) {
                assert_int_equal(res.status, TRACE_TIR);
                assert_int_equal(res.surface, 1);
                assert_true(res.transmittance == 0);
                tir++;
            } else {
                assert_int_equal(res.status, TRACE_PASSED);
                assert_true(res.transmittance > 0 && res.transmittance <= 1);
                assert_true(isfinite(r.o[0]) && isfinite(r.o[1]));
                if (margin > -1e-3)
                    min_T_near = fmin(min_T_near, res.transmittance);
                pass++;
            }
        }
        assert_true(tir > 10 && pass > 10);
        lens_free(&L);
    }
    /* A flat plate never reflects totally: inside it the angle stays below critical.
     * Up to grazing incidence the trace passes, with Fresnel's transmittance. */
    lens_t P;
    assert_int_equal(fixture_singlet(&P, INFINITY, INFINITY, 5, nglass, 0, 1e4, 10), 0);
    double n[4];
    lens_err e;
    assert_int_equal(lens_indices(&P, 0.55, n, &e), 0);
    double worst = 0;
    const double deg[] = {0, 45, 80, 89, 89.9, 89.999, 89.99999};
    for (size_t i = 0; i < sizeof deg / sizeof *deg; i++) {
        double th = deg[i] * M_PI / 180;
        lens_ray r = {{0, 0, -1e-3}, {sin(th), 0, cos(th)}};
        trace_result res = trace_to_sensor(&P, n, &r);
        assert_int_equal(res.status, TRACE_PASSED);
        double ci = cos(th), st = sin(th) / nglass, ct = sqrt(1 - st * st);
        double expect = fresnel_T(1, nglass, ci) * fresnel_T(nglass, 1, ct);
        worst = fmax(worst, fabs(res.transmittance - expect));
        assert_true(fabs(res.transmittance - expect) < 1e-9);
        assert_true(fabs(r.d[0] - sin(th)) < 1e-12); /* leaves parallel to how it came */
    }
    metric("plate", "grazing_fresnel_err", worst);
    lens_free(&P);
}

/* A flat front that is also the stop (semi-diameter 10), then a sphere (sd 9.5): rays
 * parallel to the axis hit both at their own height, so the clip test is exact. */
static void test_aperture_edge(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_singlet(&L, INFINITY, -200, 4, 1.5, 0, 10, 50), 0);
    L.surf[1].semi_diameter = 9.5;
    lens_err e;
    assert_int_equal(lens_finish(&L, &e), 0);
    double n[4];
    assert_int_equal(lens_indices(&L, 0.55, n, &e), 0);
    struct {
        double h;
        trace_status st;
        int surf;
    } c[] = {
        {9.5 * (1 - 1e-12), TRACE_PASSED, -1}, {9.5, TRACE_PASSED, -1},
        {9.5 * (1 + 1e-12), TRACE_CLIPPED, 1}, {10 * (1 - 1e-15), TRACE_CLIPPED, 1},
        {10 * (1 + 1e-12), TRACE_STOPPED, 0},
    };
    for (size_t i = 0; i < sizeof c / sizeof *c; i++) {
        lens_ray r = {{0, c[i].h, -1}, {0, 0, 1}};
        trace_result res = trace_to_sensor(&L, n, &r);
        assert_int_equal(res.status, c[i].st);
        if (c[i].surf >= 0)
            assert_int_equal(res.surface, c[i].surf);
        else
            assert_true(isfinite(r.o[0]) && isfinite(r.o[1]));
    }
    lens_free(&L);
}

/* |R| just above the semi-diameter (almost a hemisphere) and |R| = 1e6: every hit the
 * tracer reports lies on the surface to 1e-9 mm (distance to the centre equals |R|). */
static void test_extreme_radii(void **state)
{
    (void)state;
    const double radii[] = {10 * (1 + 1e-9), -10 * (1 + 1e-9), 1e6, -1e6};
    double worst_on = 0;
    for (size_t k = 0; k < sizeof radii / sizeof *radii; k++) {
        lens_surface s = {0};
        s.radius = radii[k];
        s.semi_diameter = 10;
        for (int i = 0; i <= 100; i++) {
            double h = 10 * i / 100.0;
            const double o[3] = {0, h, -20}, d[3] = {0, 0, 1};
            double t, p[3], nrm[3];
            isect_status st = intersect_surface(&s, 0, o, d, 100, &t, p, nrm);
            if (st != ISECT_HIT)
                continue;
            double R = s.radius, dz = p[2] - R;
            double on = fabs(sqrt(p[0] * p[0] + p[1] * p[1] + dz * dz) - fabs(R));
            worst_on = fmax(worst_on, on / fmax(1, fabs(R) * 1e-15 / 1e-9));
            assert_true(on < 1e-9 + fabs(R) * 1e-15);
            /* the normal is the unit radius vector, pointing to object space */
            double nn = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
            assert_true(fabs(nn - 1) < 1e-12 && nrm[2] <= 0);
        }
    }
    metric("extreme-radii", "hit_off_surface_mm", worst_on);
}

/* sag with coefficients that make Newton overshoot: R = 20, a4 .. a12 large and
 * alternating, so the profile turns back within the aperture. */
static double big_sag(const lens_surface *s, double h) { return lens_sag(s, h * h); }

static void test_wild_asphere(void **state)
{
    (void)state;
    lens_surface s = {0};
    s.radius = 20;
    s.semi_diameter = 8;
    s.asphere[0] = 2e-3;
    s.asphere[1] = -1e-4;
    s.asphere[2] = 3e-6;
    s.asphere[3] = -4e-8;
    s.asphere[4] = 2e-10;
    double worst = 0;
    int hits = 0, agree = 0;
    uint64_t st = 5;
    int nrays = sanitized() ? 300 : 2000;
    for (int i = 0; i < nrays; i++) {
        st = st * 6364136223846793005ULL + 1442695040888963407ULL;
        double a = (double)(st >> 11) / 9007199254740992.0;
        st = st * 6364136223846793005ULL + 1442695040888963407ULL;
        double b = (double)(st >> 11) / 9007199254740992.0;
        double o[3] = {0, -8 + 16 * a, -10}, ang = (b - 0.5) * 1.2;
        double d[3] = {0, sin(ang), cos(ang)};
        /* reference: the first sign change of f(t) = z(t) - sag(h(t)) within the clip
         * radius, on a fine grid, refined by bisection */
        double tref = NAN, prev_t = 0, prev_f = NAN;
        for (int j = 0; j <= 20000; j++) {
            double t = 30.0 * j / 20000;
            double y = o[1] + t * d[1];
            if (fabs(y) > 8)
                break;
            double f = o[2] + t * d[2] - big_sag(&s, y);
            if (isfinite(prev_f) && (f > 0) != (prev_f > 0)) {
                double lo = prev_t, hi = t, flo = prev_f;
                for (int k = 0; k < 200; k++) {
                    double m = 0.5 * (lo + hi), fm = o[2] + m * d[2] - big_sag(&s, o[1] + m * d[1]);
                    if ((fm > 0) == (flo > 0))
                        lo = m, flo = fm;
                    else
                        hi = m;
                }
                tref = 0.5 * (lo + hi);
                break;
            }
            prev_t = t;
            prev_f = f;
        }
        double t, p[3], nrm[3];
        isect_status is = intersect_surface(&s, 0, o, d, 64, &t, p, nrm);
        if (is == ISECT_HIT) {
            hits++;
            /* whatever root it reports is on the surface */
            double off = fabs(p[2] - big_sag(&s, p[1]));
            assert_true(off < 1e-9);
            assert_true(isfinite(nrm[0]) && isfinite(nrm[1]) && isfinite(nrm[2]));
            if (isfinite(tref)) {
                worst = fmax(worst, fabs(t - tref));
                agree += fabs(t - tref) < 1e-9;
            }
        }
    }
    metric("wild-asphere", "root_vs_bisection_mm", worst);
    assert_true(hits > nrays / 2);
    /* the first root: every hit that has a reference agrees with it */
    assert_true(worst < 1e-9);
    (void)agree;
}

/* Band edges: N-BK7's catalog range (0.3 .. 2.5 um) and the nd/Vd model's range, and
 * the fisheye's glass of nd 2.003, Vd 19.32 (its most dispersive). At the edges the
 * index is finite and the trace reversible; just outside, the wavelength is refused. */
static void test_band_edges_and_dispersion(void **state)
{
    (void)state;
    glass_catalog *cat = NULL;
    lens_err e;
    assert_int_equal(glass_catalog_load(&cat, "lenses/glass.catalog", &e), 0);
    const glass_t *bk7 = glass_catalog_find(cat, "N-BK7");
    assert_non_null(bk7);
    double nlo, nhi, nx;
    assert_int_equal(glass_index(bk7, bk7->lambda_min, &nlo, &e), 0);
    assert_int_equal(glass_index(bk7, bk7->lambda_max, &nhi, &e), 0);
    assert_true(isfinite(nlo) && isfinite(nhi) && nlo > nhi && nhi > 1.4);
    assert_int_not_equal(glass_index(bk7, bk7->lambda_min * (1 - 1e-12), &nx, &e), 0);
    assert_int_not_equal(glass_index(bk7, bk7->lambda_max * (1 + 1e-12), &nx, &e), 0);

    /* a singlet of N-BK7 traced at both edges */
    lens_t S;
    assert_int_equal(fixture_singlet(&S, 30, -30, 5, 1.5, 0, 10, 28), 0);
    S.surf[0].medium = *bk7;
    assert_int_equal(lens_finish(&S, &e), 0);
    double worst = 0;
    const double edges[] = {bk7->lambda_min, bk7->lambda_max};
    for (int k = 0; k < 2; k++) {
        double n[4];
        assert_int_equal(lens_indices(&S, edges[k], n, &e), 0);
        for (int i = 0; i < 20; i++) {
            double in[4] = {0.3 * i, -0.1 * i, -0.01 * i, 0.02}, out[4];
            lens_ray r;
            ray_from_sensor(&S, in, &r);
            trace_result res = trace_to_object(&S, n, &r, 0);
            if (res.status != TRACE_PASSED)
                continue;
            for (int j = 0; j < 3; j++)
                r.d[j] = -r.d[j];
            res = trace_to_sensor(&S, n, &r);
            assert_int_equal(res.status, TRACE_PASSED);
            ray_to_sensor(&S, &r, out);
            worst = fmax(worst, hypot(out[0] - in[0], out[1] - in[1]));
        }
    }
    metric("bk7-singlet", "band_edge_reverse_err_mm", worst);
    assert_true(worst < 1e-9);
    lens_free(&S);
    glass_catalog_free(cat);

    /* the fisheye at the nd/Vd model's band edges: its 2.003/19.32 glass is the most
     * dispersive; the index spread over the band must exceed the F-C spread */
    lens_t L;
    load("lenses/fisheye-aspherical.lens", &L);
    const glass_t *g = &L.surf[15].medium;
    assert_true(fabs(g->nd - 2.003) < 1e-9);
    double n_lo, n_hi, nF, nC;
    assert_int_equal(glass_index(g, g->lambda_min, &n_lo, &e), 0);
    assert_int_equal(glass_index(g, g->lambda_max, &n_hi, &e), 0);
    assert_int_equal(glass_index(g, GLASS_F_LINE, &nF, &e), 0);
    assert_int_equal(glass_index(g, GLASS_C_LINE, &nC, &e), 0);
    /* Abbe number from the F and C lines reproduces Vd */
    assert_true(fabs((g->nd - 1) / (nF - nC) - 19.32) < 0.05);
    assert_true(n_lo - n_hi > nF - nC);
    double *n = malloc(L.nsurf * sizeof *n);
    double worst_f = 0;
    const double lam[] = {g->lambda_min, g->lambda_max};
    for (int k = 0; k < 2; k++) {
        assert_int_equal(lens_indices(&L, lam[k], n, &e), 0);
        for (int i = 1; i <= 8; i++) {
            double x = 15.4 * i / 8, u;
            if (chief_u(&L, n, x, &u) != 0)
                continue;
            double in[4] = {x, 0, u, 0}, out[4];
            trace_result res = trace_sample(&L, n, TRACE_TO_OUTER, in, out);
            if (res.status != TRACE_PASSED)
                continue;
            lens_ray r;
            assert_int_equal(ray_from_outer(&L, out, &r), 0);
            for (int j = 0; j < 3; j++)
                r.d[j] = -r.d[j];
            res = trace_to_sensor(&L, n, &r);
            assert_int_equal(res.status, TRACE_PASSED);
            worst_f = fmax(worst_f, hypot(r.o[0] - x, r.o[1]));
        }
    }
    metric("fisheye-aspherical", "band_edge_reverse_err_mm", worst_f);
    assert_true(worst_f < 1e-8);
    double below;
    assert_int_not_equal(lens_indices(&L, g->lambda_min * (1 - 1e-9), n, &e), 0);
    (void)below;
    free(n);
    lens_free(&L);
}

/* Same rays, 1 and 2 threads: bit-identical outputs (no reduction order, no shared
 * state in the batch tracer). */
static void test_threads_bit_identical(void **state)
{
    (void)state;
    lens_t L;
    load("lenses/fisheye-aspherical.lens", &L);
    size_t count = sanitized() ? 2000 : 20000;
    double *in = malloc(count * 5 * sizeof *in);
    double *o1 = malloc(count * 5 * sizeof *o1), *o2 = malloc(count * 5 * sizeof *o2);
    uint64_t st = 99;
    for (size_t i = 0; i < count * 5; i++) {
        st = st * 6364136223846793005ULL + 1442695040888963407ULL;
        double a = (double)(st >> 11) / 9007199254740992.0;
        switch (i % 5) {
        case 0: case 1: in[i] = (a - 0.5) * 30; break;
        case 2: case 3: in[i] = (a - 0.5) * 3; break;
        default: in[i] = 0.4 + 0.3 * a;
        }
    }
    lens_err e;
    for (int tgt = 0; tgt < 2; tgt++) {
        trace_target t = tgt ? TRACE_TO_STOP : TRACE_TO_OUTER;
        assert_int_equal(trace_batch(&L, t, count, in, o1, NULL, 1, &e), 0);
        assert_int_equal(trace_batch(&L, t, count, in, o2, NULL, 2, &e), 0);
        assert_memory_equal(o1, o2, count * 5 * sizeof *o1);
    }
    free(in);
    free(o1);
    free(o2);
    lens_free(&L);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fisheye_past_180),
        cmocka_unit_test(test_hemisphere_rim),
        cmocka_unit_test(test_tir_every_surface_type),
        cmocka_unit_test(test_aperture_edge),
        cmocka_unit_test(test_extreme_radii),
        cmocka_unit_test(test_wild_asphere),
        cmocka_unit_test(test_band_edges_and_dispersion),
        cmocka_unit_test(test_threads_bit_identical),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
