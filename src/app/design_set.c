/* The set-up shared by the designer commands (design_set.h). */
#include "sparselens/design_set.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/ray_bundle.h"

int design_set_focus(design_set *ds, lens_err *err)
{
    double shift = 0;
    if (ds->focus == FOCUS_PARAXIAL &&
        imaging_paraxial_shift(ds->im[0].lens, ds->im[0].object_distance, ds->lambda[ds->primary],
                               &shift, err) != 0)
        return -1;
    if (ds->focus == FOCUS_BEST) {
        size_t n = (size_t)ds->nfields * (size_t)ds->nl;
        spot *sp = calloc(n ? n : 1, sizeof *sp);
        if (!sp) {
            lens_errf(err, NULL, 0, "out of memory");
            return -1;
        }
        int rc = 0;
        imaging im = ds->im[0];
        im.sensor_shift = 0;
        for (size_t i = 0; i < n && rc == 0; i++)
            rc = spot_trace(&im, ds->field[i / (size_t)ds->nl], ds->lambda[i % (size_t)ds->nl],
                            PUPIL_HEXAPOLAR, 400, 1, &sp[i], err);
        if (rc == 0)
            shift = spot_best_shift(sp, n);
        for (size_t i = 0; i < n; i++)
            spot_free(&sp[i]);
        free(sp);
        if (rc != 0)
            return -1;
    }
    ds->sensor_shift = shift;
    for (int m = 0; m < ds->nmodels; m++)
        ds->im[m].sensor_shift = shift;
    return 0;
}

void design_set_print_time(FILE *f, const design_set *ds, const char *what)
{
    fprintf(f, "# time imaging %s: %s %.4g s", what, ds->names[0], ds->seconds[0]);
    if (ds->nmodels > 1)
        fprintf(f, ", %s %.4g s (%.3g x the %s's)", ds->names[1], ds->seconds[1],
                ds->seconds[0] > 0 ? ds->seconds[1] / ds->seconds[0] : NAN, ds->names[0]);
    fputc('\n', f);
}

const char *design_set_field_unit(const design_set *ds)
{
    return isfinite(ds->im[0].object_distance) ? "mm" : "deg";
}

int design_set_chief(const design_set *ds, int m, double field, double lambda, double s[4],
                     lens_err *err)
{
    if (bundle_chief(&ds->im[m], field, lambda, s, err) == 0)
        return 0;
    run_error_model(err, m, ds->names[m]);
    return -1;
}

void design_set_from_cli(const char *prog, imaging_cli *a, imaging_models *models, double *field,
                         design_set *ds)
{
    memset(ds, 0, sizeof *ds);
    ds->nmodels = imaging_cli_load(prog, a, models, ds->im, ds->names);
    ds->lambda = a->lambda, ds->nl = a->nl, ds->primary = a->nl / 2;
    ds->focus = a->focus_mode;
    lens_err err;
    int nf = a->fields ? numbers_parse(a->fields, "field", field, IMAGING_MAX_FIELDS, &err)
                       : imaging_default_fields(&ds->im[0], a->lambda, a->nl, field, &err);
    if (nf < 0) {
        imaging_models_free(models);
        diag_die(prog, "%s%s", a->fields ? "--fields: " : "", err.msg);
    }
    ds->field = field, ds->nfields = nf;
}

void design_set_title(const imaging_cli *a, const imaging_models *models, const char *what,
                      char *title, size_t size)
{
    snprintf(title, size, "%s  %s", models->lens.name[0] ? models->lens.name : imaging_cli_basename(a),
             what);
}
