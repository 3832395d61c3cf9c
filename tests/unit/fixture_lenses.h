#ifndef SPARSELENS_FIXTURE_LENSES_H
#define SPARSELENS_FIXTURE_LENSES_H
/* Test lenses built in C, independent of the file readers:
 *  - fisheye-ii: the 18 surfaces of lenses/reference/fx/fisheye-ii.fx
 *    (Nikkor 10.5 mm fisheye, US 7,161,746), nd/Vd glasses, 10000 = flat, iris = stop;
 *  - dgauss.50mm: pbrt's dgauss.50mm.dat (4th column a diameter, radius 0 = stop,
 *    constant indices); its last thickness is set here to the paraxial focus at infinity;
 *  - a singlet and a flat-sided window for closed-form checks. */
#include <math.h>
#include <string.h>

#include "sparselens/lens.h"

typedef struct {
    double r, t, nd, vd, sd; /* nd 0: air; vd 0: constant index; r 0: flat */
    int stop;
} fixture_row;

static inline int fixture_build(lens_t *lens, const char *name, const fixture_row *rows, int n)
{
    lens_init(lens);
    strncpy(lens->name, name, sizeof lens->name - 1);
    for (int i = 0; i < n; i++) {
        lens_surface *s = lens_add_surface(lens);
        if (!s)
            return -1;
        s->radius = rows[i].r == 0 ? INFINITY : rows[i].r;
        s->thickness = rows[i].t;
        s->semi_diameter = rows[i].sd;
        s->is_stop = rows[i].stop;
        if (rows[i].nd > 0)
            s->medium = rows[i].vd > 0 ? glass_from_ndvd(rows[i].nd, rows[i].vd)
                                       : glass_constant(rows[i].nd);
    }
    lens_err err;
    return lens_finish(lens, &err);
}

/* Paraxial y-nu trace from an axial object at infinity at the d line (y = 1 on the first
 * surface): the height y on the last surface, and the slope nu and index n after it.
 * Written here so the tests do not depend on src/lens/paraxial.c. */
static inline void fixture_ynu(const lens_t *lens, double *y_out, double *nu_out, double *n_out)
{
    double y = 1, nu = 0, n1 = 1;
    for (size_t i = 0; i < lens->nsurf; i++) {
        const lens_surface *s = &lens->surf[i];
        double c = isfinite(s->radius) ? 1.0 / s->radius : 0;
        double n2 = glass_index_unchecked(&s->medium, GLASS_D_LINE);
        nu -= y * c * (n2 - n1);
        if (i + 1 < lens->nsurf)
            y += s->thickness * nu / n2;
        n1 = n2;
    }
    *y_out = y, *nu_out = nu, *n_out = n1;
}

/* The back focal distance (last surface to focus). */
static inline double fixture_bfl(const lens_t *lens)
{
    double y, nu, n;
    fixture_ynu(lens, &y, &nu, &n);
    return -y / (nu / n);
}

/* Effective focal length at the d line. */
static inline double fixture_efl(const lens_t *lens)
{
    double y, nu, n;
    fixture_ynu(lens, &y, &nu, &n);
    return -1.0 / nu;
}

/* Appends a spherical surface (n 1: air after it) to a lens being built by hand. */
static inline void fixture_add(lens_t *l, double r, double t, double n, double sd, int stop)
{
    lens_surface *s = lens_add_surface(l);
    s->radius = r;
    s->thickness = t;
    s->semi_diameter = sd;
    s->is_stop = stop;
    if (n != 1.0)
        s->medium = glass_constant(n);
}

static inline int fixture_fisheye_ii(lens_t *lens)
{
    static const fixture_row rows[] = {
        {85.00, 2.040, 1.62041, 60.29, 26, 0},   {16.45, 8.320, 0, 0, 15.5, 0},
        {61.18, 1.700, 1.81600, 46.63, 15, 0},   {20.15, 10.316, 0, 0, 15, 0},
        {-204.00, 3.430, 1.72000, 43.69, 10, 0}, {-31.26, 0.250, 0, 0, 10, 0},
        {-27.00, 2.780, 1.77250, 49.61, 9, 0},   {11.48, 4.930, 1.72825, 28.46, 8, 0},
        {-55.84, 5.865, 0, 0, 8, 0},             {59.67, 2.570, 1.51742, 52.42, 7.5, 0},
        {-14.20, 1.410, 1.83481, 42.72, 7.5, 0}, {-76.00, 3.660, 0, 0, 9, 0},
        {0, 8.776, 0, 0, 9, 1},                  {-1732.00, 1.490, 1.84666, 23.78, 11, 0},
        {29.90, 4.020, 1.49700, 81.61, 10, 0},   {-21.55, 0.190, 0, 0, 10, 0},
        {44.74, 3.210, 1.65160, 58.54, 11, 0},   {-44.74, 41.100, 0, 0, 11, 0},
    };
    return fixture_build(lens, "fisheye-ii", rows, (int)(sizeof rows / sizeof rows[0]));
}

static inline int fixture_dgauss50(lens_t *lens)
{
    static const fixture_row rows[] = {
        {29.475, 3.76, 1.67, 0, 25.2 / 2, 0},  {84.83, 0.12, 0, 0, 25.2 / 2, 0},
        {19.275, 4.025, 1.67, 0, 23 / 2.0, 0}, {40.77, 3.275, 1.699, 0, 23 / 2.0, 0},
        {12.75, 5.705, 0, 0, 18 / 2.0, 0},     {0, 4.5, 0, 0, 17.1 / 2, 1},
        {-14.495, 1.18, 1.603, 0, 17 / 2.0, 0}, {40.77, 6.065, 1.658, 0, 20 / 2.0, 0},
        {-20.385, 0.19, 0, 0, 20 / 2.0, 0},    {437.065, 3.22, 1.717, 0, 20 / 2.0, 0},
        {-39.73, 40, 0, 0, 20 / 2.0, 0},
    };
    if (fixture_build(lens, "dgauss.50mm", rows, (int)(sizeof rows / sizeof rows[0])))
        return -1;
    lens->surf[lens->nsurf - 1].thickness = fixture_bfl(lens);
    lens_err err;
    return lens_finish(lens, &err);
}

/* A biconvex singlet with its stop on the front face, sensor at distance t_back. */
static inline int fixture_singlet(lens_t *lens, double r1, double r2, double thick, double nd,
                                  double vd, double sd, double t_back)
{
    fixture_row rows[] = {
        {r1, thick, nd, vd, sd, 1},
        {r2, t_back, 0, 0, sd, 0},
    };
    return fixture_build(lens, "singlet", rows, 2);
}

#endif
