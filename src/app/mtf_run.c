/* lens-mtf's job (mtf_run.h). */
#include "sparselens/mtf_run.h"

#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

typedef struct {
    mtf_row *rows;
    size_t n, cap;
} row_list;

static mtf_row *row_add(row_list *l)
{
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 256;
        mtf_row *r = realloc(l->rows, cap * sizeof *r);
        if (!r)
            return NULL;
        l->rows = r, l->cap = cap;
    }
    memset(&l->rows[l->n], 0, sizeof l->rows[0]);
    return &l->rows[l->n++];
}

/* The values at x (frequency, or focus shift at rq->focus_freq) of one field of one
 * model from its wavefronts and OTFs; the "all" row sums the wavelengths' OTFs. */
static int add_rows(row_list *list, const mtf_request *rq, int m, int f, double x, wavefront *const *wf,
                    double *const *otf, const int *msz, double dz)
{
    const design_set *ds = &rq->set;
    double nu = rq->focus_freq > 0 ? rq->focus_freq : x;
    double sum[2][2] = {{0}};
    int nrow = ds->nl > 1 ? ds->nl + 1 : 1;
    for (int w = 0; w < nrow; w++) {
        mtf_row *r = row_add(list);
        if (!r)
            return -1;
        r->model = m, r->field = f, r->lambda = w, r->x = x;
        for (int d = 0; d < 2; d++) {
            int dir = d == 0 ? 1 : 0; /* tangential: frequencies along y */
            if (w < ds->nl) {
                double z[2];
                mtf_otf_at(wf[w], otf[w], msz[w], dir, nu, z);
                sum[d][0] += z[0] / ds->nl, sum[d][1] += z[1] / ds->nl;
                r->diff[d] = hypot(z[0], z[1]);
                r->geo[d] = mtf_geometric((const wavefront *const *)&wf[w], 1, dir, nu, dz);
            } else {
                r->diff[d] = hypot(sum[d][0], sum[d][1]);
                r->geo[d] = mtf_geometric((const wavefront *const *)wf, ds->nl, dir, nu, dz);
            }
        }
    }
    return 0;
}

typedef struct {
    int model, field, lambda;
    double rms_waves, strehl, na[2];
    int passed;
} wf_summary;

/* OTFs of the wavefronts as they stand (after a refocus). */
static int make_otfs(wavefront *wf, int nl, double **otf, int *msz)
{
    for (int l = 0; l < nl; l++) {
        free(otf[l]);
        if (!(otf[l] = mtf_otf(&wf[l], &msz[l])))
            return -1;
    }
    return 0;
}

/* The k-th x of a field's rows: a focus shift (mm) through focus, else a frequency from
 * 0 to Nyquist (cycles/mm). */
static double row_x(const mtf_request *rq, int k)
{
    if (rq->focus_freq > 0)
        return rq->focus_range * (2.0 * k / (rq->focus_steps - 1) - 1);
    return 1000 / (2 * rq->pixel_um) * k / rq->steps;
}

/* The rows and summaries of a field model m cannot image: at the same x as the others,
 * every figure nan. */
static int not_imaged(row_list *list, const mtf_request *rq, int m, int f, wf_summary *sum)
{
    const design_set *ds = &rq->set;
    int nx = rq->focus_freq > 0 ? rq->focus_steps : rq->steps + 1;
    int nrow = ds->nl > 1 ? ds->nl + 1 : 1;
    for (int k = 0; k < nx; k++) {
        double x = row_x(rq, k);
        for (int w = 0; w < nrow; w++) {
            mtf_row *r = row_add(list);
            if (!r)
                return -1;
            *r = (mtf_row){.model = m, .field = f, .lambda = w, .x = x, .diff = {NAN, NAN}, .geo = {NAN, NAN}};
        }
    }
    for (int l = 0; l < ds->nl; l++)
        sum[((size_t)m * ds->nfields + f) * ds->nl + l] =
            (wf_summary){m, f, l, NAN, NAN, {NAN, NAN}, 0};
    return 0;
}

/* Every field of model m: wavefronts, OTFs, rows. */
static int run_model(mtf_request *rq, int m, row_list *list, wf_summary *sum, lens_err *err)
{
    design_set *ds = &rq->set;
    wavefront_method method = ds->im[m].sys ? WAVEFRONT_RAYS : rq->lens_method;
    wavefront wf[IMAGING_MAX_WAVELENGTHS];
    wavefront *wp[IMAGING_MAX_WAVELENGTHS];
    double *otf[IMAGING_MAX_WAVELENGTHS] = {0};
    int msz[IMAGING_MAX_WAVELENGTHS], nwf = 0, rc = -1;
    for (int f = 0; f < ds->nfields; f++) {
        double ref[4];
        int st = design_set_imaged(ds, m, f, 1, "its rows are nan", err);
        if (st < 0)
            goto out;
        if (st > 0) {
            if (not_imaged(list, rq, m, f, sum) != 0)
                goto oom;
            continue;
        }
        if (design_set_chief(ds, m, ds->field[f], ds->lambda[ds->primary], ref, err) != 0)
            goto out;
        for (nwf = 0; nwf < ds->nl; nwf++) {
            wp[nwf] = &wf[nwf];
            if (wavefront_trace(&ds->im[m], ds->field[f], ds->lambda[nwf], rq->grid, method, ref, &wf[nwf],
                                err) != 0) {
                run_error_model(err, m, ds->names[m]);
                goto out;
            }
            ds->seconds[m] += wf[nwf].seconds;
            wf_summary *s = &sum[((size_t)m * ds->nfields + f) * ds->nl + nwf];
            s->model = m, s->field = f, s->lambda = nwf, s->passed = wf[nwf].passed;
            s->rms_waves = wavefront_rms(&wf[nwf]) / (ds->lambda[nwf] * 1e-3);
            s->strehl = mtf_strehl(&wf[nwf]);
            /* the numerical aperture n' sin U' of the exit beam */
            s->na[0] = wf[nwf].n_image * wf[nwf].scale[1], s->na[1] = wf[nwf].n_image * wf[nwf].scale[0];
        }
        if (rq->focus_freq > 0) {
            for (int k = 0; k < rq->focus_steps; k++) {
                double dz = row_x(rq, k);
                for (int l = 0; l < ds->nl; l++)
                    if (wavefront_refocus(&wf[l], dz) != 0) {
                        lens_errf(err, NULL, 0, "field %g: the wavefront fit failed at focus %g mm",
                                  ds->field[f], dz);
                        goto out;
                    }
                if (make_otfs(wf, ds->nl, otf, msz) != 0 || add_rows(list, rq, m, f, dz, wp, otf, msz, dz) != 0)
                    goto oom;
            }
        } else {
            if (make_otfs(wf, ds->nl, otf, msz) != 0)
                goto oom;
            for (int k = 0; k <= rq->steps; k++)
                if (add_rows(list, rq, m, f, row_x(rq, k), wp, otf, msz, 0) != 0)
                    goto oom;
        }
        for (int l = 0; l < nwf; l++)
            wavefront_free(&wf[l]);
        nwf = 0;
    }
    rc = 0;
    goto out;
oom:
    lens_errf(err, NULL, 0, "out of memory");
out:
    for (int l = 0; l < nwf; l++)
        wavefront_free(&wf[l]);
    for (int l = 0; l < IMAGING_MAX_WAVELENGTHS; l++)
        free(otf[l]);
    return rc;
}

static void lambda_name(const design_set *ds, int l, char *s, size_t n)
{
    if (l == ds->nl)
        snprintf(s, n, "all");
    else
        snprintf(s, n, "%.7g", ds->lambda[l]);
}

static void print_rows(table_out *t, const mtf_request *rq, const mtf_row *rows, size_t nrows)
{
    const design_set *ds = &rq->set;
    const char *cols[] = {"model", isfinite(ds->im[0].object_distance) ? "field_mm" : "field_deg",
                          "lambda_um", rq->focus_freq > 0 ? "focus_mm" : "freq_cyc_mm",
                          "diff_tan", "diff_sag", "geo_tan", "geo_sag"};
    char note[64];
    snprintf(note, sizeof note, "through focus at %g cycles/mm", rq->focus_freq);
    table_out_table(t, rq->focus_freq > 0 ? "through_focus" : "mtf", rq->focus_freq > 0 ? note : NULL, cols, 8);
    for (size_t i = 0; i < nrows; i++) {
        const mtf_row *r = &rows[i];
        char lam[32];
        lambda_name(ds, r->lambda, lam, sizeof lam);
        table_out_str(t, ds->names[r->model]);
        table_out_fmt(t, ds->field[r->field], 0, "%.10g");
        table_out_str(t, lam);
        table_out_fmt(t, r->x, 1e-3, "%.6g");
        for (int k = 0; k < 4; k++)
            table_out_fmt(t, k < 2 ? r->diff[k] : r->geo[k - 2], 1e-3, "%.5f");
        table_out_row_end(t);
    }
}

/* Per wavefront: cells passed, RMS in waves, Strehl, pupil scales; comment lines in text
 * (so the rows above stay one table for awk), a table "wavefronts" in JSON. */
static void print_summaries(table_out *t, const mtf_request *rq, const wf_summary *s, size_t n)
{
    const design_set *ds = &rq->set;
    const char *cols[] = {"model", "field", "lambda_um", "cells", "rms_waves", "strehl", "na_tan", "na_sag",
                          "fnumber_working"};
    if (t->json)
        table_out_table(t, "wavefronts", NULL, cols, 9);
    else
        fprintf(t->f, "# wavefront: model field lambda_um cells rms_waves strehl na_tan na_sag fnumber_working\n");
    for (size_t i = 0; i < n; i++) {
        /* the working F-number of the exit beam, 1 / (2 NA), NA the mean of the two axes' */
        double fw = 1 / (2 * sqrt(fabs(s[i].na[0] * s[i].na[1])));
        if (!t->json) {
            fprintf(t->f, "# wavefront: %s %.10g %.7g %d %.5f %.5f %.6f %.6f %.4f\n", ds->names[s[i].model],
                    ds->field[s[i].field], ds->lambda[s[i].lambda], s[i].passed, s[i].rms_waves, s[i].strehl,
                    fabs(s[i].na[0]), fabs(s[i].na[1]), fw);
            continue;
        }
        table_out_str(t, ds->names[s[i].model]);
        table_out_num(t, ds->field[s[i].field], 0);
        table_out_num(t, ds->lambda[s[i].lambda], 0);
        table_out_int(t, s[i].passed);
        table_out_num(t, s[i].rms_waves, 0);
        table_out_num(t, s[i].strehl, 0);
        table_out_num(t, fabs(s[i].na[0]), 0);
        table_out_num(t, fabs(s[i].na[1]), 0);
        table_out_num(t, fw, 0);
        table_out_row_end(t);
    }
}

static void print_difference(table_out *t, const design_set *ds, const mtf_row *rows, size_t nrows)
{
    size_t half = nrows / 2;
    double v[2] = {0, 0};
    for (size_t i = 0; i < half; i++)
        for (int d = 0; d < 2; d++) {
            double dd = fabs(rows[half + i].diff[d] - rows[i].diff[d]), dg = fabs(rows[half + i].geo[d] - rows[i].geo[d]);
            if (isfinite(dd) && isfinite(dg)) /* not a field one model cannot image */
                v[0] = fmax(v[0], dd), v[1] = fmax(v[1], dg);
        }
    char text[128];
    snprintf(text, sizeof text, "diffraction MTF differs by at most %.4f, geometric by %.4f", v[0], v[1]);
    const char *k[2] = {"diffraction_mtf", "geometric_mtf"};
    design_set_print_difference(t, ds, text, 2, k, v);
}

int mtf_run(mtf_request *rq, table_out *out, mtf_row **rows_out, size_t *nrows_out, lens_err *err)
{
    design_set *ds = &rq->set;
    if (design_set_focus(ds, err) != 0)
        return -1;
    size_t nsum = (size_t)ds->nmodels * ds->nfields * ds->nl;
    wf_summary *sum = calloc(nsum ? nsum : 1, sizeof *sum);
    row_list list = {0};
    if (!sum) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    int rc = -1;
    for (int m = 0; m < ds->nmodels; m++)
        if (run_model(rq, m, &list, sum, err) != 0)
            goto out;
    print_rows(out, rq, list.rows, list.n);
    print_summaries(out, rq, sum, nsum);
    /* each model's wavefront method: a system's is always by ray errors (run_model) */
    int has_lens = 0, has_sys = 0;
    for (int m = 0; m < ds->nmodels; m++) {
        has_lens |= !ds->im[m].sys;
        has_sys |= ds->im[m].sys != NULL;
    }
    if (!out->json) {
        fprintf(out->f, "# pixel %g um: Nyquist %g cycles/mm; pupil grid %d x %d", rq->pixel_um,
                1000 / (2 * rq->pixel_um), rq->grid, rq->grid);
        if (has_lens)
            fprintf(out->f, "; lens wavefront by %s",
                    rq->lens_method == WAVEFRONT_PATH ? "path lengths" : "ray errors");
        if (has_sys)
            fprintf(out->f, "; system wavefront by ray errors");
        fputc('\n', out->f);
    } else {
        table_out_keys(out, "sampling", NULL);
        table_out_key_num(out, "pixel_um", rq->pixel_um);
        table_out_key_num(out, "nyquist_cyc_mm", 1000 / (2 * rq->pixel_um));
        table_out_key_int(out, "pupil_grid", rq->grid);
        if (has_lens)
            table_out_key_str(out, "lens_wavefront",
                              rq->lens_method == WAVEFRONT_PATH ? "path" : "rays");
        if (has_sys)
            table_out_key_str(out, "system_wavefront", "rays");
    }
    design_set_print_footer(out, ds, "the wavefronts");
    if (ds->nmodels > 1)
        print_difference(out, ds, list.rows, list.n);
    rc = 0;
    if (rq->png) {
        /* the diffraction limit of the first field (the axis, usually) at the primary wavelength */
        const wf_summary *s0 = &sum[ds->primary];
        double nu_c = 2 * sqrt(fabs(s0->na[0] * s0->na[1])) / (ds->lambda[ds->primary] * 1e-3);
        mtf_figure fig = {ds->nmodels, ds->names, ds->nfields, ds->nl, ds->field, ds->lambda, list.rows, list.n,
                          rq->focus_freq, nu_c, rq->title, isfinite(ds->im[0].object_distance)};
        rc = mtf_write_png(&fig, rq->png, err);
    }
out:
    free(sum);
    if (rc == 0 && rows_out) {
        *rows_out = list.rows;
        *nrows_out = list.n;
    } else {
        free(list.rows);
    }
    return rc;
}
