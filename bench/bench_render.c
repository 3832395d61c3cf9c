/* The lens part of lens-render's camera rays: ns per camera ray through the lens map,
 * exact tracing against the polynomial system lens-render fits for a grey scene (the
 * same rays: sensor points over the sensor, directions from the line pupil), on
 * lenses/dgauss.50mm.lens (36x24 sensor) and lenses/fisheye-ii.lens (23.6x15.7),
 * single thread, CPU time of this thread, median of 5 runs.
 * Prints "bench render_map_{exact,poly}_<lens>_ns_per_ray VALUE ns" (one ray a call),
 * "bench render_batch_{exact,poly}_<lens>_ns_per_ray" (cam->map_batch over blocks of
 * 512 rays, as lens-render calls it), the share of the rays that pass the line pupil,
 * and the lens part of the full estimator (--estimator full: the system's Jacobian, the
 * frames, G-bar and p_A(s1)) against the map alone.
 * Usage: bench_render [RAYS]   (default 200000; from the repository root) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sparselens/glass.h"
#include "sparselens/lens.h"
#include "sparselens/render.h"
#include "sparselens/render_effects.h"
#include "sparselens/render_lens.h"
#include "sparselens/scene.h"
#include "sparselens/trace.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* median ns per ray of cam->map over the rays; *passed gets the share that pass */
static double time_map(const render_camera *cam, const double *rays, size_t n, double *passed)
{
    double t[5];
    long pass = 0;
    for (int rep = 0; rep < 5; rep++) {
        double o[3], d[3], eta, t0 = now();
        pass = 0;
        for (size_t i = 0; i < n; i++) pass += cam->map(cam->ctx, rays + 5 * i, o, d, &eta);
        t[rep] = (now() - t0) / n * 1e9;
    }
    qsort(t, 5, sizeof *t, cmp);
    *passed = (double)pass / n;
    return t[2];
}

/* median ns per ray of cam->map_batch over blocks of 512 rays */
static double time_batch(const render_camera *cam, const double *rays, size_t n)
{
    enum { B = 512 };
    static double o[B * 3], d[B * 3], eta[B];
    static unsigned char pass[B];
    double t[5];
    for (int rep = 0; rep < 5; rep++) {
        double t0 = now();
        for (size_t i = 0; i < n; i += B)
            cam->map_batch(cam->ctx, n - i < B ? n - i : B, rays + 5 * i, o, d, eta, pass);
        t[rep] = (now() - t0) / n * 1e9;
    }
    qsort(t, 5, sizeof *t, cmp);
    return t[2];
}

/* median ns per ray of the full estimator's lens part: cam->outer with the Jacobian, the
 * ray, and render_full_weight for a hit on the plane 1 m in front of the lens (scene
 * frame z = 1000, facing the lens) */
static double time_full(const render_camera *cam, const double *rays, size_t n)
{
    double t[5], sink = 0;
    for (int rep = 0; rep < 5; rep++) {
        double t0 = now();
        for (size_t i = 0; i < n; i++) {
            double o[4], jac[16], eta, os[3], ds[3];
            const double *in = rays + 5 * i;
            lens_ray r;
            if (!cam->outer(cam->ctx, in, o, jac, &eta) || ray_from_outer(cam->lens, o, &r)) continue;
            render_lens_to_scene(r.o, os);
            render_lens_to_scene(r.d, ds);
            if (!(ds[2] > 0)) continue;
            double tau = (1000 - os[2]) / ds[2], s1[3] = {os[0] + tau * ds[0], os[1] + tau * ds[1], 1000},
                   n1[3] = {0, 0, -1};
            render_full_terms ft;
            if (render_full_weight(cam->lens, in, o, jac, 1, eta, s1, n1, &ft) == 0) sink += ft.weight;
        }
        t[rep] = (now() - t0) / n * 1e9;
    }
    qsort(t, 5, sizeof *t, cmp);
    if (sink == 42) printf("#\n"); /* keep the loop */
    return t[2];
}

static int run(const char *name, const char *path, double sw, double sh, size_t n)
{
    lens_t lens;
    lens_err err;
    lens_init(&lens);
    if (lens_load(path, NULL, &lens, &err)) {
        fprintf(stderr, "bench_render: %s\n", err.msg);
        return 1;
    }
    scene_t s;
    if (scene_parse("camera x\nresolution 240 160\nmode grey\nplane 0 0 1000 0 0 -1 emit 1\n",
                    "bench.scene", &s, &err)) {
        fprintf(stderr, "bench_render: %s\n", err.msg);
        return 1;
    }
    render_effects e;
    double fit_s;
    poly_system *sys = NULL;
    render_camera ce, cp;
    render_lens_ctx *le = NULL, *lp = NULL;
    render_sampler smp = {0};
    double *rays = malloc(n * 5 * sizeof *rays);
    int rc = 1;
    if (!rays || render_effects_decide(&s, &lens, sw, sh, &e, &err) ||
        !(sys = render_fit(&lens, &e, 0, &fit_s, &err)) ||
        !(le = render_lens_exact(&lens, sw, sh, &ce, &err)) ||
        !(lp = render_lens_poly(sys, &lens, sw, sh, &cp, &err)) ||
        render_sampler_lens(&smp, &lens, GLASS_D_LINE, GLASS_D_LINE, hypot(sw, sh) / 2, 0, &err)) {
        fprintf(stderr, "bench_render: %s\n", rays ? err.msg : "out of memory");
        goto done;
    }
    unsigned long long st = 7;
    size_t k = 0;
    while (k < n) {
        double r[4];
        for (int j = 0; j < 4; j++) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            r[j] = (st >> 11) * 0x1.0p-53;
        }
        double x = (r[0] - 0.5) * sw, y = (r[1] - 0.5) * sh, *row = rays + 5 * k;
        if (!(render_sampler_sample(&smp, x, y, r[2], r[3], &row[2], &row[3]) > 0)) continue;
        row[0] = x, row[1] = y, row[4] = GLASS_D_LINE;
        k++;
    }
    double pe, pp;
    double te = time_map(&ce, rays, n, &pe), tp = time_map(&cp, rays, n, &pp);
    printf("bench render_map_exact_%s_ns_per_ray %.1f ns\n", name, te);
    printf("bench render_map_poly_%s_ns_per_ray %.1f ns\n", name, tp);
    printf("bench render_map_speedup_%s %.2f x\n", name, te / tp);
    double tbe = time_batch(&ce, rays, n), tbp = time_batch(&cp, rays, n);
    printf("bench render_batch_exact_%s_ns_per_ray %.1f ns\n", name, tbe);
    printf("bench render_batch_poly_%s_ns_per_ray %.1f ns\n", name, tbp);
    printf("bench render_batch_speedup_%s %.2f x\n", name, tbe / tbp);
    printf("bench render_line_pupil_pass_%s %.1f %%\n", name, 100 * pe);
    double tf = time_full(&cp, rays, n);
    printf("bench render_full_estimator_poly_%s_ns_per_ray %.1f ns\n", name, tf);
    printf("bench render_full_over_eq13_poly_%s %.2f x\n", name, tf / tp);
    rc = 0;
done:
    free(rays);
    render_sampler_free(&smp);
    render_lens_free(le);
    render_lens_free(lp);
    poly_free(sys);
    scene_free(&s);
    lens_free(&lens);
    return rc;
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? (size_t)atol(argv[1]) : 200000;
    if (n < 1) n = 1;
    int rc = run("dgauss", "lenses/dgauss.50mm.lens", 36, 24, n);
    rc |= run("fisheye-ii", "lenses/fisheye-ii.lens", 23.6, 15.7, n);
    return rc;
}
