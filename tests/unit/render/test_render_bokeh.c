/* The cat's eye: a small bright sphere far out of focus through fisheye-ii
 * (focused at 25 mm, the sphere at 500 mm) renders as a round disk at the centre of the
 * picture and, towards the corner, as a disk clipped by the front group: narrower along
 * the radius than across it.
 *
 * The independent reference is the light's own path: rays from points on the sphere's
 * silhouette, uniform in solid angle towards the front element, traced forwards through
 * the lens (trace_to_sensor, the tracer's other direction) to the sensor. Their hits,
 * weighted by the transmittance, are the sphere's picture in geometric optics; its
 * centroid and second moments along the radius and across it must match the rendered
 * image's (camera rays, line pupil, Eq. 13) within a few percent. The shape itself is
 * asserted from symmetry and from vignetting: round at the centre (the two moments
 * equal), and at the corner the radial width clearly below the tangential one and below
 * the centre disk's. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sparselens/glass.h"
#include "sparselens/render.h"
#include "sparselens/render_lens.h"
#include "sparselens/scene.h"
#include "sparselens/aim.h"
#include "sparselens/trace.h"

#define SW 23.6
#define SH 15.7
#define RES_X 472 /* 0.05 mm pixels */
#define RES_Y 314
#define WIN 40    /* window around a bokeh, pixels */
#define DIST 500.0
#define RADIUS 10.0
#define CONE atan(5.0 / DIST) /* half-angle of the light-traced cone */

typedef struct {
    double cx, cy;   /* centroid, mm */
    double sr, st;   /* standard deviations along the radius and across it, mm */
} moments;

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double u01(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

/* weighted second moments about the centroid, along er = (ex, ey) and across it */
typedef struct {
    double w, x, y, xx, xy, yy;
} acc;

static void add(acc *a, double x, double y, double w)
{
    a->w += w, a->x += w * x, a->y += w * y;
    a->xx += w * x * x, a->xy += w * x * y, a->yy += w * y * y;
}

static moments finish(const acc *a, double ex, double ey)
{
    moments m;
    m.cx = a->x / a->w, m.cy = a->y / a->w;
    double vxx = a->xx / a->w - m.cx * m.cx, vyy = a->yy / a->w - m.cy * m.cy,
           vxy = a->xy / a->w - m.cx * m.cy;
    m.sr = sqrt(ex * ex * vxx + 2 * ex * ey * vxy + ey * ey * vyy);
    m.st = sqrt(ey * ey * vxx - 2 * ex * ey * vxy + ex * ex * vyy);
    return m;
}

/* The sphere whose chief ray lands on sensor point (sx, sy): lens-frame centre. */
static void place(const lens_t *lens, const double *n, double sx, double sy, double P[3],
                  double dir[3], double F[3])
{
    double u, v;
    assert_int_equal(aim_from_sensor(lens, n, sx, sy, 0, 0, &u, &v), 0);
    double in[4] = {sx, sy, u, v};
    lens_ray r;
    ray_from_sensor(lens, in, &r);
    assert_int_equal(trace_to_object(lens, n, &r, 0).status, TRACE_PASSED);
    for (int k = 0; k < 3; k++) P[k] = r.o[k] + DIST * r.d[k], dir[k] = r.d[k], F[k] = r.o[k];
}

/* Light traced from the silhouette disk (radius RADIUS, facing the lens) to the sensor. */
static moments light_traced(const lens_t *lens, const double *n, const double P[3],
                            const double dir[3], const double F[3], double ex, double ey,
                            int rays)
{
    /* a frame (a, b) across the view direction; the cone towards the front element */
    double a[3] = {dir[1], -dir[0], 0}, la = hypot(a[0], a[1]);
    if (la < 1e-9) a[0] = 1, a[1] = 0, la = 1;
    a[0] /= la, a[1] /= la;
    double b[3] = {dir[1] * a[2] - dir[2] * a[1], dir[2] * a[0] - dir[0] * a[2],
                   dir[0] * a[1] - dir[1] * a[0]};
    acc m = {0};
    int hits = 0, rim = 0;
    uint64_t st = 42;
    for (int i = 0; i < rays; i++) {
        double rr = RADIUS * sqrt(u01(&st)), ph = 2 * M_PI * u01(&st);
        double o[3], d[3];
        for (int k = 0; k < 3; k++) o[k] = P[k] + rr * (cos(ph) * a[k] + sin(ph) * b[k]);
        /* uniform in solid angle inside a cone from o towards F, where the chief ray (to
         * the stop's centre) meets the front element, wide enough for the entrance
         * pupil: no ray may pass in its outer fifth (asserted below), so none outside it
         * is missed */
        double to[3] = {F[0] - o[0], F[1] - o[1], F[2] - o[2]}, lt = sqrt(dot(to, to));
        for (int k = 0; k < 3; k++) to[k] /= lt;
        double cmax = cos(CONE), c = 1 - u01(&st) * (1 - cmax), s = sqrt(1 - c * c),
               q = 2 * M_PI * u01(&st);
        double p1[3] = {to[1], -to[0], 0}, l1 = hypot(p1[0], p1[1]);
        if (l1 < 1e-12) p1[0] = 1, p1[1] = 0, l1 = 1;
        p1[0] /= l1, p1[1] /= l1;
        double p2[3] = {to[1] * p1[2] - to[2] * p1[1], to[2] * p1[0] - to[0] * p1[2],
                        to[0] * p1[1] - to[1] * p1[0]};
        for (int k = 0; k < 3; k++) d[k] = c * to[k] + s * (cos(q) * p1[k] + sin(q) * p2[k]);
        lens_ray r = {{o[0], o[1], o[2]}, {d[0], d[1], d[2]}};
        trace_result res = trace_to_sensor(lens, n, &r);
        if (res.status != TRACE_PASSED) continue;
        add(&m, r.o[0], r.o[1], res.transmittance);
        hits++;
        rim += acos(c) > 0.8 * CONE;
    }
    print_message("light traced: %d of %d rays reach the sensor\n", hits, rays);
    assert_int_equal(rim, 0);
    return finish(&m, ex, ey);
}

/* The renderer's picture of the same sphere in a window around (sx, sy). */
static moments rendered(const lens_t *lens, const render_sampler *smp, const double P[3],
                        double sx, double sy, double ex, double ey, long spp)
{
    double Ps[3];
    render_lens_to_scene(P, Ps);
    char text[256];
    snprintf(text, sizeof text, "camera a.lens\nresolution %d %d\nmode grey\nseed %d\n"
             "sphere %.9g %.9g %.9g %g emit 1\n", RES_X, RES_Y, getenv("BOKEH_SEED") ? atoi(getenv("BOKEH_SEED")) : 9, Ps[0], Ps[1], Ps[2], RADIUS);
    scene_t s;
    lens_err err = {{0}};
    assert_int_equal(scene_parse(text, "t.scene", &s, &err), 0);
    render_camera cam;
    render_lens_ctx *lc = render_lens_exact(lens, SW, SH, &cam, &err);
    assert_non_null(lc);
    int px = (int)((sx / SW + 0.5) * RES_X), py = (int)((sy / SH + 0.5) * RES_Y);
    render_job job = {.scene = &s, .cam = &cam, .sampler = smp, .use_eta = 1, .spp = spp,
                      .x0 = px - WIN / 2, .x1 = px + WIN / 2, .y0 = py - WIN / 2, .y1 = py + WIN / 2};
    float *img = malloc((size_t)RES_X * RES_Y * 3 * sizeof *img);
    assert_non_null(img);
    assert_int_equal(render_image(&job, img, NULL, NULL, &err), 0);
    acc m = {0};
    int edge = 0;
    for (int y = job.y0; y < job.y1; y++)
        for (int x = job.x0; x < job.x1; x++) {
            double w = img[3 * ((size_t)y * RES_X + x)];
            if (w > 0 && (x == job.x0 || y == job.y0 || x == job.x1 - 1 || y == job.y1 - 1)) edge++;
            add(&m, ((x + 0.5) / RES_X - 0.5) * SW, ((y + 0.5) / RES_Y - 0.5) * SH, w);
        }
    assert_int_equal(edge, 0); /* the window holds the whole picture */
    free(img);
    render_lens_free(lc);
    scene_free(&s);
    return finish(&m, ex, ey);
}

static void test_cats_eye(void **state)
{
    (void)state;
    lens_t lens;
    lens_err err = {{0}};
    if (lens_load("lenses/fisheye-ii.lens", NULL, &lens, &err)) fail_msg("%s", err.msg);
    assert_int_equal(render_lens_setup(&lens, 25, NAN, &err), 0);
    double n[lens.nsurf];
    assert_int_equal(lens_indices(&lens, GLASS_D_LINE, n, &err), 0);
    render_sampler smp;
    assert_int_equal(render_sampler_lens(&smp, &lens, GLASS_D_LINE, GLASS_D_LINE,
                                         0.5 * hypot(SW, SH), 0, &err), 0);
    const char *san = getenv("SANITIZE");
    int sanitized = san && *san;
    long spp = getenv("BOKEH_SPP") ? atol(getenv("BOKEH_SPP")) : sanitized ? 48 : 128;
    int rays = getenv("BOKEH_RAYS") ? atoi(getenv("BOKEH_RAYS")) : sanitized ? 40000 : 200000;
    /* the centre, and 85% of the way to the corner along the diagonal */
    double rc = 0.85 * 0.5 * hypot(SW, SH), ang = atan2(SH, SW);
    const double pts[2][2] = {{0, 0}, {rc * cos(ang), rc * sin(ang)}};
    moments mr[2], ml[2];
    for (int k = 0; k < 2; k++) {
        double ex = k ? cos(ang) : 1, ey = k ? sin(ang) : 0, P[3], dir[3], F[3];
        place(&lens, n, pts[k][0], pts[k][1], P, dir, F);
        mr[k] = rendered(&lens, &smp, P, pts[k][0], pts[k][1], ex, ey, spp);
        ml[k] = light_traced(&lens, n, P, dir, F, ex, ey, rays);
        print_message("%s: rendered centroid (%.3f, %.3f) sd radial %.4f tangential %.4f mm; "
                      "light traced (%.3f, %.3f) %.4f %.4f mm\n", k ? "corner" : "centre",
                      mr[k].cx, mr[k].cy, mr[k].sr, mr[k].st, ml[k].cx, ml[k].cy, ml[k].sr, ml[k].st);
        /* the renderer against the light's own path */
        /* (tolerances: about three times the scatter over seeds, 1-2% at 128 spp) */
        double tol = sanitized ? 0.12 : 0.06;
        assert_true(hypot(mr[k].cx - ml[k].cx, mr[k].cy - ml[k].cy) < 2 * tol * ml[k].st);
        assert_true(fabs(mr[k].sr / ml[k].sr - 1) < tol);
        assert_true(fabs(mr[k].st / ml[k].st - 1) < tol);
    }
    /* round at the centre; a cat's eye at the corner */
    assert_true(fabs(mr[0].sr / mr[0].st - 1) < (sanitized ? 0.08 : 0.03));
    assert_true(mr[1].sr < 0.8 * mr[1].st);
    assert_true(mr[1].sr < 0.8 * mr[0].sr);
    render_sampler_free(&smp);
    lens_free(&lens);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_cats_eye)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
