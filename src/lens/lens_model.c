/* The lens model's geometry: construction, checks, sag and slope of a surface. */
#include "sparselens/lens.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void lens_init(lens_t *lens)
{
    memset(lens, 0, sizeof *lens);
    lens->focal = lens->fnumber = NAN;
    lens->sensor_w = lens->sensor_h = NAN;
    lens->stop = -1;
}

void lens_free(lens_t *lens)
{
    free(lens->surf);
    free(lens->vertex_z);
    lens_init(lens);
}

lens_surface *lens_add_surface(lens_t *lens)
{
    lens_surface *s = realloc(lens->surf, (lens->nsurf + 1) * sizeof *s);
    if (!s)
        return NULL;
    lens->surf = s;
    s = &lens->surf[lens->nsurf++];
    memset(s, 0, sizeof *s);
    s->radius = INFINITY;
    s->medium = glass_air();
    strcpy(s->material, "air");
    return s;
}

lens_surface *lens_add_surface_at(lens_t *lens, const char *path, long line, lens_err *err)
{
    lens_surface *s = lens_add_surface(lens);
    if (!s) {
        lens_errf(err, path, line, "out of memory");
        return NULL;
    }
    s->line = line;
    return s;
}

int lens_copy(lens_t *dst, const lens_t *src)
{
    *dst = *src;
    dst->surf = NULL;
    dst->vertex_z = NULL;
    if (src->nsurf) {
        dst->surf = malloc(src->nsurf * sizeof *dst->surf);
        dst->vertex_z = malloc(src->nsurf * sizeof *dst->vertex_z);
        if (!dst->surf || !dst->vertex_z) {
            free(dst->surf);
            free(dst->vertex_z);
            lens_init(dst);
            return -1;
        }
        memcpy(dst->surf, src->surf, src->nsurf * sizeof *dst->surf);
        if (src->vertex_z)
            memcpy(dst->vertex_z, src->vertex_z, src->nsurf * sizeof *dst->vertex_z);
    }
    return 0;
}

double lens_total_track(const lens_t *lens)
{
    double z = 0;
    for (size_t i = 0; i < lens->nsurf; i++)
        z += lens->surf[i].thickness;
    return z;
}

int lens_surface_is_aspheric(const lens_surface *s)
{
    if (s->conic != 0)
        return 1;
    for (int i = 0; i < LENS_ASPHERE_TERMS; i++)
        if (s->asphere[i] != 0)
            return 1;
    return 0;
}

/* Polynomial part a4 h^4 + ... + a12 h^12 as a polynomial in h^2 (Horner). */
static double asphere_poly(const lens_surface *s, double h2)
{
    double p = 0;
    for (int i = LENS_ASPHERE_TERMS - 1; i >= 0; i--)
        p = p * h2 + s->asphere[i];
    return p * h2 * h2;
}

static double asphere_poly_slope(const lens_surface *s, double h2)
{
    /* d/d(h2) of sum a_{2j+4} h2^{j+2} */
    double p = 0;
    for (int i = LENS_ASPHERE_TERMS - 1; i >= 0; i--)
        p = p * h2 + (i + 2) * s->asphere[i];
    return p * h2;
}

/* A semi-diameter may equal the radius of a hemisphere (|R| = sd, the rim where the
 * surface turns parallel to the axis), but 1/R squared times sd squared rounds to a hair
 * above 1. Past the rim by this relative amount (|R| >= sd (1 - 1e-12), doubled for the
 * squares) is the rim itself. */
#define LENS_RIM_TOLERANCE 2.5e-12

double lens_sag(const lens_surface *s, double h2)
{
    double c = isfinite(s->radius) ? 1.0 / s->radius : 0.0;
    double disc = 1.0 - (1.0 + s->conic) * c * c * h2;
    if (disc < 0 && disc >= -LENS_RIM_TOLERANCE)
        disc = 0;
    if (disc < 0)
        return NAN;
    /* The rationalised form stays accurate for c -> 0 (no cancellation). */
    return c * h2 / (1.0 + sqrt(disc)) + asphere_poly(s, h2);
}

double lens_sag_slope(const lens_surface *s, double h2)
{
    double c = isfinite(s->radius) ? 1.0 / s->radius : 0.0;
    double disc = 1.0 - (1.0 + s->conic) * c * c * h2;
    if (disc <= 0)
        return NAN;
    /* d/d(h2) of c h2 / (1 + sqrt(disc)) = c / (2 sqrt(disc)) */
    return c / (2.0 * sqrt(disc)) + asphere_poly_slope(s, h2);
}

/* Media given by numbers obey the readers' range (glass_check_ndvd), however the lens
 * was built: an importer's model glass, a lens assembled in code. */
static int check_medium(const lens_surface *s, size_t i, const char *file, lens_err *err)
{
    if (s->medium.kind != GLASS_CONSTANT && s->medium.kind != GLASS_NDVD)
        return 0;
    char what[96];
    snprintf(what, sizeof what, "surface %zu: material '%.40s'", i + 1, s->material);
    return glass_check_ndvd(s->medium.nd, s->medium.kind == GLASS_NDVD ? s->medium.vd : NAN,
                            what, file, s->line, err);
}

/* Surfaces i and i+1 must not cross inside the smaller of their semi-diameters: the
 * axial gap t + sag(i+1, h) - sag(i, h) is the edge thickness of a lens element or the
 * air between two elements at height h, and a negative one is glass that would have to
 * overlap itself or its neighbour. Two allowances, both for what real prescriptions say:
 *  - elements in contact (a gap of 0 up to the digits a patent prints): a gap down to
 *    -LENS_CROSS_TOLERANCE mm, or that fraction of the height if larger, is contact;
 *  - a semi-diameter that is a mechanical (housing) radius, as in the .fx files and
 *    several shipped lenses, larger than where an element's faces actually meet: an
 *    element ground to a sharp edge at h0 has its clear aperture at h0, and the rays
 *    past h0 are lost in the tracer like any ray outside an aperture. So faces that meet
 *    only in the outer LENS_RIM_ZONE of the aperture are accepted; faces that cross
 *    further in (a thickness typo, a radius of the wrong sign) make no lens. The shipped
 *    lenses meet at 0.89 .. 0.995 of their semi-diameters where they meet at all.
 * The gap is sampled on LENS_CROSS_SAMPLES heights: spheres and the even aspheres of
 * real lenses bend slowly on that scale. */
#define LENS_CROSS_TOLERANCE 1e-3
#define LENS_RIM_ZONE 0.15
#define LENS_CROSS_SAMPLES 256

double lens_min_gap(const lens_t *lens, size_t i, double *at_h)
{
    const lens_surface *a = &lens->surf[i], *b = &lens->surf[i + 1];
    double hmax = fmin(a->semi_diameter, b->semi_diameter), worst = INFINITY;
    *at_h = 0;
    for (int k = 0; k <= LENS_CROSS_SAMPLES; k++) {
        double h = hmax * k / LENS_CROSS_SAMPLES;
        double gap = a->thickness + lens_sag(b, h * h) - lens_sag(a, h * h);
        if (gap < worst) {
            worst = gap;
            *at_h = h;
        }
    }
    return worst;
}

/* The first sampled height where the gap is below contact, or -1 if none. */
static double crossing_height(const lens_t *lens, size_t i, double *gap_there)
{
    const lens_surface *a = &lens->surf[i], *b = &lens->surf[i + 1];
    double hmax = fmin(a->semi_diameter, b->semi_diameter);
    for (int k = 0; k <= LENS_CROSS_SAMPLES; k++) {
        double h = hmax * k / LENS_CROSS_SAMPLES;
        double gap = a->thickness + lens_sag(b, h * h) - lens_sag(a, h * h);
        if (gap < -fmax(LENS_CROSS_TOLERANCE, LENS_CROSS_TOLERANCE * h)) {
            *gap_there = gap;
            return h;
        }
    }
    return -1;
}

static int check_crossing(const lens_t *lens, size_t i, const char *file, lens_err *err)
{
    const lens_surface *s = &lens->surf[i];
    double hmax = fmin(s->semi_diameter, lens->surf[i + 1].semi_diameter), gap;
    double h0 = crossing_height(lens, i, &gap);
    if (h0 < 0 || h0 > (1 - LENS_RIM_ZONE) * hmax)
        return 0;
    lens_errf(err, file, s->line,
              "surfaces %zu and %zu cross at height %g mm, inside their semi-diameter %g mm "
              "(%s %g mm there, %g on the axis): not a physical lens",
              i + 1, i + 2, h0, hmax, s->medium.kind != GLASS_AIR ? "edge thickness" : "air gap",
              gap, s->thickness);
    return -1;
}

int lens_finish(lens_t *lens, lens_err *err)
{
    const char *file = lens->path[0] ? lens->path : NULL;
    if (lens->nsurf == 0) {
        lens_errf(err, file, 0, "no surfaces");
        return -1;
    }
    int stop = -1;
    for (size_t i = 0; i < lens->nsurf; i++) {
        const lens_surface *s = &lens->surf[i];
        if (s->is_stop) {
            if (stop >= 0) {
                lens_errf(err, file, s->line, "a second aperture stop (the first is surface %d)",
                          stop + 1);
                return -1;
            }
            stop = (int)i;
        }
        if (!(s->semi_diameter > 0) || !isfinite(s->semi_diameter)) {
            lens_errf(err, file, s->line, "surface %zu: semi-diameter must be positive", i + 1);
            return -1;
        }
        if (!isfinite(s->thickness) || (i + 1 < lens->nsurf && s->thickness < 0)) {
            lens_errf(err, file, s->line, "surface %zu: thickness must be finite and not negative",
                      i + 1);
            return -1;
        }
        if (s->radius == 0 || isnan(s->radius) || !isfinite(s->conic)) {
            lens_errf(err, file, s->line, "surface %zu: radius must be non-zero (inf for flat)",
                      i + 1);
            return -1;
        }
        for (int k = 0; k < LENS_ASPHERE_TERMS; k++)
            if (!isfinite(s->asphere[k])) {
                lens_errf(err, file, s->line, "surface %zu: asphere coefficient is not finite",
                          i + 1);
                return -1;
            }
        if (isnan(lens_sag(s, s->semi_diameter * s->semi_diameter))) {
            lens_errf(err, file, s->line,
                      "surface %zu: semi-diameter %.15g exceeds what radius %.15g (conic %g) can reach",
                      i + 1, s->semi_diameter, s->radius, s->conic);
            return -1;
        }
        if (check_medium(s, i, file, err) != 0)
            return -1;
    }
    for (size_t i = 0; i + 1 < lens->nsurf; i++)
        if (check_crossing(lens, i, file, err) != 0)
            return -1;
    if (stop < 0) {
        lens_errf(err, file, 0, "no aperture stop (mark one surface with material 'stop')");
        return -1;
    }
    lens->stop = stop;
    free(lens->vertex_z);
    lens->vertex_z = malloc(lens->nsurf * sizeof *lens->vertex_z);
    if (!lens->vertex_z) {
        lens_errf(err, file, 0, "out of memory");
        return -1;
    }
    double z = 0;
    for (size_t i = 0; i < lens->nsurf; i++) {
        lens->vertex_z[i] = z;
        z += lens->surf[i].thickness;
    }
    return 0;
}
