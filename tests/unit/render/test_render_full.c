/* The unsimplified estimator (render_full.c, render_full_weight): Eq. 3 with G-bar
 * (Eq. 12) and p_A(s1) (Eq. 8) each evaluated from its own terms, on the 50 mm double
 * Gauss through the exact tracer and through a system fitted by render_fit:
 *  - p_A(s1) (s0 fixed): |d s1 / d s0'| = |ds1/dsf| |J_all| |A| against central
 *    differences of s1 over (u, v) through the whole map (lens map, scene intersection);
 *  - G-bar (s1 fixed): against the solid angle at s1 of the rays that reach it from a
 *    sensor square, by central differences over (x, y) of the ray through s1 (found by
 *    Newton on the lens map alone: no Jacobian, no frames);
 *  - their ratio against the Eq. 13 weight the renderer uses by default: equal through
 *    the exact tracer (etendue is conserved), and through the system only as closely as
 *    its map conserves etendue (a few percent: the check Eq. 13 cannot make itself);
 *  - |A| from the polynomial matches central differences of the exact tracer (the
 *    system's accuracy: a few percent);
 *  - both estimators render the same image (same seed, same samples) within noise. */
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
#include "sparselens/glass.h"
#include "sparselens/render.h"
#include "sparselens/render_effects.h"
#include "sparselens/render_lens.h"
#include "sparselens/scene.h"
#include "sparselens/trace.h"

/* checker wall at 1 m, a tilted plane and a sphere: s1 on surfaces at several angles */
static const char *scene_text =
    "camera a.lens\nresolution 12 8\nmode grey\nseed 3\n"
    "plane 0 0 1000 0 0 -1 checker 0.2 0.9 40\n"
    "plane 0 -100 0 0 1 0.1 albedo 0.5\n"
    "sphere 60 40 600 60 albedo 0.8\n"
    "disk 0 300 500 0 -1 0 200 emit 4\n";

typedef struct {
    lens_t lens;
    scene_t scene;
    poly_system *sys;
    render_camera cp, ce;
    render_lens_ctx *lp, *le;
    render_sampler smp;
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    lens_err err = {{0}};
    if (!f || fixture_dgauss50(&f->lens) || scene_parse(scene_text, "t.scene", &f->scene, &err))
        return -1;
    render_effects e;
    double fit_s;
    if (render_effects_decide(&f->scene, &f->lens, 36, 24, &e, &err) ||
        !(f->sys = render_fit(&f->lens, &e, 0, &fit_s, &err)) ||
        !(f->lp = render_lens_poly(f->sys, &f->lens, 36, 24, &f->cp, &err)) ||
        !(f->le = render_lens_exact(&f->lens, 36, 24, &f->ce, &err)) ||
        render_sampler_lens(&f->smp, &f->lens, GLASS_D_LINE, GLASS_D_LINE, hypot(18, 12), 0, &err)) {
        print_error("%s\n", err.msg);
        return -1;
    }
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    render_sampler_free(&f->smp);
    render_lens_free(f->lp);
    render_lens_free(f->le);
    poly_free(f->sys);
    scene_free(&f->scene);
    lens_free(&f->lens);
    free(f);
    return 0;
}

static double u01(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* A passing camera ray that hits the scene: its input, outer coordinates, Jacobian,
 * density, transmittance and hit. */
typedef struct {
    double in[5], o[4], jac[16], pdf, eta;
    scene_hit hit;
} cam_ray;

static int draw(const fixture *f, const render_camera *cam, uint64_t *st, cam_ray *r)
{
    double x = (u01(st) - 0.5) * 36, y = (u01(st) - 0.5) * 24, u, v;
    r->pdf = render_sampler_sample(&f->smp, x, y, u01(st), u01(st), &u, &v);
    if (!(r->pdf > 0)) return 0;
    double in[5] = {x, y, u, v, GLASS_D_LINE};
    memcpy(r->in, in, sizeof in);
    if (!cam->outer(cam->ctx, r->in, r->o, r->jac, &r->eta)) return 0;
    lens_ray lr;
    if (ray_from_outer(&f->lens, r->o, &lr)) return 0;
    double os[3], ds[3];
    render_lens_to_scene(lr.o, os);
    render_lens_to_scene(lr.d, ds);
    return scene_intersect(&f->scene, os, ds, 1e-6, INFINITY, &r->hit);
}

/* The relative differences of the full weight from Eq. 13's over 4000 camera rays:
 * median and worst. */
static void weights_against_eq13(const fixture *f, const render_camera *cam, double *median,
                                 double *worst)
{
    enum { N = 4000 };
    static double rel[N];
    uint64_t st = 11;
    int n = 0, evaluated = 0;
    while (n < N) {
        cam_ray r;
        if (!draw(f, cam, &st, &r)) continue;
        n++;
        render_full_terms t;
        if (render_full_weight(&f->lens, r.in, r.o, r.jac, r.pdf, r.eta, r.hit.p, r.hit.n, &t))
            continue;
        double w13 = render_ray_weight(r.in[2], r.in[3], r.pdf, r.eta);
        rel[evaluated++] = fabs(t.weight / w13 - 1);
        /* and the factors are not trivially 1: they do cancel */
        assert_true(t.A > 0 && t.J_all >= 1 && t.ds1_dsf > 0 && t.A_s1 > 0 && t.cos_s1 > 0);
    }
    assert_true(evaluated > 0.99 * n);
    qsort(rel, evaluated, sizeof *rel, cmp_double);
    *median = rel[evaluated / 2];
    *worst = rel[evaluated - 1];
}

static void test_weights_against_eq13(void **state)
{
    fixture *f = *state;
    double me, we, mp, wp;
    weights_against_eq13(f, &f->ce, &me, &we);
    weights_against_eq13(f, &f->cp, &mp, &wp);
    print_message("full vs Eq. 13, relative difference: exact tracer median %.2g worst %.2g; "
                  "system median %.2g worst %.2g\n", me, we, mp, wp);
    /* the tracer conserves etendue: only the differences' error remains */
    assert_true(we < 1e-4);
    /* the system does so to the accuracy of its Jacobian (test_A_against_exact: a few
     * percent); and if G-bar were again computed from the Jacobian p_A(s1) uses, the two
     * would agree to rounding here */
    assert_true(mp > 1e-3 && mp < 0.05 && wp < 0.3);
}

/* s1 of the camera ray in, when it hits object obj (else -1) */
static int s1_of(const fixture *f, const render_camera *cam, const double in[5], double s1[3],
                 int obj)
{
    double ol[3], dl[3], eta, os[3], ds[3];
    if (!cam->map(cam->ctx, in, ol, dl, &eta)) return -1;
    render_lens_to_scene(ol, os);
    render_lens_to_scene(dl, ds);
    scene_hit h;
    if (!scene_intersect(&f->scene, os, ds, 1e-6, INFINITY, &h) || h.obj != obj) return -1;
    memcpy(s1, h.p, sizeof h.p);
    return 0;
}

/* The direction (scene frame) of the ray from sensor point (x, y) that passes through
 * s1, by Newton over (u, v) on the lens map (started at in's), differences 1e-7.
 * The miss is measured as the unit vector towards s1 less the ray's direction. */
static int ray_through(const render_camera *cam, const double in[5], double x, double y,
                       const double s1[3], double d[3])
{
    double q[5] = {x, y, in[2], in[3], in[4]};
    for (int it = 0; it < 20; it++) {
        double miss[3][3]; /* at q, at q + h e_u, at q + h e_v */
        for (int k = 0; k < 3; k++) {
            double p[5] = {q[0], q[1], q[2] + (k == 1) * 1e-7, q[3] + (k == 2) * 1e-7, q[4]};
            double ol[3], dl[3], eta, os[3], ds[3];
            if (!cam->map(cam->ctx, p, ol, dl, &eta)) return -1;
            render_lens_to_scene(ol, os);
            render_lens_to_scene(dl, ds);
            double to[3] = {s1[0] - os[0], s1[1] - os[1], s1[2] - os[2]};
            double len = sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]);
            for (int j = 0; j < 3; j++) miss[k][j] = to[j] / len - ds[j];
            if (k == 0) memcpy(d, ds, sizeof ds);
        }
        double err2 = miss[0][0] * miss[0][0] + miss[0][1] * miss[0][1] + miss[0][2] * miss[0][2];
        if (err2 < 1e-26) return 0;
        /* least squares over the three components: (Ju Jv) step = -miss */
        double Ju[3], Jv[3];
        for (int j = 0; j < 3; j++) Ju[j] = (miss[1][j] - miss[0][j]) / 1e-7,
                                    Jv[j] = (miss[2][j] - miss[0][j]) / 1e-7;
        double a = 0, b = 0, c = 0, ru = 0, rv = 0;
        for (int j = 0; j < 3; j++) a += Ju[j] * Ju[j], b += Ju[j] * Jv[j], c += Jv[j] * Jv[j],
                                    ru += Ju[j] * miss[0][j], rv += Jv[j] * miss[0][j];
        double det = a * c - b * b;
        q[2] -= (c * ru - b * rv) / det;
        q[3] -= (a * rv - b * ru) / det;
    }
    return -1;
}

/* Returns how far cos^4(theta_s0) / |d s1 / d s0'| is from the differences' G. */
static double factors_finite_differences(const fixture *f, const render_camera *cam)
{
    uint64_t st = 5;
    int checked = 0, unmeasured = 0, objs[8] = {0};
    double worst = 0, worst_G = 0, worst_G_shared = 0;
    for (int guard = 0; checked < 120 && guard < 10000; guard++) {
        cam_ray r;
        if (!draw(f, cam, &st, &r)) continue;
        render_full_terms t;
        if (render_full_weight(&f->lens, r.in, r.o, r.jac, r.pdf, r.eta, r.hit.p, r.hit.n, &t))
            continue;
        /* s0 fixed: d s1 / d(u, v) */
        double h = 1e-6, du[3], dv[3], a[3], b[3], ip[5], im[5];
        int ok = 1;
        for (int k = 0; k < 2 && ok; k++) {
            memcpy(ip, r.in, sizeof ip);
            memcpy(im, r.in, sizeof im);
            ip[2 + k] += h, im[2 + k] -= h;
            ok = !s1_of(f, cam, ip, a, r.hit.obj) && !s1_of(f, cam, im, b, r.hit.obj);
            for (int j = 0; j < 3 && ok; j++) (k ? dv : du)[j] = (a[j] - b[j]) / (2 * h);
        }
        /* s1 fixed: G = cos(theta_s1) dw_s1 / dA(s0), the solid angle of the directions
         * at s1 over the sensor square, by differences of steps 1e-6 mm (1e-4 mm leaves
         * 10% truncation error through the system, near focus) and 2e-6 mm: a ray whose
         * two differences disagree by more than 1e-5 is one they cannot measure (s1 near
         * the focus of s0, where solving for the ray through s1 amplifies the solve's own
         * tolerance: 1% through some fitted systems), and is left out */
        double G_fd = 0, G_2 = 0;
        for (int m = 1; m <= 2 && ok; m++) {
            double hx = 1e-6 * m, dx[3] = {0}, dy[3] = {0};
            for (int k = 0; k < 2 && ok; k++) {
                double xp = r.in[0] + (k == 0) * hx, yp = r.in[1] + (k == 1) * hx,
                       xm = r.in[0] - (k == 0) * hx, ym = r.in[1] - (k == 1) * hx;
                ok = !ray_through(cam, r.in, xp, yp, r.hit.p, a) &&
                     !ray_through(cam, r.in, xm, ym, r.hit.p, b);
                for (int j = 0; j < 3 && ok; j++) (k ? dy : dx)[j] = (a[j] - b[j]) / (2 * hx);
            }
            double ox = dx[1] * dy[2] - dx[2] * dy[1], oy = dx[2] * dy[0] - dx[0] * dy[2],
                   oz = dx[0] * dy[1] - dx[1] * dy[0];
            *(m == 1 ? &G_fd : &G_2) = t.cos_s1 * sqrt(ox * ox + oy * oy + oz * oz);
        }
        if (!ok) continue; /* a step crossed an edge */
        double cx = du[1] * dv[2] - du[2] * dv[1], cy = du[2] * dv[0] - du[0] * dv[2],
               cz = du[0] * dv[1] - du[1] * dv[0];
        double fd = sqrt(cx * cx + cy * cy + cz * cz);
        /* p_A(s1) = p(u, v) / |d s1 / d s0'| */
        worst = fmax(worst, fabs(r.pdf / t.pA_s1 / fd - 1));
        if (!(fabs(G_fd / G_2 - 1) < 1e-5)) {
            unmeasured++;
            continue;
        }
        worst_G = fmax(worst_G, fabs(t.G / G_fd - 1));
        /* what G was when it shared p_A(s1)'s Jacobian: cos^4(theta_s0) / |d s1 / d s0'| */
        double c2 = 1 / (1 + r.in[2] * r.in[2] + r.in[3] * r.in[3]);
        worst_G_shared = fmax(worst_G_shared, fabs(c2 * c2 / fd / G_fd - 1));
        objs[r.hit.obj]++;
        checked++;
    }
    print_message("against differences, %d rays (wall %d, floor %d, sphere %d; %d left out): "
                  "p_A(s1) worst %.2g; G-bar (Eq. 12) worst %.2g (cos^4 / |d s1 / d s0'|: "
                  "%.2g)\n", checked, objs[0], objs[1], objs[2], unmeasured, worst, worst_G,
                  worst_G_shared);
    assert_true(checked >= 100 && unmeasured < checked / 10);
    assert_true(objs[0] > 0 && objs[1] > 0);
    assert_true(worst < 1e-4);
    assert_true(worst_G < 1e-4);
    return worst_G_shared;
}

static void test_factors_finite_differences(void **state)
{
    fixture *f = *state;
    factors_finite_differences(f, &f->ce);
    /* what G was when it shared p_A(s1)'s Jacobian fails this check through the system:
     * the test tells the two apart */
    assert_true(factors_finite_differences(f, &f->cp) > 1e-3);
}

/* |A| (and the supplement's d(out_x, out_y) / d(x, y) block) from the fitted system
 * against central differences of the exact tracer, on rays away from the rims. */
static void test_A_against_exact(void **state)
{
    fixture *f = *state;
    const double rays[][4] = {{0, 0, 0.05, -0.03}, {6, -4, -0.15, 0.1}, {-10, 5, 0.2, -0.12},
                              {12, 8, -0.25, -0.15}, {-3, -9, 0.08, 0.2}};
    double worst_uv = 0, worst_xy = 0;
    for (size_t k = 0; k < sizeof rays / sizeof *rays; k++) {
        double in[5] = {rays[k][0], rays[k][1], rays[k][2], rays[k][3], GLASS_D_LINE};
        double op[4], oe[4], jp[16], je[16], ep, ee;
        assert_true(f->cp.outer(f->cp.ctx, in, op, jp, &ep));
        assert_true(f->ce.outer(f->ce.ctx, in, oe, je, &ee));
        double Ap = jp[2] * jp[7] - jp[3] * jp[6], Ae = je[2] * je[7] - je[3] * je[6];
        double Xp = jp[0] * jp[5] - jp[1] * jp[4], Xe = je[0] * je[5] - je[1] * je[4];
        print_message("ray %zu: |A| poly %.5g exact %.5g; d(out)/d(x,y) poly %.5g exact %.5g\n", k,
                      Ap, Ae, Xp, Xe);
        worst_uv = fmax(worst_uv, fabs(Ap / Ae - 1));
        worst_xy = fmax(worst_xy, fabs(Xp / Xe - 1));
    }
    print_message("worst relative difference: |A| %.2g, d(x,y) block %.2g\n", worst_uv, worst_xy);
    assert_true(worst_uv < 0.03);
    /* out_x barely moves with x at fixed u (the block is ~0.25): a few % more, relatively */
    assert_true(worst_xy < 0.06);
}

/* Renders the scene with Eq. 13 and with the full estimator through cam (same seed, same
 * samples): the worst pixel difference, relative and in standard errors. */
static void images(const fixture *f, const render_camera *cam, long spp, double *worst,
                   double *worst_se)
{
    render_job a = {.scene = &f->scene, .cam = cam, .sampler = &f->smp, .use_eta = 1,
                    .spp = spp};
    render_job b = a;
    b.estimator = RENDER_ESTIMATOR_FULL;
    float ia[12 * 8 * 3], va[12 * 8 * 3], ib[12 * 8 * 3], vb[12 * 8 * 3];
    render_stats sa, sb;
    lens_err err = {{0}};
    assert_int_equal(render_image(&a, ia, va, &sa, &err), 0);
    assert_int_equal(render_image(&b, ib, vb, &sb, &err), 0);
    *worst = *worst_se = 0;
    for (int i = 0; i < 12 * 8 * 3; i++) {
        double d = fabs(ia[i] - ib[i]), se = sqrt(va[i] + vb[i]);
        *worst = fmax(*worst, d / fmax(ia[i], 1e-30));
        if (se > 0) *worst_se = fmax(*worst_se, d / se);
    }
    print_message("images: worst relative difference %.2g (%.2g standard errors); full estimator "
                  "on %.0f rays, %.0f fell back to Eq. 13\n", *worst, *worst_se, sb.full_rays,
                  sb.full_fallback);
    assert_true(sa.passed_rays == sb.passed_rays); /* same samples */
    assert_true(sb.full_fallback <= 0.01 * sb.full_rays);
}

static void test_images_agree(void **state)
{
    fixture *f = *state;
    const char *san = getenv("SANITIZE");
    long spp = san && *san ? 32 : 128;
    double worst, worst_se;
    /* the exact tracer: the same image but for the differences' rounding */
    images(f, &f->ce, spp / 4, &worst, &worst_se);
    assert_true(worst < 1e-6);
    /* the system: its weights differ by its etendue error (a few percent a ray), the
     * image within its noise */
    images(f, &f->cp, spp, &worst, &worst_se);
    assert_true(worst_se < 1);
    /* a camera without an outer-pupil Jacobian is refused */
    render_job b = {.scene = &f->scene, .cam = &f->cp, .sampler = &f->smp, .spp = 1,
                    .estimator = RENDER_ESTIMATOR_FULL};
    render_camera bare = f->cp;
    bare.outer = NULL;
    b.cam = &bare;
    lens_err err = {{0}};
    float ib[12 * 8 * 3];
    assert_int_equal(render_image(&b, ib, NULL, NULL, &err), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_weights_against_eq13),
        cmocka_unit_test(test_factors_finite_differences),
        cmocka_unit_test(test_A_against_exact),
        cmocka_unit_test(test_images_agree),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
