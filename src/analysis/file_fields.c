/* The fields, wavelengths and image size a design file states (lens_t.field_kind and the
 * lists the importers keep), turned into what the analyses and the sampler take: field
 * angles for an object at infinity, and a sensor whose corner is the largest field. */
#include "sparselens/file_fields.h"

#include <math.h>
#include <stdlib.h>

#include "sparselens/field_of_view.h"
#include "sparselens/paraxial.h"

/* The half field (degrees) of the sensor of a file that states only the axis. */
#define AXIS_ONLY_FIELD 1.0

/* How far past the largest field the sensor corner lies, as a fraction of its radius. */
#define FIELD_MARGIN 0.03

double lens_file_primary_wave(const lens_t *lens)
{
    if (lens->primary_wave >= 1 && lens->primary_wave <= lens->nwaves)
        return lens->wave_um[lens->primary_wave - 1];
    return lens->nwaves > 0 ? lens->wave_um[0] : GLASS_D_LINE;
}

/* The file's primary wavelength where every glass of the lens has an index there, else
 * the d line; n gets the indices. */
static int indices_at_primary(const lens_t *lens, double *n, double *lambda, lens_err *err)
{
    *lambda = lens_file_primary_wave(lens);
    if (lens_indices(lens, *lambda, n, NULL) == 0)
        return 0;
    *lambda = GLASS_D_LINE;
    return lens_indices(lens, *lambda, n, err);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* One field as an angle in degrees (object at infinity); NAN when it cannot be said. */
static double field_angle(const lens_t *lens, const double *n, double efl, double r)
{
    double a;
    switch (lens->field_kind) {
    case LENS_FIELD_ANGLE:
        return r;
    case LENS_FIELD_IMAGE_HEIGHT: /* the paraxial image height is efl tan(angle) */
        return isfinite(efl) && efl != 0 ? atan(r / fabs(efl)) * 180 / M_PI : NAN;
    case LENS_FIELD_REAL_IMAGE_HEIGHT:
        return r == 0 ? 0 : lens_chief_angle(lens, n, r, &a) == 0 ? a : NAN;
    default:
        return NAN;
    }
}

int lens_file_fields(const lens_t *lens, double object_distance, double *field, int max,
                     lens_err *err)
{
    if (lens->nfields <= 0 || lens->field_kind == LENS_FIELD_NONE)
        return 0;
    int finite = isfinite(object_distance), heights = lens->field_kind == LENS_FIELD_OBJECT_HEIGHT;
    if (finite != heights) /* the file's fields are for another kind of object */
        return 0;
    double *n = malloc(sizeof(double) * (lens->nsurf ? lens->nsurf : 1)), lambda, efl = NAN;
    paraxial_data p;
    if (!n || indices_at_primary(lens, n, &lambda, err) != 0) {
        if (!n)
            lens_errf(err, NULL, 0, "out of memory");
        free(n);
        return -1;
    }
    if (paraxial_compute(lens, lambda, &p, NULL) == 0)
        efl = p.efl;
    int k = 0;
    for (int i = 0; i < lens->nfields && k < max; i++) {
        double r = hypot(lens->field_x[i], lens->field_y[i]);
        double f = heights ? r : field_angle(lens, n, efl, r);
        if (isfinite(f))
            field[k++] = f;
    }
    free(n);
    qsort(field, (size_t)k, sizeof *field, cmp_double);
    int m = 0; /* the same field named twice (x and y lists) is one field */
    for (int i = 0; i < k; i++)
        if (m == 0 || field[i] != field[m - 1])
            field[m++] = field[i];
    return m;
}

int lens_sensor_from_fields(lens_t *lens, lens_err *err)
{
    if (isfinite(lens->sensor_w) && isfinite(lens->sensor_h))
        return 0;
    double field[LENS_MAX_FIELDS];
    int k = lens_file_fields(lens, INFINITY, field, LENS_MAX_FIELDS, err);
    if (k < 0)
        return -1;
    /* A file that states the axis alone (a telescope objective, a laser lens) is used
     * on and about the axis: a sensor for a small field about it, AXIS_ONLY_FIELD. */
    int axis_only = k > 0 && !(field[k - 1] > 0);
    if (axis_only)
        field[k - 1] = AXIS_ONLY_FIELD; /* the top field; the axis stays in the file */
    if (k <= 0)
        return 0;
    double *n = malloc(sizeof(double) * lens->nsurf), lambda;
    if (!n || indices_at_primary(lens, n, &lambda, err) != 0) {
        if (!n)
            lens_errf(err, NULL, 0, "out of memory");
        free(n);
        return -1;
    }
    /* The image radius of the largest field: where its real chief ray lands, the height
     * itself for real image heights. */
    double top = field[k - 1], r = NAN;
    for (int i = 0; i < lens->nfields && !axis_only && lens->field_kind == LENS_FIELD_REAL_IMAGE_HEIGHT; i++)
        r = fmax(isnan(r) ? 0 : r, hypot(lens->field_x[i], lens->field_y[i]));
    if (isnan(r)) {
        imaging im = {.lens = lens, .object_distance = INFINITY};
        double s[4];
        if (imaging_chief(&im, n, lambda, top, s, NULL) == 0)
            r = hypot(s[0], s[1]);
    }
    free(n);
    if (!(r > 0) || !isfinite(r)) {
        lens_errf(err, lens->path[0] ? lens->path : NULL, 0,
                  "the file's largest field (%g deg) has no chief ray reaching the image: "
                  "give --sensor WxH", top);
        return -1;
    }
    /* A 3:2 sensor (the shape of most of the shipped lenses') with its corner a little
     * beyond that radius: a system fitted over it then has the largest field inside its
     * domain, not on the edge where its samples thin out. */
    r *= 1 + FIELD_MARGIN;
    lens->sensor_w = 2 * r * 3 / sqrt(13);
    lens->sensor_h = 2 * r * 2 / sqrt(13);
    return 1;
}
