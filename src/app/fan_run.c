/* lens-fan's job (fan_run.h). */
#include "sparselens/fan_run.h"

#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

void fan_results_free(ray_fan *fans, size_t n)
{
    if (fans)
        for (size_t i = 0; i < n; i++)
            ray_fan_free(&fans[i]);
    free(fans);
}

static void print_rows(table_out *t, const fan_request *rq, const ray_fan *fans)
{
    const design_set *ds = &rq->set;
    const char *cols[] = {"model", isfinite(ds->im[0].object_distance) ? "field_mm" : "field_deg",
                          "lambda_um", "fan", "pupil", "ex_um", "ey_um"};
    table_out_table(t, "fans", NULL, cols, 7);
    for (int m = 0; m < ds->nmodels; m++)
        for (int f = 0; f < ds->nfields; f++)
            for (int l = 0; l < ds->nl; l++) {
                const ray_fan *fn = &fans[((size_t)m * ds->nfields + f) * ds->nl + l];
                for (int side = 0; side < 2; side++)
                    for (int i = 0; i < fn->npts; i++) {
                        table_out_str(t, ds->names[m]);
                        table_out_fmt(t, ds->field[f], 0, "%.10g");
                        table_out_fmt(t, ds->lambda[l], 0, "%.7g");
                        table_out_str(t, side ? "sag" : "tan");
                        table_out_fmt(t, fn->pupil[i], 1, "%.6g");
                        table_out_fmt(t, 1e3 * fn->ex[side * fn->npts + i], 1e-3, "%.6g");
                        table_out_fmt(t, 1e3 * fn->ey[side * fn->npts + i], 1e-3, "%.6g");
                        table_out_row_end(t);
                    }
            }
}

/* The largest difference between the two models' fans, um, over points both image. */
static double fan_difference(const design_set *ds, const ray_fan *fans)
{
    size_t half = (size_t)ds->nfields * ds->nl;
    double d = 0;
    for (size_t k = 0; k < half; k++) {
        const ray_fan *a = &fans[k], *b = &fans[half + k];
        for (int i = 0; i < 2 * a->npts; i++) {
            double dx = b->ex[i] - a->ex[i], dy = b->ey[i] - a->ey[i];
            if (isfinite(dx) && isfinite(dy))
                d = fmax(d, hypot(dx, dy));
        }
    }
    return 1e3 * d;
}

int fan_run(fan_request *rq, table_out *out, ray_fan **result, lens_err *err)
{
    design_set *ds = &rq->set;
    size_t n = (size_t)ds->nmodels * ds->nfields * ds->nl;
    ray_fan *fans = calloc(n ? n : 1, sizeof *fans);
    if (!fans) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    if (design_set_focus(ds, err) != 0)
        goto fail;
    double chief_diff = 0;
    for (int f = 0; f < ds->nfields; f++) {
        double ref[2][4];
        int imaged = 0;
        for (int m = 0; m < ds->nmodels; m++) {
            int st = design_set_imaged(ds, m, f, 1, "its rows are nan", err);
            if (st < 0)
                goto fail;
            if (st > 0) {
                for (int l = 0; l < ds->nl; l++)
                    if (ray_fan_not_imaged(rq->npts, &fans[((size_t)m * ds->nfields + f) * ds->nl + l], err) != 0)
                        goto fail;
                continue;
            }
            imaged++;
            if (design_set_chief(ds, m, ds->field[f], ds->lambda[ds->primary], ref[m], err) != 0)
                goto fail;
            for (int l = 0; l < ds->nl; l++) {
                ray_fan *fn = &fans[((size_t)m * ds->nfields + f) * ds->nl + l];
                if (ray_fan_trace(&ds->im[m], ds->field[f], ds->lambda[l], ref[m], ref[m], rq->npts, fn,
                                  err) != 0) {
                    run_error_model(err, m, ds->names[m]);
                    goto fail;
                }
                ds->seconds[m] += fn->seconds;
            }
        }
        if (imaged > 1) /* not across a field one model cannot image */
            chief_diff = fmax(chief_diff, 1e3 * hypot(ref[1][0] - ref[0][0], ref[1][1] - ref[0][1]));
    }
    print_rows(out, rq, fans);
    design_set_print_footer(out, ds, "the fans");
    if (ds->nmodels > 1) {
        double v[2] = {fan_difference(ds, fans), chief_diff};
        const char *k[2] = {"fans_um", "chief_rays_um"};
        char text[160];
        snprintf(text, sizeof text, "fans differ by at most %.4g um, chief rays by %.4g um", v[0], v[1]);
        design_set_print_difference(out, ds, text, 2, k, v);
    }
    if (rq->png) {
        ray_fan_figure fig = {ds->nmodels, ds->nfields, ds->nl, ds->names, fans, ds->field, ds->lambda,
                              rq->title, isfinite(ds->im[0].object_distance)};
        if (ray_fan_write_png(&fig, rq->png, err) != 0)
            goto fail;
    }
    if (result)
        *result = fans;
    else
        fan_results_free(fans, n);
    return 0;
fail:
    fan_results_free(fans, n);
    return -1;
}
