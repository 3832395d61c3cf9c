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
 * Then the parts of a camera sample that the polynomial and the exact path share, on
 * scenes/dgauss.scene and scenes/fisheye.scene as lens-render renders them (16 spp keys):
 * "bench render_shared_<scene>_<part>_ns_per_sample", per camera sample: the
 * low-discrepancy draws (five, a pixel's run of 16 at a time), the line pupil's draw, the
 * camera ray's scene intersection (blocks of 512, scene_intersect_camera_many), and at
 * the hits that are not emitters (their share of the samples given) the albedo and the
 * direct light (a light sample, a shadow ray, a BSDF ray: scene_direct_mis_many over
 * blocks of 512 hits, as lens-render, and scene_direct_mis one point at a time,
 * "direct_light_one"), and the direct light's two rays alone. What lens-render spends
 * besides these and the lens map is its loop.
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
#include "render/render_math.h"
#include "render/render_samples.h"
#include "render/scene_camera_block.h"
#include "render/scene_light_block.h"
#include "render/scene_light_simd.h"

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

/* Seconds (best of 3) for the direct light's two rays alone at the nd lit hits with
 * uniforms u (5 a hit): a shadow ray to a point drawn on an emitter by area, the emitter
 * chosen in proportion to its luminance times area over distance squared (the
 * estimator's choice less its cosines; the ray's test is the same whatever drew it), and
 * a cosine-weighted BSDF ray to the emitters; in AVX-512 lanes where lens-render uses
 * them (scene_simd_visible, scene_simd_emitter). */
static void light_rays(const scene_t *sc, const scene_hit *hit, size_t nd, const double *u,
                       double *t_shadow, double *t_bsdf)
{
    double *q = malloc((nd + 1) * 3 * sizeof *q), *w = malloc((nd + 1) * 3 * sizeof *w), sink = 0;
    *t_shadow = *t_bsdf = INFINITY;
    for (size_t i = 0; q && w && i < nd; i++) { /* the rays, made beforehand */
        const double *ui = u + 5 * i;
        double sel[64], total = 0, nl[3], pdf, t[3], b[3], sn, cs;
        int idx[64], ne = 0;
        for (size_t o = 0; o < sc->nobj && ne < 64; o++) {
            const scene_object *ob = &sc->obj[o];
            if (!ob->emitter || ob->kind == OBJ_PLANE) continue;
            double c[3] = {ob->p[0] - hit[i].p[0], ob->p[1] - hit[i].p[1], ob->p[2] - hit[i].p[2]};
            total += sel[ne] = ob->lum * ob->r2 / (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
            idx[ne++] = (int)o;
        }
        int j = 0;
        for (double x = ui[0] * total; j + 1 < ne && x >= sel[j]; j++) x -= sel[j];
        scene_sample_emitter(sc, ne ? idx[j] : 0, ui[1], ui[2], q + 3 * i, nl, &pdf);
        rm_frame(hit[i].n, t, b);
        rm_sincos_turn(ui[4], &sn, &cs);
        double r = sqrt(ui[3]), ct = sqrt(1 - ui[3]);
        for (int k = 0; k < 3; k++) w[3 * i + k] = ct * hit[i].n[k] + r * (cs * t[k] + sn * b[k]);
    }
    /* as lens-render traces them: eight rays a step where it can (the kernels on arrays
     * of coordinates, nd rounded up to 8), else one by one */
    size_t n8 = (nd + 7) / 8 * 8;
    double *A = malloc(3 * n8 * sizeof *A), *Q = malloc(3 * n8 * sizeof *Q);
    double *W = malloc(3 * n8 * sizeof *W), *tb = malloc(n8 * sizeof *tb);
    int *which = malloc(n8 * sizeof *which);
    unsigned char *vis = malloc(n8);
    int lanes = SCENE_SIMD && scene_simd_ok() && A && Q && W && tb && which && vis && nd;
    for (size_t i = 0; lanes && i < n8; i++)
        for (int k = 0; k < 3; k++) {
            size_t l = i < nd ? i : 0;
            A[k * n8 + i] = hit[l].p[k], Q[k * n8 + i] = q[3 * l + k], W[k * n8 + i] = w[3 * l + k];
        }
    for (int rep = 0; q && w && rep < 3; rep++) {
        double t0 = now();
#if SCENE_SIMD
        if (lanes) scene_simd_visible(sc, (int)n8, (int)n8, A, Q, vis), sink += vis[0];
#endif
        for (size_t i = 0; !lanes && i < nd; i++) sink += scene_visible(sc, hit[i].p, q + 3 * i);
        *t_shadow = fmin(*t_shadow, now() - t0);
        t0 = now();
#if SCENE_SIMD
        if (lanes) scene_simd_emitter(sc, (int)n8, (int)n8, A, W, which, tb), sink += which[0];
#endif
        for (size_t i = 0; !lanes && i < nd; i++) {
            scene_hit g;
            sink += scene_intersect_emitter(sc, hit[i].p, w + 3 * i, 1e-6, &g);
        }
        *t_bsdf = fmin(*t_bsdf, now() - t0);
    }
    free(A), free(Q), free(W), free(tb), free(which), free(vis);
    if (sink == 0.5) printf("#\n"); /* keep the loops */
    free(q);
    free(w);
}

/* Seconds (best of 3) to draw n samples' five numbers as lens-render does, a pixel's run
 * of spp at a time (ld_2d_run, ld_1d_run): pixel and pupil, and the light's three
 * (select, light, BSDF), made into camera inputs in (x y u v and a sum kept alive);
 * INFINITY without memory. */
static double time_draws(size_t n, long spp, double sw, double sh, double *in)
{
    double *dr = malloc((n + spp) * 9 * sizeof *dr), t0, best = INFINITY;
    ld_pixel key;
    for (int rep = 0; dr && rep < 3; rep++, best = fmin(best, now() - t0))
    for (size_t i = (t0 = now(), 0); i < n; i += spp) {
        int run = n - i < (size_t)spp ? (int)(n - i) : (int)spp;
        double *d = dr + 9 * i;
        ld_pixel_init(&key, ld_pixel_key(1, i / spp));
        ld_2d_run(&key, 0, spp, 0, run, d, 9);
        ld_2d_run(&key, 1, spp, 0, run, d + 2, 9);
        ld_1d_run(&key, 1, spp, 0, run, d + 4, 9);
        ld_2d_run(&key, 2, spp, 0, run, d + 5, 9);
        ld_2d_run(&key, 3, spp, 0, run, d + 7, 9);
        for (int c = 0; c < run; c++) {
            const double *e = d + 9 * c;
            double *r = in + 5 * (i + c);
            r[0] = (e[0] - 0.5) * sw, r[1] = (e[1] - 0.5) * sh, r[2] = e[2], r[3] = e[3];
            r[4] = e[4] + e[5] + e[8];
        }
    }
    free(dr);
    return best;
}

/* Seconds (best of 3) for the camera rays (org, dir in the lens's frame; those with
 * pdf > 0 that pass) to meet the scene in blocks of 512 samples, as lens-render: the
 * rays near the lens together (scene_intersect_camera_many). The hits into hit, their
 * count into nh; INFINITY without memory. */
static double time_hits(const scene_t *sc, const scene_cull *cull, double rho, size_t n,
                        const double *org, const double *dir, const double *pdf,
                        const unsigned char *pass, scene_hit *hit, size_t *nh)
{
    double *os = malloc(512 * 3 * sizeof *os), *ds = malloc(512 * 3 * sizeof *ds), t0;
    unsigned char *ok = malloc(512);
    double best = INFINITY;
    for (int rep = 0; os && ds && ok && rep < 3; rep++, best = fmin(best, now() - t0))
    for (size_t i0 = (t0 = now(), *nh = 0); i0 < n; i0 += 512) {
        size_t e = n - i0 < 512 ? n : i0 + 512, m = 0;
        for (size_t i = i0; i < e; i++) {
            if (!(pdf[i] > 0) || !pass[i]) continue;
            render_lens_to_scene(org + 3 * i, os + 3 * m);
            render_lens_to_scene(dir + 3 * i, ds + 3 * m);
            const double *o = os + 3 * m;
            if (o[0] * o[0] + o[1] * o[1] + o[2] * o[2] <= rho * rho) m++;
            else *nh += scene_intersect(sc, o, ds + 3 * m, 1e-6, INFINITY, &hit[*nh]);
        }
        scene_intersect_camera_many(sc, cull, (int)m, os, ds, 1e-6, hit + *nh, ok);
        for (size_t k = 0, h0 = *nh; k < m; k++)
            if (ok[k]) hit[(*nh)++] = hit[h0 + k];
    }
    free(os), free(ds), free(ok);
    return best;
}

/* Seconds (best of 3) for the direct light at the nd lit hits with uniforms u: the
 * block's lit hits at once (scene_direct_mis_many over 512, as lens-render), and one
 * point at a time (scene_direct_mis). */
static void time_direct(const scene_t *sc, const scene_hit *hit, size_t nd, const double *u,
                        double *t_block, double *t_one)
{
    scene_light_terms *lt = malloc(512 * sizeof *lt);
    double t0, sink = 0;
    *t_block = *t_one = INFINITY;
    for (int rep = 0; lt && rep < 3; rep++, *t_block = fmin(*t_block, now() - t0))
    for (size_t i = (t0 = now(), 0); i < nd; i += 512) {
        int m = nd - i < 512 ? (int)(nd - i) : 512;
        scene_direct_mis_many(sc, m, hit + i, u + 5 * i, lt);
        sink += lt[0].n;
    }
    for (int rep = 0; lt && rep < 3; rep++, *t_one = fmin(*t_one, now() - t0))
    for (size_t i = (t0 = now(), 0); i < nd; i++) {
        scene_direct_mis(sc, &hit[i], u + 5 * i, lt);
        sink += lt[0].n;
    }
    if (sink == 0.5) printf("#\n"); /* keep the loops */
    free(lt);
}

/* ns per call of each shared part (see the head of the file), over n camera samples */
static int shared_parts(const char *name, const char *path, size_t n)
{
    scene_t sc;
    lens_t lens;
    lens_err err;
    lens_init(&lens);
    render_camera ce;
    render_lens_ctx *le = NULL;
    render_sampler smp = {0};
    scene_cull *cull = NULL;
    double *in = malloc(n * 5 * sizeof *in), *pdf = malloc(n * sizeof *pdf);
    double *cam_in = malloc(n * 5 * sizeof *cam_in);
    scene_hit *hit = malloc(n * sizeof *hit);
    int rc = 1;
    if (scene_load(path, &sc, &err)) {
        fprintf(stderr, "bench_render: %s\n", err.msg);
        free(in), free(cam_in), free(pdf), free(hit);
        return 1;
    }
    double sw = sc.sensor_w, sh = sc.sensor_h;
    if (!in || !cam_in || !pdf || !hit || lens_load(sc.camera, NULL, &lens, &err) ||
        render_lens_setup(&lens, sc.focus, sc.fstop, &err) ||
        !(le = render_lens_exact(&lens, sw, sh, &ce, &err)) ||
        render_sampler_lens(&smp, &lens, GLASS_D_LINE, GLASS_D_LINE, hypot(sw, sh) / 2, 0, &err)) {
        fprintf(stderr, "bench_render: %s\n", err.msg);
        goto done;
    }
    /* lens-render's: the front element's rim, widened by a tenth */
    const lens_surface *f = &lens.surf[0];
    double rho = 1.1 * (fabs(lens.vertex_z[0]) +
                        hypot(f->semi_diameter, lens_sag(f, f->semi_diameter * f->semi_diameter)));
    cull = scene_cull_new(&sc, rho);
    const long spp = 16;
    double t0, t_ld, t_ps, t_cam, t_alb, t_mis, sink = 0;
    ld_pixel key;
    /* each timed loop runs three times (the outer loop's step keeps the best) */
    t_ld = t_ps = t_cam = t_alb = t_mis = INFINITY;
    t_ld = time_draws(n, spp, sw, sh, in);
    if (!(t_ld < INFINITY)) goto done;
    for (int rep = 0; rep < 3; rep++, t_ps = fmin(t_ps, now() - t0))
    for (size_t i = (t0 = now(), 0); i < n; i++) {
        const double *r = in + 5 * i;
        double *c = cam_in + 5 * i;
        pdf[i] = render_sampler_sample_2d(&smp, r[0], r[1], r[2], r[3], &c[2], &c[3]);
        c[0] = r[0], c[1] = r[1], c[4] = GLASS_D_LINE;
    }
    /* the camera rays (exact: the geometry the system approximates) */
    size_t nh = 0, nd = 0;
    double *org = malloc(n * 3 * sizeof *org), *dir = malloc(n * 3 * sizeof *dir);
    double *eta = malloc(n * sizeof *eta);
    unsigned char *pass = malloc(n);
    if (!org || !dir || !eta || !pass) goto done_rays;
    ce.map_batch(ce.ctx, n, cam_in, org, dir, eta, pass);
    t_cam = time_hits(&sc, cull, rho, n, org, dir, pdf, pass, hit, &nh);
    if (!(t_cam < INFINITY)) goto done_rays;
    for (int rep = 0; rep < 3; rep++, t_alb = fmin(t_alb, now() - t0))
    for (size_t i = (t0 = now(), 0); i < nh; i++) {
        double alb[3];
        scene_albedo(&sc, hit[i].obj, hit[i].p, alb);
        sink += alb[0];
    }
    /* the direct light's uniforms, drawn beforehand (timed above) */
    for (size_t i = 0; i < nh; i++) {
        if (scene_is_emitter(&sc.obj[hit[i].obj])) continue;
        if (i % spp == 0 || nd == 0) ld_pixel_init(&key, ld_pixel_key(2, i / spp));
        double *u = in + 5 * nd, l2[2], b2[2];
        ld_2d_px(&key, 2, spp, i % spp, l2);
        ld_2d_px(&key, 3, spp, i % spp, b2);
        u[0] = ld_1d_px(&key, 1, spp, i % spp), u[1] = l2[0], u[2] = l2[1], u[3] = b2[0], u[4] = b2[1];
        hit[nd++] = hit[i];
    }
    double t_one;
    time_direct(&sc, hit, nd, in, &t_mis, &t_one);
    if (sink == 42) printf("#\n");
    printf("bench render_shared_%s_draws_ns_per_sample %.1f ns\n", name, t_ld / n * 1e9);
    printf("bench render_shared_%s_line_pupil_ns_per_sample %.1f ns\n", name, t_ps / n * 1e9);
    printf("bench render_shared_%s_camera_hit_ns_per_sample %.1f ns\n", name, t_cam / n * 1e9);
    printf("bench render_shared_%s_albedo_ns_per_sample %.1f ns\n", name, t_alb / n * 1e9);
    printf("bench render_shared_%s_direct_light_ns_per_sample %.1f ns\n", name, t_mis / n * 1e9);
    printf("bench render_shared_%s_direct_light_one_ns_per_sample %.1f ns\n", name, t_one / n * 1e9);
    double t_sh, t_bs;
    light_rays(&sc, hit, nd, in, &t_sh, &t_bs);
    printf("bench render_shared_%s_shadow_ray_ns_per_sample %.1f ns\n", name, t_sh / n * 1e9);
    printf("bench render_shared_%s_bsdf_ray_ns_per_sample %.1f ns\n", name, t_bs / n * 1e9);
    printf("bench render_shared_%s_lit_share %.1f %%\n", name, 100.0 * nd / n);
    rc = 0;
done_rays:
    free(org), free(dir), free(eta), free(pass);
done:
    free(in), free(cam_in), free(pdf), free(hit);
    scene_cull_free(cull);
    render_sampler_free(&smp);
    render_lens_free(le);
    scene_free(&sc);
    lens_free(&lens);
    return rc;
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? (size_t)atol(argv[1]) : 200000;
    if (n < 1) n = 1;
    int rc = run("dgauss", "lenses/dgauss.50mm.lens", 36, 24, n);
    rc |= run("fisheye-ii", "lenses/fisheye-ii.lens", 23.6, 15.7, n);
    rc |= shared_parts("dgauss", "scenes/dgauss.scene", n);
    rc |= shared_parts("fisheye", "scenes/fisheye.scene", n);
    return rc;
}
