/* The whole lens-distort job as a library call (see distort_run.h). */
#include "sparselens/distort_run.h"
#include "sparselens/escape.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void distort_report_free(distort_report *rep)
{
    free(rep->rows);
    free(rep->pts[0]);
    free(rep->pts[1]);
    memset(rep, 0, sizeof *rep);
}

static int sensor_plane(const distort_request *rq, double *shift, lens_err *err)
{
    *shift = 0;
    if (rq->focus == FOCUS_FILE)
        return 0;
    spot_request sq = {.im = {rq->im[0]}, .model_names = {rq->model_names[0]}, .nmodels = 1,
                       .field = rq->field, .nfields = rq->nfields, .lambda = &rq->lambda, .nl = 1,
                       .primary = 0, .focus = rq->focus, .pattern = PUPIL_HEXAPOLAR, .rays = 100,
                       .seed = 1};
    spot_report sr;
    if (spot_run(&sq, &sr, err) != 0)
        return -1;
    *shift = sr.sensor_shift;
    spot_report_free(&sr);
    return 0;
}

int distort_run(const distort_request *rq, distort_report *rep, lens_err *err)
{
    memset(rep, 0, sizeof *rep);
    int nm = rq->nmodels, nf = rq->nfields;
    rep->nmodels = nm, rep->nfields = nf, rep->finite = isfinite(rq->im[0].object_distance);
    imaging im[2] = {rq->im[0], rq->im[1]};
    if (sensor_plane(rq, &rep->sensor_shift, err) != 0)
        return -1;
    for (int m = 0; m < nm; m++)
        im[m].sensor_shift = rep->sensor_shift;
    rep->rows = calloc((size_t)(nm * nf), sizeof *rep->rows);
    if (!rep->rows) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    if (distort_scale(&im[0], rq->lambda, &rep->scale, err) != 0)
        goto fail;
    for (int m = 0; m < nm; m++)
        if (distort_curve(&im[m], rq->lambda, rq->field, nf, rq->illum_rays, rep->rows + m * nf, err) !=
            0) {
            run_error_model(err, m, rq->model_names[m]);
            goto fail;
        }
    for (int i = 0; i < nm * nf; i++)
        rep->not_imaged += rep->rows[i].why[0] != 0;
    rep->mapping = PROJ_RECTILINEAR;
    if (!rep->finite &&
        (rep->best_left_out = distort_best_mappings(rep->rows, nm, nf, rep->best, rep->best_rms)) < 0) {
        lens_errf(err, NULL, 0, "out of memory");
        goto fail;
    }
    if (rq->mapping >= 0)
        rep->mapping = (proj_kind)rq->mapping;
    else if (!rep->finite)
        rep->mapping = rep->best[0];
    if (rq->grid <= 0)
        return 0;

    rep->sensor_w = rq->sensor_w, rep->sensor_h = rq->sensor_h;
    const lens_t *l = rq->im[0].lens;
    if (!(rep->sensor_w > 0)) {
        if (isfinite(l->sensor_w) && isfinite(l->sensor_h)) {
            rep->sensor_w = l->sensor_w, rep->sensor_h = l->sensor_h;
        } else {
            double hmax = 0;
            for (int i = 0; i < nf; i++)
                hmax = fmax(hmax, fabs(rep->rows[i].h_real));
            rep->sensor_w = rep->sensor_h = 2 * hmax / sqrt(2.0);
        }
    }
    if (!(rep->sensor_w > 0)) {
        lens_errf(err, NULL, 0, "no sensor size for the grid map: give --sensor WxH or a non-zero field");
        goto fail;
    }
    int n = rep->grid = rq->grid;
    double hw = rep->sensor_w / 2, hh = rep->sensor_h / 2;
    for (int m = 0; m < nm; m++) {
        rep->pts[m] = malloc(sizeof(double) * 4 * (size_t)(n * n));
        if (!rep->pts[m]) {
            lens_errf(err, NULL, 0, "out of memory");
            goto fail;
        }
        if (distort_grid(&im[m], rq->lambda, rep->mapping, rep->scale, hw, hh, n, n, rep->pts[m]) == 0) {
            lens_errf(err, NULL, 0, "no point of the %s grid map reaches the sensor", rq->model_names[m]);
            goto fail;
        }
    }
    if (rq->cv_width > 0)
        for (int m = 0; m < nm; m++)
            for (int fe = 0; fe < 2; fe++) {
                lens_err e2;
                rep->fit_ok[m][fe] =
                    distort_opencv(&im[m], rq->lambda, fe, rep->mapping, rep->pts[m], n * n, rep->scale, hw, hh,
                                   rq->cv_width, rq->cv_height, fe ? 85 : 80, &rep->fit[m][fe], &e2) == 0;
                if (!rep->fit_ok[m][fe])
                    snprintf(rep->fit_msg[m][fe], sizeof rep->fit_msg[m][fe], "%s", e2.msg);
            }
    return 0;
fail:
    distort_report_free(rep);
    return -1;
}

int distort_report_warnings(const distort_request *rq, const distort_report *rep,
                            report_warning *w, int max)
{
    int n = 0;
    for (int i = 0; i < rep->nmodels * rep->nfields; i++)
        if (rep->rows[i].why[0] && n < max)
            snprintf(w[n++], sizeof w[0], "%s: %.480s; its row is nan", rq->model_names[i / rep->nfields],
                     rep->rows[i].why);
    return n;
}

/* The OpenCV fits as a JSON table (text keeps its comment lines). */
static void print_fits_json(table_out *t, const distort_request *rq, const distort_report *rep)
{
    static const char *const cols[] = {"model", "camera", "fx", "fy", "cx", "cy", "k1", "k2",
                                       "k3", "k4", "p1", "p2", "rms_px", "max_px", "error"};
    table_out_table(t, "opencv", NULL, cols, (int)(sizeof cols / sizeof cols[0]));
    for (int m = 0; m < rep->nmodels; m++)
        for (int fe = 0; fe < 2; fe++) {
            const cv_camera_fit *c = &rep->fit[m][fe];
            int ok = rep->fit_ok[m][fe];
            /* brown: k1 k2 p1 p2 k3; fisheye: k1 k2 k3 k4 */
            double k[6] = {c->k[0], c->k[1], fe ? c->k[2] : c->k[4], fe ? c->k[3] : NAN,
                           fe ? NAN : c->k[2], fe ? NAN : c->k[3]};
            double v[] = {c->fx, c->fy, c->cx, c->cy, k[0], k[1], k[2], k[3], k[4], k[5], c->rms,
                          c->max_err};
            table_out_str(t, rq->model_names[m]);
            table_out_str(t, fe ? "fisheye" : "brown");
            /* the digits of the text's comment lines */
            for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
                table_out_fmt(t, ok ? v[i] : NAN, 0, i < 10 ? "%.8g" : "%.4g");
            table_out_str(t, ok ? "" : rep->fit_msg[m][fe]);
            table_out_row_end(t);
        }
}

static void print_comments_json(table_out *t, const distort_request *rq, const distort_report *rep)
{
    table_out_keys(t, "ideal", NULL);
    table_out_str(t, rep->finite ? "magnification" : "focal_length_mm");
    table_out_fmt(t, rep->scale, 0, "%.9g");
    table_out_row_end(t);
    table_out_key_num(t, "lambda_um", rq->lambda);
    table_out_key_num(t, "sensor_shift_mm", rep->sensor_shift);
    if (!rep->finite) {
        static const char *const cols[] = {"model", "mapping", "rms_pct", "fields_left_out"};
        table_out_table(t, "best_mapping", NULL, cols, 4);
        for (int m = 0; m < rep->nmodels; m++) {
            table_out_str(t, rq->model_names[m]);
            table_out_str(t, proj_name(rep->best[m]));
            table_out_fmt(t, rep->best_rms[m], 0, "%.4g");
            table_out_int(t, rep->best_left_out);
            table_out_row_end(t);
        }
    }
    if (rq->cv_width > 0 && rep->grid > 0)
        print_fits_json(t, rq, rep);
}

static void print_comments_text(FILE *f, const distort_request *rq, const distort_report *rep)
{
    if (rep->sensor_shift != 0)
        fprintf(f, "# sensor plane moved %.9g mm along the axis (--focus %s)\n", rep->sensor_shift,
                rq->focus == FOCUS_BEST ? "best" : "paraxial");
    if (rep->finite) {
        fprintf(f, "# ideal height: paraxial magnification %.9g x object height, at %.7g um\n",
                rep->scale, rq->lambda);
    } else {
        fprintf(f, "# ideal heights with f = %.9g mm (paraxial focal length at %.7g um)\n", rep->scale,
                rq->lambda);
        for (int m = 0; m < rep->nmodels; m++)
            fprintf(f, "# best mapping (%s): %s, rms distortion %.4g %% over the fields%s\n",
                    rq->model_names[m], proj_name(rep->best[m]), rep->best_rms[m],
                    rep->best_left_out ? " every model images" : "");
    }
    if (rq->cv_width <= 0 || rep->grid <= 0)
        return;
    for (int m = 0; m < rep->nmodels; m++)
        for (int fe = 0; fe < 2; fe++) {
            const cv_camera_fit *c = &rep->fit[m][fe];
            const char *kind = fe ? "fisheye" : "brown";
            if (!rep->fit_ok[m][fe])
                fprintf(f, "# opencv-%s (%s): %s\n", kind, rq->model_names[m], rep->fit_msg[m][fe]);
            else if (fe)
                fprintf(f, "# opencv-fisheye (%s): fx %.8g fy %.8g cx %.8g cy %.8g k1 %.8g k2 %.8g "
                           "k3 %.8g k4 %.8g rms_px %.4g max_px %.4g\n",
                        rq->model_names[m], c->fx, c->fy, c->cx, c->cy, c->k[0], c->k[1], c->k[2],
                        c->k[3], c->rms, c->max_err);
            else
                fprintf(f, "# opencv-brown (%s): fx %.8g fy %.8g cx %.8g cy %.8g k1 %.8g k2 %.8g "
                           "p1 %.8g p2 %.8g k3 %.8g rms_px %.4g max_px %.4g\n",
                        rq->model_names[m], c->fx, c->fy, c->cx, c->cy, c->k[0], c->k[1], c->k[2],
                        c->k[3], c->k[4], c->rms, c->max_err);
        }
}

void distort_report_print(table_out *t, const distort_request *rq, const distort_report *rep)
{
    int nf = rep->nfields;
    int ri = rq->illum_rays > 0; /* the column only when it was computed */
    const char *cols[4 + 2 + PROJ_COUNT];
    int nc = 0;
    cols[nc++] = "model";
    cols[nc++] = rep->finite ? "field_mm" : "field_deg";
    cols[nc++] = "h_real_mm";
    cols[nc++] = "h_ideal_mm";
    cols[nc++] = "distortion_pct";
    if (ri)
        cols[nc++] = "rel_illum";
    char proj_cols[PROJ_COUNT][40];
    if (!rep->finite)
        for (int k = 1; k < PROJ_COUNT; k++) {
            snprintf(proj_cols[k], sizeof proj_cols[k], "%s_pct", proj_name((proj_kind)k));
            cols[nc++] = proj_cols[k];
        }
    table_out_table(t, "distortion", NULL, cols, nc);
    /* heights that cancel to round-off are zero on the scale of the largest one */
    double H = 1;
    for (int i = 0; i < rep->nmodels * nf; i++)
        if (isfinite(rep->rows[i].h_real))
            H = fmax(H, fabs(rep->rows[i].h_real));
    for (int m = 0; m < rep->nmodels; m++)
        for (int i = 0; i < nf; i++) {
            const distort_row *r = rep->rows + m * nf + i;
            table_out_str(t, rq->model_names[m]);
            table_out_fmt(t, r->field, 0, "%.10g");
            table_out_fmt(t, r->h_real, H, "%.9g");
            table_out_fmt(t, r->h_ideal, H, "%.9g");
            table_out_fmt(t, r->dist_pct, 100, "%.6f");
            if (ri)
                table_out_fmt(t, r->rel_illum, 1, "%.5f");
            if (!rep->finite)
                for (int k = 1; k < PROJ_COUNT; k++)
                    table_out_fmt(t, r->map_pct[k], 100, "%.6f");
            table_out_row_end(t);
        }
    if (t->json)
        print_comments_json(t, rq, rep);
    else
        print_comments_text(t->f, rq, rep);
}

void distort_report_write_map(FILE *f, const char *input, const distort_request *rq,
                              const distort_report *rep)
{
    fputs("# grid map of ", f);
    text_line(f, input);
    fprintf(f, ": ideal %s image points (f or magnification %.9g) and where the "
               "chief rays land; nan where none does\n",
            proj_name(rep->mapping), rep->scale);
    fprintf(f, "# columns: model x_ideal_mm y_ideal_mm x_real_mm y_real_mm dx_um dy_um\n");
    for (int m = 0; m < rep->nmodels; m++)
        for (int i = 0; i < rep->grid * rep->grid; i++) {
            const double *p = rep->pts[m] + 4 * i;
            fprintf(f, "%s %.12g %.12g %.12g %.12g %.6g %.6g\n", rq->model_names[m], p[0], p[1], p[2],
                    p[3], (p[2] - p[0]) * 1e3, (p[3] - p[1]) * 1e3);
        }
}

double distort_auto_factor(const distort_report *rep)
{
    double maxd = 0;
    for (int m = 0; m < rep->nmodels; m++)
        for (int i = 0; i < rep->grid * rep->grid; i++) {
            const double *p = rep->pts[m] + 4 * i;
            if (isfinite(p[2]))
                maxd = fmax(maxd, hypot(p[2] - p[0], p[3] - p[1]));
        }
    double x = maxd > 0 ? 0.1 * fmax(rep->sensor_w, rep->sensor_h) / 2 / maxd : 1;
    if (!(x > 1))
        return 1;
    double e = pow(10, floor(log10(x))), m = x / e;
    return (m < 2 ? 1 : m < 5 ? 2 : 5) * e;
}
