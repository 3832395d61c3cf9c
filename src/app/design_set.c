/* The set-up shared by the designer commands (design_set.h). */
#include "sparselens/design_set.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/cli.h"
#include "sparselens/ray_bundle.h"

int design_set_focus(design_set *ds, lens_err *err)
{
    if (ds->focused)
        return 0;
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
        for (size_t i = 0; i < n && rc >= 0; i++)
            rc = spot_trace(&im, ds->field[i / (size_t)ds->nl], ds->lambda[i % (size_t)ds->nl],
                            PUPIL_HEXAPOLAR, 400, 1, &sp[i], err);
        /* a field the lens cannot image (rc 1) has no rays, so no say in the plane */
        if (rc >= 0)
            shift = spot_best_shift(sp, n);
        for (size_t i = 0; i < n; i++)
            spot_free(&sp[i]);
        free(sp);
        if (rc < 0)
            return -1;
    }
    ds->sensor_shift = shift;
    for (int m = 0; m < ds->nmodels; m++)
        ds->im[m].sensor_shift = shift;
    ds->focused = 1;
    return 0;
}

void design_set_print_footer(table_out *t, const design_set *ds, const char *what)
{
    double ratio = ds->seconds[0] > 0 ? ds->seconds[1] / ds->seconds[0] : NAN;
    if (!t->json) {
        if (ds->sensor_shift != 0)
            fprintf(t->f, "# sensor plane moved %.9g mm along the axis\n", ds->sensor_shift);
        fprintf(t->f, "# time imaging %s: %s %.4g s", what, ds->names[0], ds->seconds[0]);
        if (ds->nmodels > 1)
            fprintf(t->f, ", %s %.4g s (%.3g x the %s's)", ds->names[1], ds->seconds[1], ratio, ds->names[0]);
        fputc('\n', t->f);
        return;
    }
    table_out_keys(t, "sensor", NULL);
    table_out_key_num(t, "shift_mm", ds->sensor_shift);
    table_out_keys(t, "time", NULL);
    for (int m = 0; m < ds->nmodels; m++) {
        char key[32];
        snprintf(key, sizeof key, "%s_s", ds->names[m]);
        table_out_key_num(t, key, ds->seconds[m]);
    }
    if (ds->nmodels > 1) {
        table_out_key_num(t, "ratio", ratio);
    }
}

void design_set_print_difference(table_out *t, const design_set *ds, const char *text, int n,
                                 const char *const *keys, const double *values)
{
    if (!t->json) {
        fprintf(t->f, "# %s - %s: %s\n", ds->names[1], ds->names[0], text);
        return;
    }
    table_out_keys(t, "difference", NULL);
    for (int i = 0; i < n; i++) {
        table_out_key_num(t, keys[i], values[i]);
    }
}

const char *design_set_field_unit(const design_set *ds)
{
    return isfinite(ds->im[0].object_distance) ? "mm" : "deg";
}

int design_set_chief(const design_set *ds, int m, double field, double lambda, double s[4],
                     lens_err *err)
{
    int rc = bundle_chief(&ds->im[m], field, lambda, s, err);
    if (rc != 0)
        run_error_model(err, m, ds->names[m]);
    return rc;
}

int design_set_imaged(design_set *ds, int m, int f, int all_lambda, const char *tail, lens_err *err)
{
    for (int l = 0; l < ds->nl; l++) {
        if (!all_lambda && l != ds->primary)
            continue;
        double s[4];
        lens_err why;
        int rc = bundle_chief(&ds->im[m], ds->field[f], ds->lambda[l], s, &why);
        if (rc < 0) {
            *err = why;
            run_error_model(err, m, ds->names[m]);
            return -1;
        }
        if (rc > 0) { /* the first wavelength that fails says why */
            if (ds->nwarnings < 2 * IMAGING_MAX_FIELDS)
                snprintf(ds->warning[ds->nwarnings++], sizeof ds->warning[0], "%s: %.480s; %s", ds->names[m],
                         why.msg, tail);
            return 1;
        }
    }
    return 0;
}

/* The fields: --fields, or the default ones (spread: that many from 0 to the largest). */
static int fields_from_cli(const imaging_cli *a, const imaging *im, int spread, double *field,
                           lens_err *err)
{
    if (a->fields)
        return numbers_parse(a->fields, "field", field, IMAGING_MAX_FIELDS, err);
    int n = imaging_default_fields(im, a->lambda, a->nl, field, err);
    if (n <= 0 || spread <= 0)
        return n;
    double top = field[n - 1];
    n = top > 0 ? spread : 1;
    for (int i = 0; i < n; i++)
        field[i] = top * i / (spread - 1.0);
    return n;
}

void design_run_begin(const char *prog, design_run *r, imaging_cli *a, const output_cli *out,
                      int spread, const char *what, design_set *ds)
{
    memset(ds, 0, sizeof *ds);
    r->set = ds;
    ds->nmodels = imaging_cli_load(prog, a, &r->models, ds->im, ds->names);
    ds->lambda = a->lambda, ds->nl = a->nl, ds->primary = a->primary;
    ds->focus = a->focus_mode;
    lens_err err;
    int nf = fields_from_cli(a, &ds->im[0], spread, r->field, &err);
    if (nf < 0) {
        imaging_models_free(&r->models);
        diag_die(prog, "%s%s", a->fields ? "--fields: " : "", err.msg);
    }
    ds->field = r->field, ds->nfields = nf;
    if (design_set_focus(ds, &err) != 0) {
        imaging_models_free(&r->models);
        diag_die(prog, "%s", err.msg);
    }
    imaging_cli_setup(a, &r->models, ds->lambda[ds->primary], ds->sensor_shift, &r->setup);
    snprintf(r->title, sizeof r->title, "%s  %s  %s",
             r->models.lens.name[0] ? r->models.lens.name : imaging_cli_basename(a), what,
             r->setup.text);
    r->written[0] = a->png, r->written[1] = NULL;
    output_cli_begin(out, &r->t, stdout, 6);
}

int design_run_end(const char *prog, design_run *r, int rc, const lens_err *err)
{
    int status = rc != 0;
    if (rc == 0) {
        imaging_setup_print(&r->t, &r->setup, &r->models);
        /* a field a model cannot image: the table is whole (nan rows), the status says so */
        report_warning w[2 * IMAGING_MAX_FIELDS + 1];
        int nw = imaging_cli_model_warning(&r->models, w);
        memcpy(w + nw, r->set->warning, (size_t)r->set->nwarnings * sizeof *w);
        imaging_cli_end_table(&r->t, stderr, prog, w, nw + r->set->nwarnings);
        status = r->set->nwarnings ? 2 : 0; /* the model's warning alone leaves it 0 */
        if (cli_end_stdout(prog, r->written, 2))
            status = 1;
    } else {
        table_out_end(&r->t, NULL, 0);
        diag_print(prog, err);
    }
    imaging_models_free(&r->models);
    return status;
}
