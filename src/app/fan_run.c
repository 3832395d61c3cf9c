/* lens-fan's job (fan_run.h). */
#include "sparselens/fan_run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void fan_results_free(ray_fan *fans, size_t n)
{
    if (fans)
        for (size_t i = 0; i < n; i++)
            ray_fan_free(&fans[i]);
    free(fans);
}

static void print_rows(FILE *out, const fan_request *rq, const ray_fan *fans)
{
    const design_set *ds = &rq->set;
    fprintf(out, "# columns: model field_%s lambda_um fan pupil ex_um ey_um\n", design_set_field_unit(ds));
    for (int m = 0; m < ds->nmodels; m++)
        for (int f = 0; f < ds->nfields; f++)
            for (int l = 0; l < ds->nl; l++) {
                const ray_fan *fn = &fans[((size_t)m * ds->nfields + f) * ds->nl + l];
                for (int side = 0; side < 2; side++)
                    for (int i = 0; i < fn->npts; i++)
                        fprintf(out, "%s %.10g %.7g %s %.6g %.6g %.6g\n", ds->names[m], ds->field[f],
                                ds->lambda[l], side ? "sag" : "tan", fn->pupil[i],
                                1e3 * fn->ex[side * fn->npts + i], 1e3 * fn->ey[side * fn->npts + i]);
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

int fan_run(fan_request *rq, FILE *out, ray_fan **result, lens_err *err)
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
        for (int m = 0; m < ds->nmodels; m++) {
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
        if (ds->nmodels > 1)
            chief_diff = fmax(chief_diff, 1e3 * hypot(ref[1][0] - ref[0][0], ref[1][1] - ref[0][1]));
    }
    print_rows(out, rq, fans);
    if (ds->sensor_shift != 0)
        fprintf(out, "# sensor plane moved %.9g mm along the axis\n", ds->sensor_shift);
    design_set_print_time(out, ds, "the fans");
    if (ds->nmodels > 1)
        fprintf(out, "# %s - %s: fans differ by at most %.4g um, chief rays by %.4g um\n", ds->names[1],
                ds->names[0], fan_difference(ds, fans), chief_diff);
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
