/* Ray-object intersection, textures and emitters of a scene (frame: scene.h). All
 * surfaces are Lambertian reflectors or emitters, enough to show what a lens does. */
#include <math.h>
#include <string.h>

#include "sparselens/scene.h"

#include "render/render_math.h"
#include "render/scene_light_simd.h"

#define EPS_T 1e-6 /* mm: self-intersection guard, far below any scene feature */
#define dot3 rm_dot3

int scene_is_emitter(const scene_object *o)
{
    return o->emitter;
}

size_t scene_emitter_count(const scene_t *s)
{
    size_t k = 0;
    for (size_t i = 0; i < s->nobj; i++) k += s->obj[i].emitter;
    return k;
}

/* t of the nearest hit with object o, or INFINITY; a plane's or disk's hit at tmax or
 * beyond may be INFINITY too (tmax: a search's nearest so far, which spares the
 * quotient). Inlined: every sample tests a few dozen objects, and a call costs about as
 * much as a plane's test. */
static inline __attribute__((always_inline)) double hit_object(const scene_object *o,
                                                               const double org[3],
                                                               const double d[3], double tmin,
                                                               double tmax)
{
    if (o->kind == OBJ_SPHERE) {
        double oc[3] = {org[0] - o->p[0], org[1] - o->p[1], org[2] - o->p[2]};
        double b = dot3(oc, d), cc = dot3(oc, oc) - o->r2;
        double disc = b * b - cc;
        if (disc < 0) return INFINITY;
        double sq = sqrt(disc);
        /* the root with the smaller magnitude first avoids cancellation */
        double t0 = -b - sq, t1 = -b + sq;
        if (t0 > tmin) return t0;
        if (t1 > tmin) return t1;
        return INFINITY;
    }
    double den = dot3(d, o->n);
    double q[3] = {o->p[0] - org[0], o->p[1] - org[1], o->p[2] - org[2]}, num = dot3(q, o->n);
    /* behind the origin (or parallel): no quotient; beyond tmax: none either, |num| >=
     * tmax |den| (a ray in the plane, 0 / 0, fails both) */
    if (!(num > 0 ? den > 0 : num < 0 && den < 0)) return INFINITY;
    if (fabs(num) >= tmax * fabs(den)) return INFINITY;
    double t = num / den;
    if (!(t > tmin)) return INFINITY;
    if (o->kind == OBJ_DISK) {
        double h[3];
        for (int k = 0; k < 3; k++) h[k] = org[k] + t * d[k] - o->p[k];
        if (dot3(h, h) > o->r2) return INFINITY;
    }
    return t;
}

/* The hit record of object which at ray parameter t. */
static void fill_hit(const scene_t *s, int which, double t, const double o[3], const double d[3],
                     scene_hit *hit)
{
    const scene_object *ob = &s->obj[which];
    hit->t = t;
    hit->obj = which;
    for (int k = 0; k < 3; k++) hit->p[k] = o[k] + t * d[k];
    if (ob->kind == OBJ_SPHERE)
        for (int k = 0; k < 3; k++) hit->n[k] = (hit->p[k] - ob->p[k]) / ob->radius;
    else
        memcpy(hit->n, ob->n, sizeof hit->n);
    if (dot3(hit->n, d) > 0)
        for (int k = 0; k < 3; k++) hit->n[k] = -hit->n[k];
}

void scene_fill_hit(const scene_t *s, int which, double t, const double o[3], const double d[3],
                    scene_hit *hit)
{
    fill_hit(s, which, t, o, d, hit);
}

int scene_intersect(const scene_t *s, const double o[3], const double d[3], double tmin,
                    double tmax, scene_hit *hit)
{
    double best = tmax;
    int which = -1;
    for (size_t i = 0; i < s->nobj; i++) {
        double t = hit_object(&s->obj[i], o, d, tmin, best);
        if (t < best) best = t, which = (int)i;
    }
    if (which < 0) return 0;
    fill_hit(s, which, best, o, d, hit);
    return 1;
}

int scene_intersect_emitter(const scene_t *s, const double o[3], const double d[3],
                            double tmin, scene_hit *hit)
{
    double best = INFINITY;
    int which = -1;
    for (size_t i = 0; i < s->nobj; i++) {
        if (!s->obj[i].emitter) continue;
        double t = hit_object(&s->obj[i], o, d, tmin, best);
        if (t < best) best = t, which = (int)i;
    }
    if (which < 0) return 0;
    /* an object in front of it, the first found: an emitter there would have been nearer
     * (an equal t keeps the lower index, as scene_intersect does) */
    for (size_t i = 0; i < s->nobj; i++) {
        if (s->obj[i].emitter) continue;
        double t = hit_object(&s->obj[i], o, d, tmin, INFINITY); /* ties count */
        if (t < best || (t == best && (int)i < which)) return 0;
    }
    fill_hit(s, which, best, o, d, hit);
    return 1;
}

int scene_intersect_listed(const scene_t *s, const int *spheres, int nlisted, const double o[3],
                           const double d[3], double tmin, double tmax, scene_hit *hit)
{
    double best = tmax;
    int which = -1;
    for (size_t i = 0; i < s->nobj; i++) {
        if (s->obj[i].kind == OBJ_SPHERE) continue;
        double t = hit_object(&s->obj[i], o, d, tmin, best);
        if (t < best) best = t, which = (int)i;
    }
    for (int k = 0; k < nlisted; k++) {
        double t = hit_object(&s->obj[spheres[k]], o, d, tmin, best);
        if (t < best) best = t, which = spheres[k];
    }
    if (which < 0) return 0;
    fill_hit(s, which, best, o, d, hit);
    return 1;
}

int scene_visible(const scene_t *s, const double a[3], const double b[3])
{
    double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double len = sqrt(dot3(d, d));
    if (!(len > 0)) return 1;
    double inv = 1 / len;
    for (int k = 0; k < 3; k++) d[k] *= inv;
    /* any blocker will do: the first one found ends the search */
    double tmax = len * (1 - 1e-9) - EPS_T;
    for (size_t i = 0; i < s->nobj; i++)
        if (hit_object(&s->obj[i], a, d, EPS_T, tmax) < tmax) return 0;
    return 1;
}

/* Tangent frame of a plane, chosen so that a plane facing the camera (normal -z) has
 * e1 = +x (right) and e2 = +y (up): pictures on it appear as drawn. */
static void plane_frame(const double n[3], double e1[3], double e2[3])
{
    double up[3] = {0, 1, 0};
    if (fabs(n[1]) > 0.999) up[0] = 1, up[1] = 0;
    e1[0] = n[1] * up[2] - n[2] * up[1];
    e1[1] = n[2] * up[0] - n[0] * up[2];
    e1[2] = n[0] * up[1] - n[1] * up[0];
    double l = sqrt(dot3(e1, e1));
    for (int k = 0; k < 3; k++) e1[k] /= l;
    e2[0] = e1[1] * n[2] - e1[2] * n[1];
    e2[1] = e1[2] * n[0] - e1[0] * n[2];
    e2[2] = e1[0] * n[1] - e1[1] * n[0];
}

void scene_albedo(const scene_t *s, int obj, const double p[3], double rgb[3])
{
    const scene_object *o = &s->obj[obj];
    const scene_texture *t = &o->tex;
    const double *from = t->a;
    rgb[0] = rgb[1] = rgb[2] = 0;
    if (o->emitter) return;
    switch (t->kind) {
    case TEX_CONSTANT:
        break;
    case TEX_CHECKER: {
        /* a solid checker: the same pattern on planes and spheres */
        /* The parity of each cell index from floor, not a cast to long: a tiny square or
         * a far hit gives indices past LONG_MAX (undefined behaviour when cast). */
        /* On a plane (or disk) the hit is first put back on it exactly: a plane on a
         * cell face (z = 1000 with cubes of 40) would otherwise take either colour by
         * the last bit of the hit, a different one for two ways of tracing one ray. */
        double q[3] = {p[0], p[1], p[2]};
        if (o->kind != OBJ_SPHERE) {
            double off = (p[0] - o->p[0]) * o->n[0] + (p[1] - o->p[1]) * o->n[1] +
                         (p[2] - o->p[2]) * o->n[2];
            for (int j = 0; j < 3; j++) q[j] -= off * o->n[j];
        }
        /* f - 2 floor(f / 2) is |fmod(f, 2)| for a whole f (every step exact), NaN for an
         * infinite one as fmod's: the parities without libm's fmod */
        double k = 0;
        for (int j = 0; j < 3; j++) {
            double f = floor(q[j] / t->size);
            k += f - 2 * floor(0.5 * f);
        }
        if (k == 1 || k == 3) from = t->b;
        break;
    }
    case TEX_IMAGE: {
        double u, v; /* [0, 1) across the picture, v = 0 at its top */
        if (o->kind == OBJ_SPHERE) {
            double q[3];
            for (int k = 0; k < 3; k++) q[k] = (p[k] - o->p[k]) / o->radius;
            u = 0.5 + atan2(q[0], -q[2]) / (2 * M_PI);
            v = acos(fmax(-1, fmin(1, q[1]))) / M_PI;
        } else {
            double e1[3], e2[3], q[3];
            plane_frame(o->n, e1, e2);
            for (int k = 0; k < 3; k++) q[k] = p[k] - o->p[k];
            double height = t->size * t->h / t->w;
            u = dot3(q, e1) / t->size + 0.5;
            v = 0.5 - dot3(q, e2) / height;
            u -= floor(u); /* tiles */
            v -= floor(v);
        }
        int x = (int)(u * t->w), y = (int)(v * t->h);
        if (x >= t->w) x = t->w - 1;
        if (y >= t->h) y = t->h - 1;
        if (x < 0) x = 0;
        if (y < 0) y = 0;
        const float *px = t->pix + 3 * ((size_t)y * t->w + x);
        for (int c = 0; c < 3; c++) rgb[c] = px[c];
        return;
    }
    default:
        return;
    }
    for (int c = 0; c < 3; c++) rgb[c] = from[c];
}

int scene_emitted(const scene_t *s, int obj, const double p[3], const double w[3],
                  double rgb[3])
{
    const scene_object *o = &s->obj[obj];
    rgb[0] = rgb[1] = rgb[2] = 0;
    if (!o->emitter) return 0;
    double n[3];
    if (o->kind == OBJ_SPHERE)
        for (int k = 0; k < 3; k++) n[k] = p[k] - o->p[k];
    else
        memcpy(n, o->n, sizeof n);
    if (dot3(n, w) <= 0) return 0;
    memcpy(rgb, o->emit, 3 * sizeof *rgb);
    return 1;
}

void scene_sample_emitter(const scene_t *s, int obj, double u1, double u2, double p[3],
                          double n[3], double *pdf_area)
{
    const scene_object *o = &s->obj[obj];
    if (o->kind == OBJ_SPHERE) {
        double z = 1 - 2 * u1, r = sqrt(fmax(0, 1 - z * z)), phi = 2 * M_PI * u2;
        n[0] = r * cos(phi);
        n[1] = r * sin(phi);
        n[2] = z;
        for (int k = 0; k < 3; k++) p[k] = o->p[k] + o->radius * n[k];
        *pdf_area = 1 / (4 * M_PI * o->radius * o->radius);
    } else if (o->kind == OBJ_DISK) {
        double e1[3], e2[3], r = o->radius * sqrt(u1), phi = 2 * M_PI * u2;
        plane_frame(o->n, e1, e2);
        for (int k = 0; k < 3; k++)
            p[k] = o->p[k] + r * (cos(phi) * e1[k] + sin(phi) * e2[k]);
        memcpy(n, o->n, 3 * sizeof *n);
        *pdf_area = 1 / (M_PI * o->radius * o->radius);
    } else { /* an infinite plane cannot be sampled by area: it is only seen directly */
        memcpy(p, o->p, 3 * sizeof *p);
        memcpy(n, o->n, 3 * sizeof *n);
        *pdf_area = 0;
    }
}

void scene_direct(const scene_t *s, int obj, const double p[3], const double n[3],
                  const double *u, double rgb[3])
{
    double albedo[3], sum[3] = {0, 0, 0};
    scene_albedo(s, obj, p, albedo);
    rgb[0] = rgb[1] = rgb[2] = 0;
    if (albedo[0] <= 0 && albedo[1] <= 0 && albedo[2] <= 0) return;
    size_t j = 0;
    for (size_t i = 0; i < s->nobj; i++) {
        if (!scene_is_emitter(&s->obj[i])) continue;
        double q[3], nl[3], pdf, le[3];
        scene_sample_emitter(s, (int)i, u[2 * j], u[2 * j + 1], q, nl, &pdf);
        j++;
        if (!(pdf > 0)) continue;
        double w[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        double d2 = dot3(w, w), d = sqrt(d2);
        if (!(d > 0)) continue;
        for (int k = 0; k < 3; k++) w[k] /= d;
        double cr = dot3(n, w), cl = -dot3(nl, w);
        if (cr <= 0 || cl <= 0) continue;
        double back[3] = {-w[0], -w[1], -w[2]};
        if (!scene_emitted(s, (int)i, q, back, le) || !scene_visible(s, p, q)) continue;
        double g = cr * cl / (d2 * pdf);
        for (int c = 0; c < 3; c++) sum[c] += le[c] * g;
    }
    for (int c = 0; c < 3; c++) rgb[c] = albedo[c] / M_PI * sum[c];
}
