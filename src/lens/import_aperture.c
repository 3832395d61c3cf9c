/* Clear apertures the design file leaves to the program (Zemax surfaces without DIAM,
 * CODE V surfaces without CIR): both programs size them from the rays of the file's
 * aperture and fields, and so does this, paraxially (import_common.h). */
#include "lens/import_common.h"

#include <math.h>
#include <stdlib.h>

/* Heights of a paraxial ray (y, nu = n u in air) at every surface. */
static void trace_heights(const lens_t *lens, const double *n, double y, double nu, double *ys,
                          double *nu_out)
{
    double before = 1.0;
    for (size_t i = 0; i < lens->nsurf; i++) {
        const lens_surface *s = &lens->surf[i];
        ys[i] = y;
        nu -= y * (isfinite(s->radius) ? 1.0 / s->radius : 0.0) * (n[i] - before);
        y += s->thickness * nu / n[i];
        before = n[i];
    }
    if (nu_out)
        *nu_out = nu;
}

double import_top_field(const lens_t *lens)
{
    double top = 0;
    for (int i = 0; i < lens->nfields; i++)
        top = fmax(top, hypot(lens->field_x[i], lens->field_y[i]));
    return top;
}

/* The top field as an angle in degrees for an object at infinity: image heights through
 * the focal length (y' = f tan u); object heights say nothing of an object at infinity. */
static double top_field_angle(const lens_t *lens, double efl)
{
    double top = import_top_field(lens);
    switch (lens->field_kind) {
    case LENS_FIELD_ANGLE:
        return top < 90 ? top : 0;
    case LENS_FIELD_IMAGE_HEIGHT:
    case LENS_FIELD_REAL_IMAGE_HEIGHT:
        return isfinite(efl) && efl != 0 ? atan(top / fabs(efl)) * 180 / M_PI : 0;
    default:
        return 0;
    }
}

int import_size_apertures(lens_t *lens, const int *missing, double epd_mm, double fno,
                          const char *key, const char *aperture_keys, lens_err *err)
{
    size_t ns = lens->nsurf;
    int k = 0;
    for (size_t i = 0; i < ns; i++)
        k += missing[i] != 0;
    if (k == 0)
        return 0;
    double *buf = calloc(4 * ns, sizeof *buf);
    if (!buf) {
        lens_errf(err, lens->path, 0, "out of memory");
        return -1;
    }
    double *n = buf, *ym = buf + ns, *ya = buf + 2 * ns, *yb = buf + 3 * ns;
    for (size_t i = 0; i < ns; i++) {
        lens_err e;
        if (glass_index(&lens->surf[i].medium, GLASS_D_LINE, &n[i], &e) != 0) {
            lens_errf(err, lens->path, lens->surf[i].line, "%s", e.msg);
            free(buf);
            return -1;
        }
    }
    double nu_last;
    trace_heights(lens, n, 1.0, 0.0, yb, &nu_last); /* the efl, and a ray for the chief */
    double efl = nu_last != 0 ? -1.0 / nu_last : NAN;
    double epd = isfinite(epd_mm) && epd_mm > 0 ? epd_mm
                 : isfinite(fno) && fno > 0     ? fabs(efl) / fno
                                                : NAN;
    /* No aperture value: the stop's own clear aperture, where the file gives it, is the
     * aperture (Zemax's "float by stop size"), its image in object space the pupil. */
    int st = lens->stop >= 0 ? lens->stop : -1;
    for (size_t i = 0; st < 0 && i < ns; i++)
        if (lens->surf[i].is_stop)
            st = (int)i;
    if (!(epd > 0) && st >= 0 && !missing[st] && lens->surf[st].semi_diameter > 0 && yb[st] != 0)
        epd = 2 * lens->surf[st].semi_diameter / fabs(yb[st]);
    if (!(epd > 0) || !isfinite(epd)) {
        free(buf);
        lens_errf(err, lens->path, 0, "%d surface%s without a clear aperture (%s), and no %s to size them",
                  k, k > 1 ? "s" : "", key, aperture_keys);
        return -1;
    }
    trace_heights(lens, n, epd / 2, 0.0, ym, NULL);
    double field = top_field_angle(lens, efl);
    trace_heights(lens, n, 0.0, tan(field * M_PI / 180), ya, NULL);
    int stop = 0;
    for (size_t i = 0; i < ns; i++)
        if (lens->surf[i].is_stop)
            stop = (int)i;
    /* The chief ray: the field's ray plus the axis-parallel one that puts it through the
     * stop centre. The top field's beam reaches |marginal| + |chief| on every surface. */
    double y0 = yb[stop] != 0 ? -ya[stop] / yb[stop] : 0;
    for (size_t i = 0; i < ns; i++)
        if (missing[i])
            lens->surf[i].semi_diameter = fabs(ym[i]) + fabs(ya[i] + y0 * yb[i]);
    lens_add_note(lens, "%d semi-diameter%s not in the file (%s), set from paraxial rays "
                        "(EPD %g mm, field %g deg)",
                  k, k > 1 ? "s" : "", key, epd, field);
    free(buf);
    return 0;
}

int import_set_fields(lens_t *lens, lens_field_kind kind, const double *x, int nx,
                      const double *y, int n, lens_err *err)
{
    if (n > LENS_MAX_FIELDS) {
        lens_errf(err, lens->path, 0, "%d fields: at most %d are read", n, LENS_MAX_FIELDS);
        return -1;
    }
    lens->field_kind = n > 0 ? kind : LENS_FIELD_NONE;
    lens->nfields = n;
    for (int i = 0; i < n; i++) {
        lens->field_x[i] = x && i < nx ? x[i] : 0;
        lens->field_y[i] = y[i];
    }
    return 0;
}

int import_set_waves(lens_t *lens, const double *um, const double *weight, int n, int primary,
                     lens_err *err)
{
    if (n > LENS_MAX_WAVES) {
        lens_errf(err, lens->path, 0, "%d wavelengths: at most %d are read", n, LENS_MAX_WAVES);
        return -1;
    }
    lens->nwaves = n;
    for (int i = 0; i < n; i++) {
        lens->wave_um[i] = um[i];
        lens->wave_weight[i] = weight ? weight[i] : 1;
    }
    lens->primary_wave = primary >= 1 && primary <= n ? primary : 0;
    return 0;
}

void import_seat_stop(lens_t *lens)
{
    size_t i = lens->stop >= 0 ? (size_t)lens->stop : lens->nsurf;
    for (size_t k = 0; k < lens->nsurf; k++)
        if (lens->surf[k].is_stop)
            i = k;
    if (i + 1 >= lens->nsurf)
        return;
    lens_surface *s = &lens->surf[i];
    const lens_surface *next = &lens->surf[i + 1];
    int air_before = i == 0 || lens->surf[i - 1].medium.kind == GLASS_AIR;
    if (isfinite(s->radius) || s->conic != 0 || lens_surface_is_aspheric(s) ||
        s->medium.kind != GLASS_AIR || !air_before || s->thickness > 1e-6)
        return;
    /* A plane stop on the vertex of a surface curving towards it: the stop ring rests on
     * that surface at its rim, where the surface is sag(rim) in front of its vertex. */
    double r2 = s->semi_diameter * s->semi_diameter;
    double gap = s->thickness + lens_sag(next, r2);
    if (!(gap < 0) || !isfinite(gap))
        return;
    double shift = -gap;
    if (i > 0) {
        lens_surface *prev = &lens->surf[i - 1];
        if (prev->thickness < shift)
            return; /* no room in front: lens_finish says the surfaces cross */
        prev->thickness -= shift;
    }
    s->thickness += shift;
    lens_add_note(lens, "stop plane moved %.3g mm in front of surface %zu's vertex, onto its "
                        "rim (the file puts it on the vertex)",
                  shift, i + 2);
}
