/* lens-distort's job as a whole (distort_cli.h): the models loaded, the fields chosen,
 * distort_run, then the report, the displacement map and the grid picture. */
#include "sparselens/distort_cli.h"

#include <math.h>
#include <stdio.h>

#include "sparselens/distort_run.h"
#include "sparselens/outfile.h"

/* --fields, or 11 fields from the axis to the largest lens-spot would choose. */
static int choose_fields(const distort_request *rq, const char *fields_s, double *field,
                         lens_err *err)
{
    if (fields_s) {
        int n = numbers_parse(fields_s, "field", field, IMAGING_MAX_FIELDS, err);
        if (n < 0) {
            lens_err e = *err;
            lens_errf(err, NULL, 0, "--fields: %s", e.msg);
        }
        return n;
    }
    double given[IMAGING_MAX_FIELDS];
    int n = imaging_default_fields(&rq->im[0], &rq->lambda, 1, given, err);
    if (n < 0)
        return -1;
    /* the file's largest field exactly: the field it states distortion for */
    for (int i = 0; i < 10; i++)
        field[i] = round(given[n - 1] * i / 10 * 100) / 100;
    field[10] = given[n - 1];
    return 11;
}

int distort_cli_run(distort_cli *o, FILE *out, FILE *log, const char *prog, lens_err *err)
{
    const char *input = o->im.input, *fields_s = o->im.fields, *map_path = o->map, *png = o->png;
    int opencv = o->opencv.w > 0;
    double field[IMAGING_MAX_FIELDS];
    distort_request rq = {.mapping = o->mapping,
                          .sensor_w = o->sensor.w, .sensor_h = o->sensor.h,
                          .focus = o->im.focus_mode, .illum_rays = o->illum_rays,
                          .cv_width = (int)o->opencv.w, .cv_height = (int)o->opencv.h};
    if (opencv && isfinite(o->im.object_distance)) {
        lens_errf(err, NULL, 0, "--opencv needs an object at infinity");
        return -1;
    }
    rq.grid = png || map_path || opencv ? o->grid : 0;

    imaging_models models;
    if ((rq.nmodels = imaging_cli_models(&o->im, &models, rq.im, rq.model_names, err)) < 0)
        return -1;
    rq.lambda = o->im.lambda[o->im.primary]; /* the file's primary may replace the default */
    rq.field = field;
    distort_report rep;
    if ((rq.nfields = choose_fields(&rq, fields_s, field, err)) < 0 ||
        distort_run(&rq, &rep, err) != 0) {
        imaging_models_free(&models);
        return -1;
    }
    imaging_setup setup;
    imaging_cli_setup(&o->im, &models, rq.lambda, rep.sensor_shift, &setup);
    table_out t;
    output_cli_begin(&o->out, &t, out, 6);
    distort_report_print(&t, &rq, &rep);
    imaging_setup_print(&t, &setup, &models);
    int rc = 0;
    if (map_path) {
        outfile *of = outfile_open(map_path, err);
        if (of)
            distort_report_write_map(outfile_stream(of), input, &rq, &rep);
        if (!of || outfile_commit(of, err) != 0) {
            fprintf(log, "%s: %s\n", prog, err->msg);
            rc = 1;
        }
    }
    if (png && rc == 0) {
        double factor = isfinite(o->exaggerate) ? o->exaggerate : distort_auto_factor(&rep);
        const char *base = imaging_cli_basename(&o->im);
        char title[600];
        snprintf(title, sizeof title, "%s  distortion grid map (%s ideal, %.4g µm)  %s",
                 models.lens.name[0] ? models.lens.name : base, proj_name(rep.mapping), rq.lambda,
                 setup.text);
        if (distort_write_png(png, title, rq.nmodels, rq.model_names, (const double *const *)rep.pts,
                              rep.grid, rep.grid, rep.sensor_w / 2, rep.sensor_h / 2, factor, err) != 0) {
            fprintf(log, "%s: %s\n", prog, err->msg);
            rc = 1;
        } else if (!t.json) {
            fprintf(out, "# grid map %s: %dx%d points over %gx%g mm, displacement exaggerated x%g\n", png,
                   rep.grid, rep.grid, rep.sensor_w, rep.sensor_h, factor);
        } else {
            table_out_keys(&t, "grid_map", NULL);
            table_out_key_str(&t, "file", png);
            table_out_key_int(&t, "points_per_side", rep.grid);
            table_out_key_num(&t, "exaggeration", factor);
        }
    }
    /* a field a model cannot image: the table is whole (nan rows), the status says so */
    report_warning w[2 * IMAGING_MAX_FIELDS];
    int nw = imaging_cli_model_warning(&models, w);
    nw += distort_report_warnings(&rq, &rep, w + nw, 2 * IMAGING_MAX_FIELDS - nw);
    imaging_cli_end_table(&t, log, prog, w, nw);
    if (rc == 0 && rep.not_imaged)
        rc = 2;
    distort_report_free(&rep);
    imaging_models_free(&models);
    return rc;
}
