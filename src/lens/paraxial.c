/* First-order optics by 2x2 ray-transfer matrices in (y, nu = n u).
 *
 * Conventions: a refraction at surface i of power phi = (n_after - n_before) / R maps
 * (y, nu) -> (y, nu - phi y); a transfer over thickness t in index n maps
 * (y, nu) -> (y + t nu / n, nu). For a matrix [[A, B], [C, D]] from the first vertex
 * (before refraction) to the last vertex (after refraction), with air on both sides:
 *   efl = -1/C,  bfl = -A/C,  ffl = D/C
 * (a thin lens of power phi gives f, f, -f). Pupils are the images of the stop through
 * the surfaces in front of it (entrance) and behind it (exit). */
#include "sparselens/paraxial.h"

#include <math.h>
#include <string.h>

#include "sparselens/lens.h"

typedef struct {
    double a, b, c, d;
} mat2;

static const mat2 IDENTITY = {1, 0, 0, 1};

static mat2 mul(mat2 m, mat2 n) /* m after n */
{
    return (mat2){m.a * n.a + m.b * n.c, m.a * n.b + m.b * n.d, m.c * n.a + m.d * n.c,
                  m.c * n.b + m.d * n.d};
}

static double curvature(const lens_surface *s)
{
    return isfinite(s->radius) ? 1.0 / s->radius : 0.0;
}

/* Refraction at surfaces first..last with the transfers between them (not after last). */
static mat2 span(const lens_t *lens, const double *n, size_t first, size_t last)
{
    mat2 m = IDENTITY;
    for (size_t i = first; i <= last && i < lens->nsurf; i++) {
        double before = i == 0 ? 1.0 : n[i - 1];
        double phi = (n[i] - before) * curvature(&lens->surf[i]);
        m = mul((mat2){1, 0, -phi, 1}, m);
        if (i < last)
            m = mul((mat2){1, lens->surf[i].thickness / n[i], 0, 1}, m);
    }
    return m;
}

void paraxial_trace_forward(const lens_t *lens, const double *n, double y0, double nu0,
                            double *y_out, double *nu_out)
{
    mat2 m = span(lens, n, 0, lens->nsurf - 1);
    size_t last = lens->nsurf - 1;
    m = mul((mat2){1, lens->surf[last].thickness / n[last], 0, 1}, m);
    *y_out = m.a * y0 + m.b * nu0;
    *nu_out = m.c * y0 + m.d * nu0;
}

int paraxial_compute(const lens_t *lens, double lambda, paraxial_data *p, lens_err *err)
{
    memset(p, 0, sizeof *p);
    if (lens->nsurf == 0 || lens->stop < 0) {
        lens_errf(err, lens->path, 0, "lens has no surfaces or no stop");
        return -1;
    }
    double n[lens->nsurf];
    if (lens_indices(lens, lambda, n, err) != 0)
        return -1;
    size_t last = lens->nsurf - 1, s = (size_t)lens->stop;
    double n_image = n[last];
    mat2 m = span(lens, n, 0, last);
    p->lambda = lambda;
    /* An afocal lens (no power: a window, a telescope) has no focal points; its
     * focal lengths are infinite without a sign, where -1/C would give -inf for a
     * power that is only zero by cancellation. */
    p->afocal = m.c == 0;
    p->efl = p->afocal ? INFINITY : -1.0 / m.c;
    p->bfl = p->afocal ? INFINITY : -m.a * n_image / m.c;
    p->ffl = p->afocal ? INFINITY : m.d / m.c;
    p->stop_surface = (int)s + 1;
    p->total_track = lens_total_track(lens);
    p->sensor_distance = lens->surf[last].thickness;
    double r_stop = lens->surf[s].semi_diameter;

    /* Entrance pupil: object-space ray through the stop centre, and the marginal ray
     * from infinity grazing the stop edge. */
    mat2 f = IDENTITY;
    if (s > 0) {
        f = span(lens, n, 0, s - 1);
        f = mul((mat2){1, lens->surf[s - 1].thickness / n[s - 1], 0, 1}, f);
    }
    p->entrance_pupil_z = f.a != 0 ? f.b / f.a : INFINITY;
    p->entrance_pupil_diameter = 2.0 * r_stop / fabs(f.a);
    p->fnumber = p->afocal ? INFINITY : p->efl / p->entrance_pupil_diameter;

    /* Exit pupil: image of the stop through surfaces s..last. */
    mat2 b = span(lens, n, s, last);
    p->exit_pupil_z = b.d != 0 ? -b.b * n_image / b.d : INFINITY;
    p->exit_pupil_diameter = 2.0 * r_stop * fabs(b.a + p->exit_pupil_z / n_image * b.c);

    /* Object conjugate to the sensor: an axial object point at z = -d images onto the
     * sensor when (A' d + B') = 0 for the matrix up to the sensor plane. */
    mat2 t = mul((mat2){1, lens->surf[last].thickness / n_image, 0, 1}, m);
    p->focus_distance = t.a != 0 ? -t.b / t.a : INFINITY;
    if (fabs(t.a) < 1e-12 * fabs(t.b))
        p->focus_distance = INFINITY;
    return 0;
}

int paraxial_focus_thickness(const lens_t *lens, double lambda, double distance, double *thickness,
                             lens_err *err)
{
    double n[lens->nsurf];
    if (lens->nsurf == 0 || lens_indices(lens, lambda, n, err) != 0)
        return -1;
    mat2 m = span(lens, n, 0, lens->nsurf - 1);
    double n_image = n[lens->nsurf - 1];
    double t;
    if (isinf(distance))
        t = -m.a * n_image / m.c;
    else
        t = -(m.a * distance + m.b) * n_image / (m.c * distance + m.d);
    if (!isfinite(t) || t <= 0) {
        lens_errf(err, lens->path[0] ? lens->path : NULL, 0,
                  "an object at %g mm has no real image behind the lens (sensor distance %g)",
                  distance, t);
        return -1;
    }
    *thickness = t;
    return 0;
}

int lens_set_fnumber(lens_t *lens, double fnumber, lens_err *err)
{
    paraxial_data p;
    if (!(fnumber > 0) || !isfinite(fnumber)) {
        lens_errf(err, NULL, 0, "f-number must be positive, not %g", fnumber);
        return -1;
    }
    if (paraxial_compute(lens, GLASS_D_LINE, &p, err) != 0)
        return -1;
    if (fnumber < p.fnumber * (1 - 1e-12)) {
        lens_errf(err, lens->path[0] ? lens->path : NULL, 0,
                  "f/%g is faster than the lens' widest aperture f/%.3g", fnumber, p.fnumber);
        return -1;
    }
    if (fnumber > LENS_FNUMBER_MAX) {
        lens_errf(err, lens->path[0] ? lens->path : NULL, 0,
                  "f/%g is outside the accepted range f/%.3g (the lens' widest) to f/%g",
                  fnumber, p.fnumber, LENS_FNUMBER_MAX);
        return -1;
    }
    lens->surf[lens->stop].semi_diameter *= p.fnumber / fnumber;
    return 0;
}
