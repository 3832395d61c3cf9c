/* Ray aiming: the ray from a sensor point, or from an object direction or point, that
 * crosses the stop surface at a given point.
 *
 * Two unknowns, two equations (the stop hit's x and y): Newton's method with a
 * finite-difference Jacobian and step halving. The traces inside it extend every
 * surface beyond its semi-diameter (clip = 0) so that the map is smooth; whether the
 * aimed ray is vignetted is for the caller to find out by tracing it. */
#include <math.h>

#include "sparselens/aim.h"
#include "sparselens/trace.h"
#include "trace/trace_core.h"

/* Builds the start ray for parameters (a, b); returns 0 when it is defined. */
typedef int (*ray_builder)(const void *ctx, double a, double b, lens_ray *r);

typedef struct {
    const lens_t *lens;
    const double *n;
    int first, last; /* trace from first to last (the stop) */
    double sx, sy;
    ray_builder build;
    const void *ctx;
    long *budget; /* traces left for this ray, or NULL: no bound */
} aim_problem;

/* Traces one object-space ray may take to be aimed from the stop centre. On the 18
 * shipped lenses every ray that can be aimed is found within 43 traces (10 on average);
 * a stop point no ray reaches (a stop wider than the beam the other surfaces can form,
 * as on fisheye-ii at its computed f/1.75) used to cost about 6000 traces of step
 * halving and shrinking continuation steps before giving up, 99 % of lens-spot's time
 * on such lenses. */
#define AIM_OBJECT_BUDGET 600

/* Residual of the stop hit; 0 when the ray reaches the stop surface. */
static int residual(const aim_problem *p, double a, double b, double f[2])
{
    lens_ray r;
    if (p->budget && --*p->budget < 0)
        return -1;
    if (p->build(p->ctx, a, b, &r))
        return -1;
    trace_result res = trace_path(p->lens, p->n, &r, p->first, p->last, 0, 0);
    if (res.status != TRACE_PASSED)
        return -1;
    f[0] = r.o[0] - p->sx;
    f[1] = r.o[1] - p->sy;
    return 0;
}

/* Newton from (a, b); scale is the size of a typical step in the parameters. */
static int newton(const aim_problem *p, double *a, double *b, double scale, double tol)
{
    double f[2];
    if (residual(p, *a, *b, f))
        return -1;
    double norm = hypot(f[0], f[1]);
    for (int it = 0; it < 60; it++) {
        if (norm <= tol)
            return 0;
        /* forward differences, backward where the forward ray does not get through */
        double h = 1e-7 * scale, hb = h, fa[2], fb[2];
        if (residual(p, *a + h, *b, fa)) {
            h = -h;
            if (residual(p, *a + h, *b, fa))
                return -1;
        }
        if (residual(p, *a, *b + hb, fb)) {
            hb = -hb;
            if (residual(p, *a, *b + hb, fb))
                return -1;
        }
        double j00 = (fa[0] - f[0]) / h, j10 = (fa[1] - f[1]) / h;
        double j01 = (fb[0] - f[0]) / hb, j11 = (fb[1] - f[1]) / hb;
        double det = j00 * j11 - j01 * j10;
        if (!(fabs(det) > 0) || !isfinite(det))
            return -1;
        double da = -(j11 * f[0] - j01 * f[1]) / det;
        double db = -(-j10 * f[0] + j00 * f[1]) / det;
        double lam = 1;
        int improved = 0;
        for (int k = 0; k < 40; k++, lam *= 0.5) {
            double g[2];
            if (!residual(p, *a + lam * da, *b + lam * db, g) && hypot(g[0], g[1]) < norm) {
                *a += lam * da;
                *b += lam * db;
                f[0] = g[0];
                f[1] = g[1];
                norm = hypot(g[0], g[1]);
                improved = 1;
                break;
            }
        }
        if (!improved)
            return norm <= 100 * tol ? 0 : -1;
    }
    return norm <= tol ? 0 : -1;
}

/* From a solution for the stop centre to one for (sx, sy): the target moves out in
 * steps that shrink when Newton fails to follow, so that strongly curved rear groups
 * (where a far start leaves the surfaces' domains) are still solved. */
static int continuation(aim_problem *p, double sx, double sy, double *a, double *b,
                        double scale)
{
    double t = 0, dt = 1;
    while (t < 1) {
        double tn = fmin(1, t + dt), a1 = *a, b1 = *b;
        p->sx = tn * sx;
        p->sy = tn * sy;
        if (p->budget && *p->budget < 0)
            return -1;
        if (newton(p, &a1, &b1, scale, 1e-10 * (1 + hypot(sx, sy) + p->lens->surf[p->lens->stop].semi_diameter)) == 0) {
            *a = a1;
            *b = b1;
            t = tn;
            dt *= 2;
        } else if ((dt *= 0.25) < 1e-4) {
            return -1;
        }
    }
    return 0;
}

/* The stop semi-diameter sets the scale of positions; aim to 1e-10 of it. */
static double tolerance(const lens_t *lens)
{
    return 1e-10 * (1 + lens->surf[lens->stop].semi_diameter);
}

typedef struct {
    const lens_t *lens;
    double x, y;
} sensor_ctx;

static int build_sensor(const void *ctx, double u, double v, lens_ray *r)
{
    const sensor_ctx *c = ctx;
    double in[4] = {c->x, c->y, u, v};
    ray_from_sensor(c->lens, in, r);
    return 0;
}

int aim_from_sensor(const lens_t *lens, const double *n, double x, double y, double sx,
                    double sy, double *u, double *v)
{
    if (!isfinite(x) || !isfinite(y) || !isfinite(sx) || !isfinite(sy))
        return -1;
    sensor_ctx c = {lens, x, y};
    aim_problem p = {lens, n, (int)lens->nsurf - 1, lens->stop, sx, sy, build_sensor, &c, NULL};
    /* Start: straight at the stop centre, as if the rear group were not there (shrunk
     * towards the sensor point's own axis-parallel ray if that does not get through). */
    double D = lens_total_track(lens) - lens->vertex_z[lens->stop];
    double a = 0, b = 0;
    int found = 0;
    p.sx = p.sy = 0;
    for (double s = 1; s > 1e-3 && !found; s *= 0.5) {
        double f[2];
        a = -s * x / D;
        b = -s * y / D;
        found = !residual(&p, a, b, f) && newton(&p, &a, &b, 1.0, tolerance(lens)) == 0;
    }
    if (!found || continuation(&p, sx, sy, &a, &b, 1.0))
        return -1;
    *u = a;
    *v = b;
    return 0;
}

static int build_object(const void *ctx, double a, double b, lens_ray *r)
{
    const aim_object_ctx *c = ctx;
    if (!c->finite) {
        for (int k = 0; k < 3; k++) {
            r->d[k] = c->d[k];
            r->o[k] = c->o[k] + a * c->e1[k] + b * c->e2[k] - c->dist * c->d[k];
        }
        return 0;
    }
    /* From the point towards the point Q(a, b) of the plane through the front vertex
     * region normal to the reference direction. */
    double q[3], l = 0;
    for (int k = 0; k < 3; k++) {
        q[k] = c->o[k] + c->d[k] * c->dist + a * c->e1[k] + b * c->e2[k] - c->o[k];
        l += q[k] * q[k];
    }
    l = sqrt(l);
    if (!(l > 0))
        return -1;
    for (int k = 0; k < 3; k++) {
        r->o[k] = c->o[k];
        r->d[k] = q[k] / l;
    }
    return 0;
}

/* e1 in the plane of d and the axis (the meridional plane), e2 = d x e1. */
static void perp_frame(const double d[3], double e1[3], double e2[3])
{
    double rho = hypot(d[0], d[1]);
    double ax = rho > 1e-12 ? d[0] / rho : 1, ay = rho > 1e-12 ? d[1] / rho : 0;
    /* radial unit (ax, ay, 0) minus its component along d */
    double dot = ax * d[0] + ay * d[1];
    e1[0] = ax - dot * d[0];
    e1[1] = ay - dot * d[1];
    e1[2] = -dot * d[2];
    double l = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int k = 0; k < 3; k++)
        e1[k] /= l;
    e2[0] = d[1] * e1[2] - d[2] * e1[1];
    e2[1] = d[2] * e1[0] - d[0] * e1[2];
    e2[2] = d[0] * e1[1] - d[1] * e1[0];
}

int aim_object_prepare(const lens_t *lens, const double *n, const double *dir,
                       const double *point, aim_object_start *st)
{
    if ((dir == NULL) == (point == NULL))
        return -1;
    const lens_surface *s0 = &lens->surf[0];
    double sd0 = s0->semi_diameter;
    /* A reference point near the front element: the middle of its sag. */
    double zref = lens->vertex_z[0] + 0.5 * lens_sag(s0, sd0 * sd0);
    aim_object_ctx c = {0};
    c.lens = lens;
    double size = lens_total_track(lens);
    for (size_t i = 0; i < lens->nsurf; i++)
        size = fmax(size, lens->surf[i].semi_diameter);
    if (dir) {
        double l = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        if (!(l > 0) || !isfinite(l))
            return -1;
        for (int k = 0; k < 3; k++)
            c.d[k] = dir[k] / l;
        c.o[0] = 0, c.o[1] = 0, c.o[2] = zref;
        c.dist = 4 * size + 100;
    } else {
        if (!isfinite(point[0]) || !isfinite(point[1]) || !isfinite(point[2]))
            return -1;
        c.finite = 1;
        double to[3] = {-point[0], -point[1], zref - point[2]};
        double l = sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]);
        if (!(l > 0))
            return -1;
        for (int k = 0; k < 3; k++) {
            c.o[k] = point[k];
            c.d[k] = to[k] / l;
        }
        c.dist = l;
    }
    perp_frame(c.d, c.e1, c.e2);
    aim_problem p = {lens, n, 0, lens->stop, 0, 0, build_object, &c, NULL};
    /* Scan the meridional line for the start nearest the stop centre (then follow the
     * target out to (sx, sy)); fields past 90 degrees enter far off the axis, so the scan is wide. */
    enum { NSCAN = 81 };
    double span = 1.5 * sd0;
    double best = INFINITY, ba = 0, bb = 0;
    for (int i = 0; i < NSCAN; i++) {
        double a = -span + 2 * span * i / (NSCAN - 1), f[2];
        if (residual(&p, a, 0, f))
            continue;
        double nf = hypot(f[0], f[1]);
        if (nf < best) {
            best = nf;
            ba = a;
            bb = 0;
        }
    }
    if (!isfinite(best) || newton(&p, &ba, &bb, sd0, tolerance(lens)))
        return -1;
    st->ctx = c;
    st->n = n;
    st->a = ba;
    st->b = bb;
    return 0;
}

int aim_object_to(const aim_object_start *st, double sx, double sy, lens_ray *r)
{
    return aim_object_to_within(st, sx, sy, AIM_OBJECT_BUDGET, r);
}

int aim_object_to_within(const aim_object_start *st, double sx, double sy, long max_traces,
                         lens_ray *r)
{
    if (!isfinite(sx) || !isfinite(sy))
        return -1;
    const lens_t *lens = st->ctx.lens;
    long budget = max_traces;
    aim_problem p = {lens, st->n, 0, lens->stop, 0, 0, build_object, &st->ctx,
                     max_traces > 0 ? &budget : NULL};
    double a = st->a, b = st->b;
    if (continuation(&p, sx, sy, &a, &b, lens->surf[0].semi_diameter))
        return -1;
    build_object(&st->ctx, a, b, r);
    return 0;
}

int aim_from_object(const lens_t *lens, const double *n, const double *dir, const double *point,
                    double sx, double sy, lens_ray *r)
{
    aim_object_start st;
    if (!isfinite(sx) || !isfinite(sy) || aim_object_prepare(lens, n, dir, point, &st) != 0)
        return -1;
    return aim_object_to(&st, sx, sy, r);
}
