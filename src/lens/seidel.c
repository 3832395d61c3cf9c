/* Paraxial ray table and Seidel sums (seidel.h). */
#include "sparselens/seidel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/glass.h"
#include "sparselens/paraxial.h"

static double curvature(const lens_surface *s)
{
    return isfinite(s->radius) && s->radius != 0 ? 1 / s->radius : 0;
}

int seidel_compute(const lens_t *lens, double lambda, double field, seidel_data *s, lens_err *err)
{
    memset(s, 0, sizeof *s);
    paraxial_data p;
    if (paraxial_compute(lens, lambda, &p, err) != 0)
        return -1;
    if (p.afocal || !isfinite(p.entrance_pupil_z) || !(p.entrance_pupil_diameter > 0)) {
        lens_errf(err, lens->path, 0, "no finite entrance pupil: the Seidel sums need one");
        return -1;
    }
    if (!(fabs(field) < 90)) {
        lens_errf(err, lens->path, 0, "field %g deg: must lie within (-90, 90)", field);
        return -1;
    }
    s->surf = calloc(lens->nsurf, sizeof *s->surf);
    if (!s->surf) {
        lens_errf(err, lens->path, 0, "out of memory");
        return -1;
    }
    s->nsurf = lens->nsurf, s->lambda = lambda, s->field = field;
    /* both rays at the first surface's vertex plane, object space of index 1 */
    double n = 1, y = p.entrance_pupil_diameter / 2, u = 0;
    double ub = tan(field * M_PI / 180), yb = -ub * p.entrance_pupil_z;
    s->y0 = y, s->ubar0 = ub;
    s->H = n * (u * yb - ub * y);
    for (size_t i = 0; i < lens->nsurf; i++) {
        const lens_surface *sf = &lens->surf[i];
        double c = curvature(sf), n2 = glass_index_unchecked(&sf->medium, lambda);
        double A = n * (u + y * c), Ab = n * (ub + yb * c);
        double u2 = (n * u - y * (n2 - n) * c) / n2, ub2 = (n * ub - yb * (n2 - n) * c) / n2;
        double D = u2 / n2 - u / n;
        seidel_surface *o = &s->surf[i];
        o->S[0] = -A * A * y * D;
        o->S[1] = -A * Ab * y * D;
        o->S[2] = -Ab * Ab * y * D;
        o->S[3] = -s->H * s->H * c * (1 / n2 - 1 / n);
        if (fabs(A) > 1e-12 * fabs(Ab))
            o->S[4] = Ab / A * (o->S[2] + o->S[3]);
        else if (fabs(o->S[2] + o->S[3]) > 0)
            s->s5_undefined++;
        /* the quartic departure of a conic or asphere from the sphere of the same c */
        double d = sf->conic * c * c * c / 8 + sf->asphere[0];
        if (d != 0 && y != 0) {
            double dS = 8 * (n2 - n) * d * y * y * y * y, r = yb / y;
            o->S[0] += dS, o->S[1] += dS * r, o->S[2] += dS * r * r, o->S[4] += dS * r * r * r;
        }
        o->y = y, o->u = u2, o->ybar = yb, o->ubar = ub2, o->n = n2;
        for (int k = 0; k < 5; k++)
            s->sum[k] += o->S[k];
        n = n2, u = u2, ub = ub2;
        y += sf->thickness * u, yb += sf->thickness * ub;
    }
    return 0;
}

void seidel_free(seidel_data *s)
{
    free(s->surf);
    memset(s, 0, sizeof *s);
}
