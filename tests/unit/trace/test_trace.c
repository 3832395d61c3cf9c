/* The exact tracer: symmetry, reversibility, the paraxial limit, flags, hard cases. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixture_lenses.h"
#include "sparselens/aim.h"
#include "sparselens/trace.h"
#include "sparselens/trace_packet.h"

static uint64_t lcg(uint64_t *st)
{
    *st = *st * 6364136223846793005ULL + 1442695040888963407ULL;
    return *st >> 11;
}
static double unif(uint64_t *st) { return (double)lcg(st) / 9007199254740992.0; }

static int nrays(int n) { return getenv("SANITIZE") && *getenv("SANITIZE") ? n / 8 : n; }

/* A sensor ray towards a uniform point of the rear element's vertex-plane disc. */
static void rear_ray(const lens_t *L, uint64_t *st, double rmax, double in[4])
{
    size_t k = L->nsurf - 1;
    double D = lens_total_track(L) - L->vertex_z[k], sd = L->surf[k].semi_diameter;
    double a = 2 * M_PI * unif(st), r = sd * sqrt(unif(st));
    double b = 2 * M_PI * unif(st), s = rmax * sqrt(unif(st));
    in[0] = s * cos(b);
    in[1] = s * sin(b);
    in[2] = (r * cos(a) - in[0]) / D;
    in[3] = (r * sin(a) - in[1]) / D;
}

static void test_status_names(void **state)
{
    (void)state;
    assert_string_equal(trace_status_name(TRACE_PASSED), "passed");
    assert_string_equal(trace_status_name(TRACE_TIR), "tir");
    assert_string_equal(trace_status_name(TRACE_STOPPED), "stopped");
}

/* Rotating the input about the axis rotates the lens-frame output ray. */
static void test_rotational_symmetry(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    double n[32];
    lens_err e;
    assert_int_equal(lens_indices(&L, 0.55, n, &e), 0);
    uint64_t st = 42;
    int passed = 0;
    for (int i = 0; i < nrays(4000); i++) {
        double in[4], in2[4];
        rear_ray(&L, &st, 14.5, in);
        double phi = 2 * M_PI * unif(&st), c = cos(phi), s = sin(phi);
        in2[0] = c * in[0] - s * in[1];
        in2[1] = s * in[0] + c * in[1];
        in2[2] = c * in[2] - s * in[3];
        in2[3] = s * in[2] + c * in[3];
        lens_ray r1, r2;
        ray_from_sensor(&L, in, &r1);
        ray_from_sensor(&L, in2, &r2);
        trace_result a = trace_to_object(&L, n, &r1, 0), b = trace_to_object(&L, n, &r2, 0);
        if (a.status != b.status) /* within rounding of an aperture edge: rare */
            continue;
        if (a.status != TRACE_PASSED)
            continue;
        passed++;
        assert_true(fabs(a.transmittance - b.transmittance) < 1e-12);
        assert_true(fabs(c * r1.o[0] - s * r1.o[1] - r2.o[0]) < 1e-9);
        assert_true(fabs(s * r1.o[0] + c * r1.o[1] - r2.o[1]) < 1e-9);
        assert_true(fabs(r1.o[2] - r2.o[2]) < 1e-9);
        assert_true(fabs(c * r1.d[0] - s * r1.d[1] - r2.d[0]) < 1e-11);
        assert_true(fabs(s * r1.d[0] + c * r1.d[1] - r2.d[1]) < 1e-11);
        assert_true(fabs(r1.d[2] - r2.d[2]) < 1e-11);
    }
    assert_true(passed > nrays(4000) / 4);
    lens_free(&L);
}

/* Sensor -> outer, then back from the reversed outer ray, gives the start to 1e-9 mm;
 * it also goes through the outer parametrisation and back. */
static void check_reversible(const lens_t *L, double lambda, int count, double rmax, int *past90)
{
    double n[32];
    lens_err e;
    assert_int_equal(lens_indices(L, lambda, n, &e), 0);
    uint64_t st = 9;
    int passed = 0;
    for (int i = 0; i < count; i++) {
        double in[4], outer[4], back[4];
        rear_ray(L, &st, rmax, in);
        trace_result res = trace_sample(L, n, TRACE_TO_OUTER, in, outer);
        if (res.status != TRACE_PASSED)
            continue;
        passed++;
        lens_ray r;
        assert_int_equal(ray_from_outer(L, outer, &r), 0);
        if (past90 && r.d[2] > 0)
            (*past90)++;
        for (int k = 0; k < 3; k++)
            r.d[k] = -r.d[k];
        trace_result b = trace_to_sensor(L, n, &r);
        assert_int_equal(b.status, TRACE_PASSED);
        /* Fresnel transmittance is the same both ways (reciprocity) */
        assert_true(fabs(b.transmittance - res.transmittance) < 1e-12);
        ray_to_sensor(L, &r, back);
        assert_true(fabs(back[0] - in[0]) < 1e-9 && fabs(back[1] - in[1]) < 1e-9);
        assert_true(fabs(back[2] - in[2]) < 1e-9 && fabs(back[3] - in[3]) < 1e-9);
    }
    assert_true(passed > count / 10);
}

static void test_reversibility(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    int past90 = 0;
    check_reversible(&L, 0.36, nrays(2000), 14.5, NULL);   /* band edges of nd/Vd glass */
    check_reversible(&L, 1.0, nrays(2000), 14.5, NULL);
    check_reversible(&L, GLASS_D_LINE, nrays(8000), 14.5, &past90);
    /* fisheye fields past 90 degrees are among the rays checked */
    assert_true(past90 > 0);
    lens_free(&L);
    assert_int_equal(fixture_dgauss50(&L), 0);
    check_reversible(&L, 0.5, nrays(4000), 21.6, NULL);
    lens_free(&L);
}

/* A tiny ray parallel to the axis crosses it at the paraxial focus. */
static double exact_bfl(const lens_t *L, const double *n, double y0, double *efl)
{
    lens_ray r = {{0, y0, -1}, {0, 0, 1}};
    trace_result res = trace_to_sensor(L, n, &r);
    assert_int_equal(res.status, TRACE_PASSED);
    double zc = r.o[2] - r.o[1] * r.d[2] / r.d[1];
    *efl = -y0 * r.d[2] / r.d[1];
    return zc - L->vertex_z[L->nsurf - 1];
}

static void test_paraxial_limit(void **state)
{
    (void)state;
    /* Thick singlet against the lensmaker's equation (closed form, constant index). */
    double R1 = 50, R2 = -80, d = 6, nn = 1.6;
    lens_t L;
    assert_int_equal(fixture_singlet(&L, R1, R2, d, nn, 0, 10, 60), 0);
    double n[32], efl;
    lens_err e;
    assert_int_equal(lens_indices(&L, 0.55, n, &e), 0);
    double P = (nn - 1) * (1 / R1 - 1 / R2 + (nn - 1) * d / (nn * R1 * R2));
    double f = 1 / P, bfl = f * (1 - (nn - 1) * d / (nn * R1));
    double b = exact_bfl(&L, n, 1e-4, &efl);
    assert_true(fabs(b - bfl) < 1e-6 * bfl);
    assert_true(fabs(efl - f) < 1e-6 * f);
    /* thin-lens limit: d -> 0, constant index */
    lens_free(&L);
    assert_int_equal(fixture_singlet(&L, 100, -100, 1e-3, 1.5, 0, 0.4, 100), 0);
    assert_int_equal(lens_indices(&L, 0.55, n, &e), 0);
    exact_bfl(&L, n, 1e-4, &efl);
    assert_true(fabs(efl - 100) < 1e-3);
    lens_free(&L);
    /* fisheye-ii and the double Gauss against the y-nu trace of the fixture */
    for (int k = 0; k < 2; k++) {
        assert_int_equal(k ? fixture_dgauss50(&L) : fixture_fisheye_ii(&L), 0);
        assert_int_equal(lens_indices(&L, GLASS_D_LINE, n, &e), 0);
        double bp = fixture_bfl(&L), ep = fixture_efl(&L);
        b = exact_bfl(&L, n, 1e-4, &efl);
        assert_true(fabs(b - bp) < 1e-6 * fabs(bp));
        assert_true(fabs(efl - ep) < 1e-6 * fabs(ep));
        lens_free(&L);
    }
}

/* A flat-fronted block of n = 1.8 with a back face of R = 12: a ray parallel to the axis
 * at height 9 meets the back face at asin(9/12) = 48.6 deg > the critical 33.7 deg. */
static void test_tir_and_clipping(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_singlet(&L, INFINITY, 12, 5, 1.8, 0, 10, 20), 0);
    double n[4];
    lens_err e;
    assert_int_equal(lens_indices(&L, 0.55, n, &e), 0);
    lens_ray r = {{0, 9, -1}, {0, 0, 1}};
    trace_result res = trace_to_sensor(&L, n, &r);
    assert_int_equal(res.status, TRACE_TIR);
    assert_int_equal(res.surface, 1);
    assert_true(res.transmittance == 0);
    lens_ray r2 = {{0, 3, -1}, {0, 0, 1}}; /* asin(3/12) = 14.5 deg: passes */
    res = trace_to_sensor(&L, n, &r2);
    assert_int_equal(res.status, TRACE_PASSED);
    assert_true(res.transmittance > 0.8 && res.transmittance < 1);
    /* the stop is surface 0: a ray beyond its semi-diameter is stopped there */
    lens_ray r3 = {{0, 10.5, -1}, {0, 0, 1}};
    res = trace_to_sensor(&L, n, &r3);
    assert_int_equal(res.status, TRACE_STOPPED);
    assert_int_equal(res.surface, 0);
    /* exactly at the edge of the clear aperture: passes the stop (then meets TIR) */
    lens_ray r4 = {{0, 10, -1}, {0, 0, 1}};
    res = trace_to_sensor(&L, n, &r4);
    assert_int_not_equal(res.status, TRACE_STOPPED);
    /* a ray travelling away from the lens misses */
    lens_ray r5 = {{0, 0, -1}, {0, 0, -1}};
    res = trace_to_sensor(&L, n, &r5);
    assert_int_equal(res.status, TRACE_MISSED);
    /* non-finite input is flagged invalid, and nothing comes out */
    double bad[4] = {NAN, 0, 0, 0}, out[4];
    res = trace_sample(&L, n, TRACE_TO_OUTER, bad, out);
    assert_int_equal(res.status, TRACE_INVALID);
    assert_true(isnan(out[0]) && isnan(out[3]));
    lens_free(&L);
    /* clipped at a lens semi-diameter (not the stop): fisheye-ii, from the sensor */
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    double nf[32];
    assert_int_equal(lens_indices(&L, 0.55, nf, &e), 0);
    double in[4] = {0, 0, 12.0 / 41.1, 0};
    res = trace_sample(&L, nf, TRACE_TO_OUTER, in, out);
    assert_int_equal(res.status, TRACE_CLIPPED);
    assert_int_equal(res.surface, 17);
    lens_free(&L);
}

/* On-axis rays, grazing rays and a flat |R| = 1e6 surface. */
static void test_hard_cases(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    double n[32], out[4];
    lens_err e;
    assert_int_equal(lens_indices(&L, GLASS_D_LINE, n, &e), 0);
    double axis[4] = {0, 0, 0, 0};
    trace_result res = trace_sample(&L, n, TRACE_TO_OUTER, axis, out);
    assert_int_equal(res.status, TRACE_PASSED);
    assert_true(out[0] == 0 && out[1] == 0 && out[2] == 0 && out[3] == 0);
    /* normal incidence everywhere: eta is the product of ((n1-n2)/(n1+n2))^2 losses */
    double eta = 1, n1 = 1;
    for (size_t i = 0; i < L.nsurf; i++) {
        double rr = (n1 - n[i]) / (n1 + n[i]);
        eta *= 1 - rr * rr;
        n1 = n[i];
    }
    assert_true(fabs(res.transmittance - eta) < 1e-14);
    res = trace_sample(&L, n, TRACE_TO_STOP, axis, out);
    assert_int_equal(res.status, TRACE_PASSED);
    assert_true(out[0] == 0 && out[1] == 0 && out[2] == 0 && out[3] == 0);
    /* nothing unflagged is nan: a sweep over wild inputs */
    uint64_t st = 77;
    for (int i = 0; i < nrays(20000); i++) {
        double in[4] = {(unif(&st) - 0.5) * 40, (unif(&st) - 0.5) * 40, (unif(&st) - 0.5) * 6,
                        (unif(&st) - 0.5) * 6};
        if (i % 97 == 0)
            in[2] = 1e6; /* almost parallel to the sensor */
        for (int tgt = 0; tgt < 2; tgt++) {
            res = trace_sample(&L, n, tgt ? TRACE_TO_STOP : TRACE_TO_OUTER, in, out);
            int fin = isfinite(out[0]) && isfinite(out[1]) && isfinite(out[2]) && isfinite(out[3]);
            if (res.status == TRACE_PASSED)
                assert_true(fin && res.transmittance > 0 && res.transmittance <= 1);
            else
                assert_true(isnan(out[0]) && isnan(out[2]) && res.transmittance == 0);
        }
    }
    lens_free(&L);
    /* grazing: a ray nearly tangent to the front of a hemisphere-ish element */
    assert_int_equal(fixture_singlet(&L, 10, INFINITY, 12, 1.5, 0, 9.9, 20), 0);
    assert_int_equal(lens_indices(&L, 0.55, n, &e), 0);
    lens_ray g = {{-30, 9.95, 10}, {1, 0, 0}}; /* tangent-ish at height ~9.95 > sd */
    res = trace_to_sensor(&L, n, &g);
    assert_true(res.status == TRACE_CLIPPED || res.status == TRACE_STOPPED || res.status == TRACE_MISSED);
    lens_ray g2 = {{-30, 0, 10 - 1e-9}, {1, 0, 0}}; /* grazing the sphere's rim plane */
    res = trace_to_sensor(&L, n, &g2);
    assert_int_not_equal(res.status, TRACE_PASSED);
    lens_free(&L);
    /* A plate with flat faces: lateral shift only, to rounding. A window with |R| = 1e6
     * faces is the same plate to within its power (~1e-6 / mm) times the heights. */
    for (int k = 0; k < 2; k++) {
        double rad = k ? 1e6 : INFINITY;
        assert_int_equal(fixture_singlet(&L, rad, -rad, 10, 1.5, 0, 20, 30), 0);
        assert_int_equal(lens_indices(&L, 0.55, n, &e), 0);
        double th = 0.3;
        lens_ray w = {{0, 0, -5}, {sin(th), 0, cos(th)}};
        res = trace_to_sensor(&L, n, &w);
        assert_int_equal(res.status, TRACE_PASSED);
        double tht = asin(sin(th) / 1.5);
        double x_expect = 5 * tan(th) + 10 * tan(tht) + 30 * tan(th);
        double tol = k ? 1e-3 : 1e-12;
        assert_true(fabs(w.o[0] - x_expect) < tol);
        assert_true(fabs(w.d[0] - sin(th)) < (k ? 1e-4 : 1e-15));
        assert_true(fabs(w.o[2] - lens_total_track(&L)) < 1e-12);
        lens_free(&L);
    }
}

static void test_wavelength_range(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    double n[32];
    lens_err e;
    assert_int_equal(lens_indices(&L, 0.36, n, &e), 0);
    assert_int_equal(lens_indices(&L, 1.0, n, &e), 0);
    assert_int_equal(lens_indices(&L, 0.3599, n, &e), -1);
    assert_non_null(strstr(e.msg, "surface 1"));
    assert_int_equal(lens_indices(&L, 1.0001, n, &e), -1);
    lens_free(&L);
}

/* The batch: same results as one by one, the same with 1 or 2 threads, bad rows nan. */
static void test_batch(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    size_t N = (size_t)nrays(4000);
    double *in = malloc(N * 5 * sizeof *in), *o1 = malloc(N * 5 * sizeof *o1),
           *o2 = malloc(N * 5 * sizeof *o2);
    trace_result *r1 = malloc(N * sizeof *r1);
    uint64_t st = 5;
    for (size_t i = 0; i < N; i++) {
        rear_ray(&L, &st, 14, in + 5 * i);
        in[5 * i + 4] = (i % 3) ? 0.4 + 0.3 * unif(&st) : 0.55;
    }
    lens_err e;
    assert_int_equal(trace_batch(&L, TRACE_TO_OUTER, N, in, o1, r1, 1, &e), 0);
    assert_int_equal(trace_batch(&L, TRACE_TO_OUTER, N, in, o2, NULL, 2, &e), 0);
    assert_memory_equal(o1, o2, N * 5 * sizeof *o1);
    for (size_t i = 0; i < N; i += 37) {
        double n[32], out[4];
        assert_int_equal(lens_indices(&L, in[5 * i + 4], n, &e), 0);
        trace_result r = trace_sample(&L, n, TRACE_TO_OUTER, in + 5 * i, out);
        assert_int_equal(r.status, r1[i].status);
        if (r.status == TRACE_PASSED) {
            assert_memory_equal(out, o1 + 5 * i, 4 * sizeof *out);
            assert_true(o1[5 * i + 4] == r.transmittance);
        } else {
            assert_true(isnan(o1[5 * i]) && o1[5 * i + 4] == 0);
        }
    }
    in[5 * 10 + 4] = 0.2; /* out of range */
    in[5 * 20 + 4] = 1.5;
    assert_int_equal(trace_batch(&L, TRACE_TO_STOP, N, in, o1, r1, 2, &e), -1);
    assert_non_null(strstr(e.msg, "ray 11"));
    assert_true(isnan(o1[50]) && isnan(o1[54]) && isnan(o1[100]));
    assert_int_equal(r1[10].status, TRACE_INVALID);
    free(in), free(o1), free(o2), free(r1);
    lens_free(&L);
}

/* The outer pupil's (u, v) turn with the ray like its (x, y) (ray_frames.h): a lens
 * turned about its axis is the same lens, so the meridional frame of lens-fit can model
 * the directions too. The frame of earlier versions (e_x = normalize(-n_z, 0, n_x))
 * fails this by up to 0.1 in u at the rim of fisheye-ii's front element. Through the
 * packet kernel (trace_batch) and the scalar path (trace_sample). */
static void test_outer_frame_turns_with_ray(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    size_t N = (size_t)nrays(2000);
    double *in = malloc(N * 10 * sizeof *in), *out = malloc(N * 10 * sizeof *out);
    uint64_t st = 11;
    double *phi = malloc(N * sizeof *phi);
    for (size_t i = 0; i < N; i++) {
        double *a = in + 5 * i, *b = in + 5 * (N + i);
        rear_ray(&L, &st, 14, a);
        a[4] = 0.55;
        phi[i] = 2 * M_PI * unif(&st);
        double c = cos(phi[i]), s = sin(phi[i]);
        b[0] = c * a[0] - s * a[1], b[1] = s * a[0] + c * a[1];
        b[2] = c * a[2] - s * a[3], b[3] = s * a[2] + c * a[3];
        b[4] = a[4];
    }
    lens_err e;
    double n[32];
    assert_int_equal(trace_batch(&L, TRACE_TO_OUTER, 2 * N, in, out, NULL, 2, &e), 0);
    assert_int_equal(lens_indices(&L, 0.55, n, &e), 0);
    int passed = 0, past90 = 0;
    for (size_t i = 0; i < N; i++) {
        const double *p = out + 5 * i, *q = out + 5 * (N + i);
        if (!(p[4] > 0) || !(q[4] > 0))
            continue;
        passed++;
        past90 += p[2] * p[2] + p[3] * p[3] > 0.5; /* far from the normal */
        double c = cos(phi[i]), s = sin(phi[i]);
        assert_true(fabs(c * p[0] - s * p[1] - q[0]) < 1e-9);
        assert_true(fabs(s * p[0] + c * p[1] - q[1]) < 1e-9);
        assert_true(fabs(c * p[2] - s * p[3] - q[2]) < 1e-11);
        assert_true(fabs(s * p[2] + c * p[3] - q[3]) < 1e-11);
        double sc[4];
        trace_result r = trace_sample(&L, n, TRACE_TO_OUTER, in + 5 * (N + i), sc);
        assert_int_equal(r.status, TRACE_PASSED);
        for (int k = 0; k < 4; k++)
            assert_true(fabs(sc[k] - q[k]) < 1e-12);
    }
    assert_true(passed > (int)N / 4 && past90 > 0);
    free(in), free(out), free(phi);
    lens_free(&L);
}

/* Every SIMD width of the packet kernel gives the same bits as the 2-lane one. */
static void test_packet_widths(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    enum { M = 8 * 50 };
    static double nbuf[M][32];
    static lens_ray ref[M], got[M];
    static trace_result rref[M], rgot[M];
    const double *np[M];
    uint64_t st = 3;
    lens_err e;
    for (int i = 0; i < M; i++) {
        double in[4];
        rear_ray(&L, &st, 14.5, in);
        ray_from_sensor(&L, in, &ref[i]);
        assert_int_equal(lens_indices(&L, 0.4 + 0.3 * unif(&st), nbuf[i], &e), 0);
        np[i] = nbuf[i];
    }
    memcpy(got, ref, sizeof got);
    static double oref[4 * M], ogot[4 * M];
    trace_packet_to_object_w(&L, np, M, ref, 0, rref, oref, 2);
    /* the kernel's outer coordinates are ray_to_outer's, to rounding */
    for (int i = 0; i < M; i++) {
        if (rref[i].status != TRACE_PASSED)
            continue;
        double o[4];
        ray_to_outer(&L, &ref[i], o);
        for (int k = 0; k < 4; k++)
            assert_true(fabs(o[k] - oref[4 * i + k]) < 1e-13);
    }
    for (int w = 4; w <= trace_packet_width(); w *= 2) {
        for (int last = 0; last <= 1; last++) {
            lens_ray a[M];
            memcpy(a, got, sizeof a);
            if (last) {
                lens_ray b[M];
                trace_result rb[M];
                memcpy(b, got, sizeof b);
                trace_packet_to_object_w(&L, np, M, b, L.stop, rb, NULL, 2);
                trace_packet_to_object_w(&L, np, M, a, L.stop, rgot, NULL, w);
                assert_memory_equal(a, b, sizeof a);
                assert_memory_equal(rgot, rb, sizeof rb);
            } else {
                trace_packet_to_object_w(&L, np, M, a, 0, rgot, ogot, w);
                assert_memory_equal(a, ref, sizeof a);
                assert_memory_equal(ogot, oref, sizeof ogot);
                assert_memory_equal(rgot, rref, sizeof rgot);
            }
        }
    }
    lens_free(&L);
}

/* Ray aiming from the sensor: the aimed ray, traced with clipping, crosses the stop at
 * the requested point. */
static void test_aim_from_sensor(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    double n[32];
    lens_err e;
    assert_int_equal(lens_indices(&L, GLASS_D_LINE, n, &e), 0);
    /* Targets known to be reachable: the stop hits of random passing rays; aiming from
     * the same sensor point must find a ray through the same stop point. */
    uint64_t st = 21;
    int done = 0;
    for (int i = 0; i < 400 && done < 40; i++) {
        double in[4], out[4], u, v;
        rear_ray(&L, &st, 14, in);
        if (trace_sample(&L, n, TRACE_TO_STOP, in, out).status != TRACE_PASSED)
            continue;
        done++;
        assert_int_equal(aim_from_sensor(&L, n, in[0], in[1], out[0], out[1], &u, &v), 0);
        double in2[4] = {in[0], in[1], u, v}, out2[4];
        assert_int_equal(trace_sample(&L, n, TRACE_TO_STOP, in2, out2).status, TRACE_PASSED);
        assert_true(fabs(out2[0] - out[0]) < 1e-8 && fabs(out2[1] - out[1]) < 1e-8);
        assert_true(fabs(u - in[2]) < 1e-7 && fabs(v - in[3]) < 1e-7);
    }
    assert_int_equal(done, 40);
    /* an unreachable target (far outside the stop, through the extended rear surfaces)
     * is reported, not returned as garbage */
    double u0 = 7, v0 = 7;
    if (aim_from_sensor(&L, n, 10, 3, 500, 500, &u0, &v0) != 0)
        assert_true(u0 == 7 && v0 == 7);
    /* the chief ray from the centre is the axis */
    double u, v;
    assert_int_equal(aim_from_sensor(&L, n, 0, 0, 0, 0, &u, &v), 0);
    assert_true(fabs(u) < 1e-12 && fabs(v) < 1e-12);
    lens_free(&L);
}

/* Chief rays of fisheye-ii from object directions up to 95 degrees off the axis: they
 * pass, they cross the stop centre (checked by tracing back from the image), the image
 * height grows with the angle, and a 1 degree field lands at efl tan(1 deg). */
static void test_aim_from_object(void **state)
{
    (void)state;
    lens_t L;
    assert_int_equal(fixture_fisheye_ii(&L), 0);
    double n[32];
    lens_err e;
    assert_int_equal(lens_indices(&L, GLASS_D_LINE, n, &e), 0);
    double prev = -1;
    const double angles[] = {1, 10, 30, 60, 80, 90, 95};
    for (int i = 0; i < 7; i++) {
        double a = angles[i] * M_PI / 180, phi = 0.7 * i;
        double dir[3] = {-sin(a) * cos(phi), -sin(a) * sin(phi), cos(a)};
        lens_ray r;
        assert_int_equal(aim_from_object(&L, n, dir, NULL, 0, 0, &r), 0);
        assert_true(fabs(r.d[0] - dir[0]) < 1e-15 && fabs(r.d[2] - dir[2]) < 1e-15);
        trace_result t = trace_to_sensor(&L, n, &r);
        assert_int_equal(t.status, TRACE_PASSED);
        double h = hypot(r.o[0], r.o[1]);
        assert_true(h > prev);
        prev = h;
        /* image on the far side of the axis, in the same azimuth */
        assert_true(fabs(atan2(-r.o[1], -r.o[0]) - atan2(sin(phi), cos(phi))) < 1e-9);
        if (i == 0) { /* height where the chief ray crosses the paraxial focal plane */
            double zf = L.vertex_z[L.nsurf - 1] + fixture_bfl(&L);
            double hf = hypot(r.o[0] + (zf - r.o[2]) * r.d[0] / r.d[2],
                              r.o[1] + (zf - r.o[2]) * r.d[1] / r.d[2]);
            assert_true(fabs(hf - fixture_efl(&L) * tan(a)) < 2e-3 * hf);
        }
        double back[4]; /* the arriving ray in the sensor parametrisation (reversed) */
        ray_to_sensor(&L, &r, back);
        double out[4];
        assert_int_equal(trace_sample(&L, n, TRACE_TO_STOP, back, out).status, TRACE_PASSED);
        assert_true(hypot(out[0], out[1]) < 1e-8);
    }
    /* a finite object point, through a point off the stop centre */
    double pt[3] = {30, -20, -400};
    lens_ray r;
    assert_int_equal(aim_from_object(&L, n, NULL, pt, 2, 1, &r), 0);
    assert_true(r.o[0] == 30 && r.o[1] == -20 && r.o[2] == -400);
    assert_int_equal(trace_to_sensor(&L, n, &r).status, TRACE_PASSED);
    double back[4], out[4];
    ray_to_sensor(&L, &r, back);
    assert_int_equal(trace_sample(&L, n, TRACE_TO_STOP, back, out).status, TRACE_PASSED);
    assert_true(fabs(out[0] - 2) < 1e-8 && fabs(out[1] - 1) < 1e-8);
    /* bad calls */
    double dir[3] = {0, 0, 1};
    assert_int_equal(aim_from_object(&L, n, dir, pt, 0, 0, &r), -1);
    assert_int_equal(aim_from_object(&L, n, NULL, NULL, 0, 0, &r), -1);
    lens_free(&L);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_status_names),     cmocka_unit_test(test_rotational_symmetry),
        cmocka_unit_test(test_reversibility),    cmocka_unit_test(test_paraxial_limit),
        cmocka_unit_test(test_tir_and_clipping), cmocka_unit_test(test_hard_cases),
        cmocka_unit_test(test_wavelength_range), cmocka_unit_test(test_batch),
        cmocka_unit_test(test_packet_widths),    cmocka_unit_test(test_aim_from_sensor),
        cmocka_unit_test(test_aim_from_object), cmocka_unit_test(test_outer_frame_turns_with_ray),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
