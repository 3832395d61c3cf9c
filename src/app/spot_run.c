/* The whole lens-spot job as a library call: every field and wavelength for each model,
 * the focus, the polychromatic pools, the table (see spot_run.h). */
#include "sparselens/spot_run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void spot_report_free(spot_report *rep)
{
    size_t n = (size_t)rep->nmodels * (size_t)rep->nfields;
    if (rep->spots)
        for (size_t i = 0; i < n * (size_t)rep->nl; i++)
            spot_free(&rep->spots[i]);
    if (rep->pooled)
        for (size_t i = 0; i < n; i++)
            spot_free(&rep->pooled[i]);
    free(rep->spots);
    free(rep->pooled);
    free(rep->why);
    memset(rep, 0, sizeof *rep);
}

void run_error_model(lens_err *err, int m, const char *name)
{
    if (m == 0)
        return;
    char msg[sizeof err->msg];
    snprintf(msg, sizeof msg, "%s", err->msg);
    lens_errf(err, NULL, 0, "%s: %s", name, msg);
}

int spot_run(const spot_request *rq, spot_report *rep, lens_err *err)
{
    memset(rep, 0, sizeof *rep);
    int nm = rq->nmodels, nf = rq->nfields, nl = rq->nl;
    size_t n = (size_t)nm * (size_t)nf;
    rep->spots = calloc(n * (size_t)nl, sizeof *rep->spots);
    rep->pooled = calloc(n, sizeof *rep->pooled);
    rep->why = calloc(n, sizeof *rep->why);
    if (!rep->spots || !rep->pooled || !rep->why) {
        free(rep->spots), free(rep->pooled), free(rep->why);
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    rep->nmodels = nm, rep->nfields = nf, rep->nl = nl;
    imaging im[2] = {rq->im[0], rq->im[1]};
    double shift = 0;
    if (rq->focus == FOCUS_PARAXIAL &&
        imaging_paraxial_shift(im[0].lens, im[0].object_distance, rq->lambda[rq->primary], &shift,
                               err) != 0)
        goto fail;
    for (int m = 0; m < nm; m++)
        im[m].sensor_shift = shift;
    for (int m = 0; m < nm; m++)
        for (int f = 0; f < nf; f++)
            for (int l = 0; l < nl; l++) {
                spot *s = &rep->spots[((size_t)m * nf + f) * nl + l];
                int st = spot_trace(&im[m], rq->field[f], rq->lambda[l], rq->pattern, rq->rays,
                                    rq->seed, s, err);
                if (st < 0) {
                    run_error_model(err, m, rq->model_names[m]);
                    goto fail;
                }
                lens_err *why = &rep->why[(size_t)m * nf + f];
                if (st > 0 && !why->msg[0]) { /* the first wavelength that fails says why */
                    *why = *err;
                    rep->not_imaged++;
                }
            }
    if (rq->focus == FOCUS_BEST) {
        /* one plane for every model (the first one's best), so a system is judged at
         * the lens's focus */
        double dz = spot_best_shift(rep->spots, (size_t)nf * (size_t)nl);
        for (size_t i = 0; i < n * (size_t)nl; i++) {
            spot_shift(&rep->spots[i], dz);
            spot_stats(&rep->spots[i]);
        }
        shift += dz;
    }
    rep->sensor_shift = shift;
    for (size_t i = 0; i < n; i++) {
        if (spot_pool(&rep->spots[i * (size_t)nl], (size_t)nl, (size_t)rq->primary, &rep->pooled[i]) != 0) {
            lens_errf(err, NULL, 0, "out of memory");
            goto fail;
        }
        if (rep->why[i].msg[0]) /* a wavelength missing: no pooled spot either */
            spot_mark_not_imaged(&rep->pooled[i]);
    }
    return 0;
fail:
    spot_report_free(rep);
    return -1;
}

int spot_report_warnings(const spot_request *rq, const spot_report *rep, report_warning *w, int max)
{
    int n = 0;
    for (int m = 0; m < rep->nmodels; m++)
        for (int fi = 0; fi < rep->nfields; fi++) {
            const lens_err *why = &rep->why[(size_t)m * rep->nfields + fi];
            if (why->msg[0] && n < max)
                snprintf(w[n++], sizeof w[0], "%s: %.480s; its rows are nan", rq->model_names[m], why->msg);
        }
    return n;
}

/* Positions on the sensor that cancel to round-off (a centroid on the axis) are zero on
 * the scale of the largest image height in the table. */
static double position_scale(const spot_report *rep)
{
    double s = 1;
    size_t n = (size_t)rep->nmodels * (size_t)rep->nfields * (size_t)rep->nl;
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 2; k++)
            if (isfinite(rep->spots[i].chief[k]))
                s = fmax(s, fabs(rep->spots[i].chief[k]));
    return s;
}

static void row(table_out *t, const char *model, const spot *s, double L)
{
    table_out_str(t, model);
    table_out_fmt(t, s->field, 0, "%.10g");
    if (isnan(s->lambda)) /* the pooled wavelengths */
        table_out_str(t, "all");
    else
        table_out_fmt(t, s->lambda, 0, "%.7g");
    table_out_int(t, (long long)s->rays);
    table_out_int(t, (long long)s->passed);
    table_out_fmt(t, s->vignetted, 0, "%.6f");
    for (int k = 0; k < 2; k++)
        table_out_fmt(t, s->chief[k], L, "%.9g");
    for (int k = 0; k < 2; k++)
        table_out_fmt(t, s->centroid[k], L, "%.9g");
    double um[] = {s->rms_chief, s->max_chief, s->rms_centroid, s->max_centroid, s->airy};
    for (int k = 0; k < 5; k++)
        table_out_fmt(t, um[k] * 1e3, L * 1e3, "%.6g");
    table_out_row_end(t);
}

void spot_report_print(table_out *t, const spot_request *rq, const spot_report *rep,
                       const char *focus_name)
{
    int finite = isfinite(rq->im[0].object_distance);
    const char *cols[] = {"model", finite ? "field_mm" : "field_deg", "lambda_um", "rays", "passed",
                          "vignetted", "chief_x_mm", "chief_y_mm", "centroid_x_mm", "centroid_y_mm",
                          "rms_chief_um", "max_chief_um", "rms_centroid_um", "max_centroid_um",
                          "airy_um"};
    double L = position_scale(rep);
    table_out_table(t, "spots", NULL, cols, (int)(sizeof cols / sizeof cols[0]));
    for (int m = 0; m < rep->nmodels; m++)
        for (int fi = 0; fi < rep->nfields; fi++) {
            for (int l = 0; l < rep->nl; l++)
                row(t, rq->model_names[m], &rep->spots[((size_t)m * rep->nfields + fi) * rep->nl + l], L);
            if (rep->nl > 1)
                row(t, rq->model_names[m], &rep->pooled[(size_t)m * rep->nfields + fi], L);
        }
    if (!t->json) { /* as before: a comment under the table */
        if (rep->sensor_shift != 0)
            fprintf(t->f, "# sensor plane moved %.9g mm along the axis (--focus %s)\n",
                    rep->sensor_shift, focus_name);
        return;
    }
    table_out_keys(t, "sensor", NULL);
    table_out_key_str(t, "focus", focus_name);
    table_out_key_num(t, "shift_mm", rep->sensor_shift);
}

int focus_mode_parse(const char *s, focus_mode *mode)
{
    static const char *const names[] = {"file", "paraxial", "best"};
    for (int i = 0; i < 3; i++)
        if (strcmp(s, names[i]) == 0) {
            *mode = (focus_mode)i;
            return 0;
        }
    return -1;
}
