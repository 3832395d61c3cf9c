/* The meridional section as polylines (layout.h). */
#include "sparselens/layout.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/aim.h"
#include "sparselens/ray_bundle.h"
#include "sparselens/ray_path.h"

void layout_free(layout_drawing *d)
{
    for (int i = 0; i < d->nlines; i++)
        free(d->line[i].zy);
    free(d->line);
    memset(d, 0, sizeof *d);
}

static double *add_line(layout_drawing *d, layout_kind kind, int field, int n)
{
    if (d->nlines == d->cap) {
        int cap = d->cap ? 2 * d->cap : 64;
        layout_line *l = realloc(d->line, sizeof *l * (size_t)cap);
        if (!l)
            return NULL;
        d->line = l, d->cap = cap;
    }
    double *zy = malloc(sizeof(double) * 2 * (size_t)n);
    if (!zy)
        return NULL;
    d->line[d->nlines++] = (layout_line){kind, field, n, zy};
    for (int i = 0; i < n; i++)
        zy[2 * i] = zy[2 * i + 1] = NAN;
    return zy;
}

/* z of surface i at height y. */
static double surface_z(const lens_t *lens, size_t i, double y)
{
    return lens->vertex_z[i] + lens_sag(&lens->surf[i], y * y);
}

enum { PROFILE = 24 }; /* points per half profile */

/* The outline of the element between surfaces i and i + 1: the front profile upwards,
 * the top edge (flat: a radial step at the narrower surface's rim, then along z), the
 * back profile downwards, the bottom edge. */
static int add_element(layout_drawing *d, const lens_t *lens, size_t i)
{
    double hf = lens->surf[i].semi_diameter, hb = lens->surf[i + 1].semi_diameter, h = fmax(hf, hb);
    double *zy = add_line(d, LAYOUT_ELEMENT, -1, 2 * (2 * PROFILE + 1) + 4);
    if (!zy)
        return -1;
    int k = 0;
#define PUT(z, y) (zy[2 * k] = (z), zy[2 * k + 1] = (y), k++)
    for (int j = -PROFILE; j <= PROFILE; j++)
        PUT(surface_z(lens, i, hf * j / PROFILE), hf * j / PROFILE);
    if (hf < h)
        PUT(surface_z(lens, i, hf), h);
    if (hb < h)
        PUT(surface_z(lens, i + 1, hb), h);
    for (int j = PROFILE; j >= -PROFILE; j--)
        PUT(surface_z(lens, i + 1, hb * j / PROFILE), hb * j / PROFILE);
    if (hb < h)
        PUT(surface_z(lens, i + 1, hb), -h);
    if (hf < h)
        PUT(surface_z(lens, i, hf), -h);
#undef PUT
    d->line[d->nlines - 1].n = k;
    return 0;
}

static int add_lens(layout_drawing *d, const lens_t *lens, double sensor_z, double sensor_half)
{
    for (size_t i = 0; i + 1 < lens->nsurf; i++)
        if (lens->surf[i].medium.kind != GLASS_AIR && add_element(d, lens, i) != 0)
            return -1;
    const lens_surface *st = &lens->surf[lens->stop];
    double blade = 0.25 * st->semi_diameter + 1;
    for (int side = -1; side <= 1; side += 2) {
        double *zy = add_line(d, LAYOUT_STOP, -1, 2);
        if (!zy)
            return -1;
        double zs = surface_z(lens, (size_t)lens->stop, st->semi_diameter);
        zy[0] = zs, zy[1] = side * st->semi_diameter;
        zy[2] = zs, zy[3] = side * (st->semi_diameter + blade);
    }
    double *zy = add_line(d, LAYOUT_SENSOR, -1, 2);
    if (!zy)
        return -1;
    zy[0] = zy[2] = sensor_z, zy[1] = -sensor_half, zy[3] = sensor_half;
    return 0;
}

/* One field's rays through the lens, drawn from a start before the first surface. */
static int add_rays(layout_drawing *d, const imaging *im, const ray_bundle *b, int f, double lead)
{
    const lens_t *lens = im->lens;
    int ns = (int)lens->nsurf;
    double *pts = malloc(sizeof(double) * 3 * (size_t)ns), zs = lens_total_track(lens) + im->sensor_shift;
    if (!pts)
        return -1;
    for (size_t i = 0; i < b->count; i++) {
        if (!b->aimed[i])
            continue;
        lens_ray r = b->ray[i];
        int clip, k = ray_path(lens, b->n, &r, pts, NULL, &clip);
        int passed = k == ns && r.d[2] > 0, n = 1 + k + (clip ? 1 : 0) + (passed ? 1 : 0);
        double *zy = add_line(d, LAYOUT_RAY, f, n);
        if (!zy) {
            free(pts);
            return -1;
        }
        /* the start: `lead` mm back along the ray from where it meets the first surface
         * (or from its origin, a finite object's point, when that is nearer) */
        const lens_ray *o = &b->ray[i];
        double back = lead;
        if (k > 0 || clip) {
            double dz = pts[2] - o->o[2], dy = pts[1] - o->o[1];
            back = fmin(lead, hypot(dz, dy)) - hypot(dz, dy);
            zy[0] = o->o[2] - back * o->d[2], zy[1] = o->o[1] - back * o->d[1];
        } else {
            zy[0] = o->o[2], zy[1] = o->o[1];
        }
        int m = 1;
        for (int j = 0; j < k + (clip ? 1 : 0); j++, m++)
            zy[2 * m] = pts[3 * j + 2], zy[2 * m + 1] = pts[3 * j + 1];
        if (passed) {
            double u = (zs - r.o[2]) / r.d[2];
            zy[2 * m] = zs, zy[2 * m + 1] = r.o[1] + u * r.d[1];
            d->passed++;
        }
        d->rays++;
    }
    free(pts);
    return 0;
}

/* The system's image-space rays: from its sensor ray back to the rear vertex plane;
 * returns the largest distance from the lens's sensor points (NAN if none compared). */
static double add_system_rays(layout_drawing *d, const imaging *lens_im, const imaging *sys_im,
                              const ray_bundle *b, const double *seed, int f)
{
    size_t n = b->count;
    double *s = malloc(sizeof(double) * 4 * n), *e = malloc(sizeof(double) * 4 * n), diff = NAN;
    int *ok = malloc(sizeof(int) * n), *oke = malloc(sizeof(int) * n);
    if (s && e && ok && oke) {
        d->seconds[1] += bundle_image(sys_im, b, seed, s, ok);
        d->seconds[0] += bundle_image(lens_im, b, NULL, e, oke);
        const lens_t *lens = lens_im->lens;
        double zs = lens_total_track(lens) + sys_im->sensor_shift, zr = lens->vertex_z[lens->nsurf - 1];
        for (size_t i = 0; i < n; i++) {
            if (!ok[i])
                continue;
            double *zy = add_line(d, LAYOUT_SYSTEM, f, 2);
            if (!zy)
                break;
            zy[0] = zs, zy[1] = s[4 * i + 1];
            zy[2] = zr, zy[3] = s[4 * i + 1] - (zr - zs) * s[4 * i + 3];
            if (oke[i]) {
                double dd = hypot(s[4 * i] - e[4 * i], s[4 * i + 1] - e[4 * i + 1]);
                diff = isnan(diff) ? dd : fmax(diff, dd);
            }
        }
    }
    free(s), free(e), free(ok), free(oke);
    return diff;
}

static void extent(layout_drawing *d)
{
    d->zmin = d->ymin = INFINITY, d->zmax = d->ymax = -INFINITY;
    for (int i = 0; i < d->nlines; i++)
        for (int k = 0; k < d->line[i].n; k++) {
            double z = d->line[i].zy[2 * k], y = d->line[i].zy[2 * k + 1];
            if (isfinite(z) && isfinite(y)) {
                d->zmin = fmin(d->zmin, z), d->zmax = fmax(d->zmax, z);
                d->ymin = fmin(d->ymin, y), d->ymax = fmax(d->ymax, y);
            }
        }
}

/* 1 when ray r, traced with indices n, reaches the sensor (the test add_rays draws by);
 * pts holds 3 doubles a surface. */
static int lands(const lens_t *lens, const double *n, lens_ray r, double *pts)
{
    int clip, k = ray_path(lens, n, &r, pts, NULL, &clip);
    return k == (int)lens->nsurf && r.d[2] > 0;
}

enum { SCAN = 65, EDGE_STEPS = 16 }; /* 2 / 64 / 2^16: an end to 5e-7 of the stop radius */

/* The end of the passing run between normalised stop points `in` (passes) and `out`
 * (stopped), by bisection with the field's aim prepared once: the last passing point. */
static double refine_end(const lens_t *lens, const double *n, const aim_object_start *st, double in, double out,
                         double *pts)
{
    double stop = lens->surf[lens->stop].semi_diameter;
    for (int it = 0; it < EDGE_STEPS; it++) {
        double mid = 0.5 * (in + out);
        lens_ray r;
        int ok = aim_object_to(st, 0, mid * stop, &r) == 0 && lands(lens, n, r, pts);
        *(ok ? &in : &out) = mid;
    }
    return in;
}

/* The meridian's passing part for one field: the run of stop points whose rays reach the
 * sensor around the chief ray (the longest run when the chief ray is stopped), as
 * [lowest, highest] normalised py; the whole meridian when no point passes, so that the
 * drawing still shows where the rays stop. A designer's layout shows the bundle that
 * forms the image; rays across the whole stop of a vignetted field mostly end on barrels
 * (dgauss.50mm at its full field: 10 of 20). */
static int passing_span(const imaging *im, double field, double lambda, double *pts, double span[2],
                        lens_err *err)
{
    const lens_t *lens = im->lens;
    double pupil[2 * SCAN];
    for (int i = 0; i < SCAN; i++)
        pupil[2 * i] = 0, pupil[2 * i + 1] = -1 + 2.0 * i / (SCAN - 1);
    ray_bundle b;
    if (bundle_aim(im, field, lambda, pupil, SCAN, &b, err) != 0)
        return -1;
    int pass[SCAN];
    for (int i = 0; i < SCAN; i++)
        pass[i] = b.aimed[i] && lands(lens, b.n, b.ray[i], pts);
    int lo = -1, hi = -1;
    for (int i = 0; i < SCAN; i++) {
        if (!pass[i] || (i > 0 && pass[i - 1]))
            continue;
        int j = i;
        while (j + 1 < SCAN && pass[j + 1])
            j++;
        int chief = i <= SCAN / 2 && SCAN / 2 <= j;
        if (lo < 0 || chief || (!(lo <= SCAN / 2 && SCAN / 2 <= hi) && j - i > hi - lo))
            lo = i, hi = j;
        if (chief)
            break;
    }
    span[0] = -1, span[1] = 1;
    aim_object_start st;
    /* a passing point means the field's aim can be prepared */
    if (lo >= 0 && imaging_aim_prepare(im, b.n, field, &st) == 0) {
        if (lo > 0)
            span[0] = refine_end(lens, b.n, &st, pupil[2 * lo + 1], pupil[2 * lo - 1], pts);
        if (hi < SCAN - 1)
            span[1] = refine_end(lens, b.n, &st, pupil[2 * hi + 1], pupil[2 * hi + 3], pts);
    }
    bundle_free(&b);
    return 0;
}

int layout_build(const imaging *lens_im, const imaging *sys_im, const unsigned char *sys_skip,
                 const double *field, int nf, double lambda, int nrays, int full_stop, layout_drawing *d,
                 lens_err *err)
{
    memset(d, 0, sizeof *d);
    d->nfields = nf, d->field = field, d->finite = isfinite(lens_im->object_distance);
    d->system_diff = NAN;
    const lens_t *lens = lens_im->lens;
    double track = lens_total_track(lens), half = 0;
    for (size_t i = 0; i < lens->nsurf; i++)
        half = fmax(half, lens->surf[i].semi_diameter);
    if (isfinite(lens->sensor_w) && isfinite(lens->sensor_h))
        half = 0.5 * hypot(lens->sensor_w, lens->sensor_h);
    /* the plane the rays end on: the file's, moved to the focus asked for */
    if (add_lens(d, lens, track + lens_im->sensor_shift, half) != 0)
        goto oom;
    if (nf > IMAGING_MAX_FIELDS) {
        layout_free(d);
        lens_errf(err, NULL, 0, "%d fields: a layout draws at most %d", nf, IMAGING_MAX_FIELDS);
        return -1;
    }
    double *pupil = malloc(sizeof(double) * 2 * (size_t)nrays);
    double *pts = malloc(sizeof(double) * 3 * lens->nsurf);
    if (!pupil || !pts) {
        free(pupil), free(pts);
        goto oom;
    }
    /* object-space rays are drawn over a third of the track */
    double lead = 0.3 * track;
    for (int f = 0; f < nf; f++) {
        double *span = d->span[f];
        span[0] = -1, span[1] = 1;
        if (!full_stop && passing_span(lens_im, field[f], lambda, pts, span, err) != 0) {
            free(pupil), free(pts);
            layout_free(d);
            return -1;
        }
        for (int i = 0; i < nrays; i++)
            pupil[2 * i] = 0, pupil[2 * i + 1] = nrays > 1 ? span[0] + (span[1] - span[0]) * i / (nrays - 1)
                                                 : span[0] <= 0 && 0 <= span[1] ? 0
                                                                                : 0.5 * (span[0] + span[1]);
        ray_bundle b;
        if (bundle_aim(lens_im, field[f], lambda, pupil, (size_t)nrays, &b, err) != 0) {
            free(pupil), free(pts);
            layout_free(d);
            return -1;
        }
        int rc = add_rays(d, lens_im, &b, f, lead);
        if (rc == 0 && sys_im && !(sys_skip && sys_skip[f])) {
            double chief[4];
            if (bundle_chief(sys_im, field[f], lambda, chief, err) != 0) {
                bundle_free(&b);
                free(pupil), free(pts);
                layout_free(d);
                return -1;
            }
            double diff = add_system_rays(d, lens_im, sys_im, &b, chief, f);
            if (isfinite(diff))
                d->system_diff = isnan(d->system_diff) ? diff : fmax(d->system_diff, diff);
        }
        bundle_free(&b);
        if (rc != 0) {
            free(pupil), free(pts);
            goto oom;
        }
    }
    free(pupil), free(pts);
    /* the sensor line reaches the highest image drawn */
    for (int i = 0; i < d->nlines; i++)
        if (d->line[i].kind == LAYOUT_SENSOR)
            for (int j = 0; j < d->nlines; j++) {
                const layout_line *r = &d->line[j];
                double y = r->n ? fabs(r->zy[2 * r->n - 1]) : 0;
                if (r->kind == LAYOUT_RAY && r->zy[2 * r->n - 2] == d->line[i].zy[0] && y > d->line[i].zy[3])
                    d->line[i].zy[1] = -y, d->line[i].zy[3] = y;
            }
    double *axis = add_line(d, LAYOUT_AXIS, -1, 2);
    if (!axis)
        goto oom;
    extent(d);
    axis[0] = d->zmin, axis[1] = 0, axis[2] = d->zmax, axis[3] = 0;
    return 0;
oom:
    layout_free(d);
    lens_errf(err, NULL, 0, "out of memory");
    return -1;
}

void layout_field_rgb(int f, double rgb[3])
{
    static const double c[6][3] = {{0.0, 0.35, 0.85}, {0.0, 0.6, 0.2}, {0.85, 0.1, 0.1},
                                   {0.85, 0.5, 0.0},  {0.55, 0.1, 0.7}, {0.0, 0.6, 0.65}};
    memcpy(rgb, c[f % 6], sizeof c[0]);
}
