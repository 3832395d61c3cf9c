/* lens-field's job (field_run.h). */
#include "sparselens/field_run.h"

#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "sparselens/distort.h"
#include "sparselens/paraxial.h"
#include "sparselens/plot.h"

int field_focal_shift(const imaging *im, const double *lambda, int n, double ref_lambda,
                      double delta, double *shift, double *seconds, lens_err *err)
{
    field_focus ref, ff;
    if (field_focus_trace(im, 0, ref_lambda, delta, &ref, err) != 0)
        return -1;
    *seconds += ref.seconds;
    for (int i = 0; i < n; i++) {
        if (field_focus_trace(im, 0, lambda[i], delta, &ff, err) != 0)
            return -1;
        *seconds += ff.seconds;
        shift[i] = ff.z_sag - ref.z_sag;
    }
    return 0;
}

/* The row of a field the model cannot image: every figure nan. */
static void not_imaged(field_row *r, double field, double lambda)
{
    r->focus = (field_focus){.field = field, .lambda = lambda, .chief = {NAN, NAN, NAN, NAN},
                             .z_tan = NAN, .z_sag = NAN};
    r->distortion_pct = r->lateral_um = NAN;
}

static int run_rows(field_request *rq, field_row *rows, lens_err *err)
{
    design_set *ds = &rq->set;
    double scale;
    lens_err none;
    /* an afocal lens (a window) has field curves but no ideal image height */
    if (distort_scale(&ds->im[0], ds->lambda[ds->primary], &scale, &none) != 0)
        scale = NAN;
    int finite = isfinite(ds->im[0].object_distance);
    for (int m = 0; m < ds->nmodels; m++)
        for (int f = 0; f < ds->nfields; f++) {
            field_row *r = &rows[((size_t)m * ds->nfields + f) * ds->nl];
            int st = design_set_imaged(ds, m, f, 1, "its rows are nan", err);
            if (st < 0)
                return -1;
            if (st > 0) {
                for (int l = 0; l < ds->nl; l++)
                    not_imaged(&r[l], ds->field[f], ds->lambda[l]);
                continue;
            }
            for (int l = 0; l < ds->nl; l++) {
                if (field_focus_trace(&ds->im[m], ds->field[f], ds->lambda[l], rq->delta, &r[l].focus,
                                      err) != 0) {
                    run_error_model(err, m, ds->names[m]);
                    return -1;
                }
                ds->seconds[m] += r[l].focus.seconds;
            }
            double ideal = finite ? scale * ds->field[f] : scale * tan(ds->field[f] * M_PI / 180);
            double y0 = r[ds->primary].focus.chief[1];
            for (int l = 0; l < ds->nl; l++) {
                double y = r[l].focus.chief[1];
                r[l].distortion_pct = ds->field[f] == 0 ? 0 : 100 * (y - ideal) / ideal;
                r[l].lateral_um = 1e3 * (y - y0);
            }
        }
    return 0;
}

static void print_rows(table_out *t, const design_set *ds, const field_row *rows)
{
    const char *cols[] = {"model", isfinite(ds->im[0].object_distance) ? "field_mm" : "field_deg",
                          "lambda_um", "chief_y_mm", "z_tan_mm", "z_sag_mm", "astig_mm", "petzval_mm",
                          "distortion_pct", "lateral_colour_um"};
    table_out_table(t, "field_curves", NULL, cols, 10);
    for (int m = 0; m < ds->nmodels; m++)
        for (int f = 0; f < ds->nfields; f++)
            for (int l = 0; l < ds->nl; l++) {
                const field_row *r = &rows[((size_t)m * ds->nfields + f) * ds->nl + l];
                double tz = r->focus.z_tan, sz = r->focus.z_sag;
                double v[6] = {tz, sz, tz - sz, 0.5 * (3 * sz - tz), r->distortion_pct, r->lateral_um};
                table_out_str(t, ds->names[m]);
                table_out_fmt(t, ds->field[f], 0, "%.10g");
                table_out_fmt(t, ds->lambda[l], 0, "%.7g");
                table_out_fmt(t, r->focus.chief[1], 1, "%.9g");
                /* the foci are differences of distances of tens of mm: round-off about
                 * 1e-14 mm, shown as 0 below 1e-12 mm (it had printed an on-axis
                 * astigmatism of -1.1e-14) */
                for (int k = 0; k < 6; k++)
                    table_out_fmt(t, v[k], k < 4 ? 1 : k == 4 ? 1e-3 : 1, "%.6g");
                table_out_row_end(t);
            }
}

/* Largest differences between the models: foci (mm), distortion (%), lateral colour (um). */
static void print_difference(table_out *t, const design_set *ds, const field_row *rows)
{
    size_t half = (size_t)ds->nfields * ds->nl;
    double dz = 0, dd = 0, dl = 0, dy = 0;
    int skipped = 0;
    for (size_t k = 0; k < half; k++) {
        const field_row *a = &rows[k], *b = &rows[half + k];
        /* a field one model cannot image has nan rows: left out as well */
        if (!isfinite(a->focus.z_tan + a->focus.z_sag + b->focus.z_tan + b->focus.z_sag)) {
            skipped++;
            continue;
        }
        dz = fmax(dz, fmax(fabs(b->focus.z_tan - a->focus.z_tan), fabs(b->focus.z_sag - a->focus.z_sag)));
        dd = fmax(dd, fabs(b->distortion_pct - a->distortion_pct));
        dl = fmax(dl, fabs(b->lateral_um - a->lateral_um));
        dy = fmax(dy, fabs(b->focus.chief[1] - a->focus.chief[1]));
    }
    char text[320];
    int n = snprintf(text, sizeof text,
                     "foci differ by at most %.4g mm, chief-ray heights by %.4g um, distortion by %.4g %%, "
                     "lateral colour by %.4g um",
                     dz, 1e3 * dy, dd, dl);
    if (skipped && n > 0 && (size_t)n < sizeof text)
        snprintf(text + n, sizeof text - (size_t)n, " (%d rows without a finite focus left out)", skipped);
    const char *k[5] = {"foci_mm", "chief_y_um", "distortion_pct", "lateral_colour_um", "rows_left_out"};
    double v[5] = {dz, 1e3 * dy, dd, dl, skipped};
    design_set_print_difference(t, ds, text, 5, k, v);
}

/* The models' largest focal-shift difference, um. */
static void print_shift_difference(table_out *t, const design_set *ds, const double *shift, int n)
{
    double d = 0;
    for (int i = 0; i < n; i++)
        d = fmax(d, 1e3 * fabs(shift[n + i] - shift[i]));
    char text[96];
    snprintf(text, sizeof text, "focal shifts differ by at most %.4g um", d);
    const char *k[1] = {"focal_shift_um"};
    design_set_print_difference(t, ds, text, 1, k, &d);
}

static int run_focal_shift(field_request *rq, table_out *out, lens_err *err)
{
    design_set *ds = &rq->set;
    int n = rq->focal_shift;
    double lo = ds->lambda[0], hi = ds->lambda[0];
    for (int l = 1; l < ds->nl; l++)
        lo = fmin(lo, ds->lambda[l]), hi = fmax(hi, ds->lambda[l]);
    double *lam = malloc(sizeof(double) * (size_t)n * 4);
    if (!lam) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    double *shift = lam + n, *parax = lam + 3 * n, ref = ds->lambda[ds->primary];
    for (int i = 0; i < n; i++)
        lam[i] = lo + (hi - lo) * i / (n - 1);
    int rc = -1;
    const imaging *im0 = &ds->im[0];
    double t0;
    if (paraxial_focus_thickness(im0->lens, ref, im0->object_distance, &t0, err) != 0)
        goto out;
    for (int i = 0; i < n; i++) {
        double t;
        if (paraxial_focus_thickness(im0->lens, lam[i], im0->object_distance, &t, err) != 0)
            goto out;
        parax[i] = t - t0;
    }
    for (int m = 0; m < ds->nmodels; m++)
        if (field_focal_shift(&ds->im[m], lam, n, ref, rq->delta, shift + m * n, &ds->seconds[m], err) != 0) {
            run_error_model(err, m, ds->names[m]);
            goto out;
        }
    const char *cols[] = {"model", "lambda_um", "focal_shift_um", "paraxial_focal_shift_um"};
    table_out_table(out, "focal_shift", NULL, cols, 4);
    for (int m = 0; m < ds->nmodels; m++)
        for (int i = 0; i < n; i++) {
            table_out_str(out, ds->names[m]);
            table_out_fmt(out, lam[i], 0, "%.7g");
            table_out_fmt(out, 1e3 * shift[m * n + i], 1e-3, "%.6g");
            table_out_fmt(out, 1e3 * parax[i], 1e-3, "%.6g");
            table_out_row_end(out);
        }
    if (!out->json)
        fprintf(out->f, "# focal shift: the axial focus of rays close to the axis, from that at %.7g um; "
                        "paraxial: the lens's paraxial focus\n", ref);
    design_set_print_footer(out, ds, "the close rays");
    if (ds->nmodels > 1)
        print_shift_difference(out, ds, shift, n);
    rc = 0;
    if (rq->png) {
        field_shift_figure fig = {ds->nmodels, ds->names, n, lam, shift, rq->title};
        rc = field_shift_write_png(&fig, rq->png, err);
    }
out:
    free(lam);
    return rc;
}

int field_run(field_request *rq, table_out *out, field_row **result, lens_err *err)
{
    design_set *ds = &rq->set;
    if (design_set_focus(ds, err) != 0)
        return -1;
    if (rq->focal_shift > 1)
        return run_focal_shift(rq, out, err);
    size_t n = (size_t)ds->nmodels * ds->nfields * ds->nl;
    field_row *rows = calloc(n ? n : 1, sizeof *rows);
    if (!rows) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    if (run_rows(rq, rows, err) != 0) {
        free(rows);
        return -1;
    }
    print_rows(out, ds, rows);
    design_set_print_footer(out, ds, "the close rays");
    if (ds->nmodels > 1)
        print_difference(out, ds, rows);
    int rc = 0;
    if (rq->png) {
        field_figure fig = {ds->nmodels, ds->nfields, ds->nl, ds->names, rows, ds->field, ds->lambda,
                            ds->primary, rq->title, isfinite(ds->im[0].object_distance)};
        rc = field_write_png(&fig, rq->png, err);
    }
    if (result && rc == 0)
        *result = rows;
    else
        free(rows);
    return rc;
}
