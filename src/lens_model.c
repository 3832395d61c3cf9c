/* The lens model's geometry: construction, checks, sag and slope of a surface. */
#include "lens.h"

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

double lens_sag(const lens_surface *s, double h2)
{
    double c = isfinite(s->radius) ? 1.0 / s->radius : 0.0;
    double disc = 1.0 - (1.0 + s->conic) * c * c * h2;
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
                      "surface %zu: semi-diameter %g exceeds what radius %g (conic %g) can reach",
                      i + 1, s->semi_diameter, s->radius, s->conic);
            return -1;
        }
    }
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
