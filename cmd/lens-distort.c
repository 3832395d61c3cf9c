/* lens-distort: distortion curve, relative illumination, grid map and OpenCV camera
 * model check of a lens or a polynomial system (man lens-distort). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/distort_cli.h"
#include "sparselens/distort_run.h"
#include "sparselens/outfile.h"

static const char *const prog = "lens-distort";

int main(int argc, char **argv)
{
    distort_cli o;
    distort_cli_default(&o);
    const char *operand[1];
    int nop = opt_parse(&distort_command, argc, argv, &o, operand, 1);
    imaging_cli_finish(prog, &o.im, operand, nop);
    const char *input = o.im.input, *fields_s = o.im.fields, *map_path = o.map, *png = o.png;
    int opencv = o.opencv.w > 0;
    cli_check_output(prog, map_path);
    cli_check_output(prog, png);
    lens_err err;
    double field[IMAGING_MAX_FIELDS];
    distort_request rq = {.lambda = o.im.lambda[o.im.nl / 2], .mapping = o.mapping,
                          .sensor_w = o.sensor.w, .sensor_h = o.sensor.h,
                          .focus = o.im.focus_mode, .illum_rays = o.illum_rays,
                          .cv_width = (int)o.opencv.w, .cv_height = (int)o.opencv.h};
    if (opencv && isfinite(o.im.object_distance))
        diag_die(prog, "--opencv needs an object at infinity");
    rq.grid = png || map_path || opencv ? o.grid : 0;

    imaging_models models;
    rq.nmodels = imaging_cli_load(prog, &o.im, &models, rq.im, rq.model_names);
    if (fields_s) {
        rq.nfields = numbers_parse(fields_s, "field", field, IMAGING_MAX_FIELDS, &err);
        if (rq.nfields < 0)
            diag_die(prog, "--fields: %s", err.msg);
    } else {
        /* 11 fields from the axis to the largest lens-spot would choose */
        double three[3];
        if (imaging_default_fields(&rq.im[0], &rq.lambda, 1, three, &err) < 0)
            diag_die(prog, "%s", err.msg);
        rq.nfields = 11;
        for (int i = 0; i < rq.nfields; i++)
            field[i] = round(three[2] * i / (rq.nfields - 1) * 100) / 100;
    }
    rq.field = field;

    distort_report rep;
    if (distort_run(&rq, &rep, &err) != 0) {
        imaging_models_free(&models);
        diag_print(prog, &err);
        return 1;
    }
    imaging_setup setup;
    imaging_cli_setup(&o.im, &models, rq.lambda, rep.sensor_shift, &setup);
    table_out t;
    output_cli_begin(&o.out, &t, stdout, 6);
    distort_report_print(&t, &rq, &rep);
    imaging_setup_print(&t, &setup, &models);
    int rc = 0;
    if (map_path) {
        outfile *of = outfile_open(map_path, &err);
        if (of)
            distort_report_write_map(outfile_stream(of), input, &rq, &rep);
        if (!of || outfile_commit(of, &err) != 0) {
            diag_print(prog, &err);
            rc = 1;
        }
    }
    if (png && rc == 0) {
        double factor = isfinite(o.exaggerate) ? o.exaggerate : distort_auto_factor(&rep);
        const char *base = imaging_cli_basename(&o.im);
        char title[600];
        snprintf(title, sizeof title, "%s  distortion grid map (%s ideal, %.4g µm)  %s",
                 models.lens.name[0] ? models.lens.name : base, proj_name(rep.mapping), rq.lambda,
                 setup.text);
        if (distort_write_png(png, title, rq.nmodels, rq.model_names, (const double *const *)rep.pts,
                              rep.grid, rep.grid, rep.sensor_w / 2, rep.sensor_h / 2, factor, &err) != 0) {
            diag_print(prog, &err);
            rc = 1;
        } else if (!t.json) {
            printf("# grid map %s: %dx%d points over %gx%g mm, displacement exaggerated x%g\n", png,
                   rep.grid, rep.grid, rep.sensor_w, rep.sensor_h, factor);
        } else {
            table_out_keys(&t, "grid_map", NULL);
            table_out_str(&t, "file");
            table_out_str(&t, png);
            table_out_row_end(&t);
            table_out_str(&t, "points_per_side");
            table_out_int(&t, rep.grid);
            table_out_row_end(&t);
            table_out_str(&t, "exaggeration");
            table_out_num(&t, factor, 0);
            table_out_row_end(&t);
        }
    }
    /* a field a model cannot image: the table is whole (nan rows), the status says so */
    report_warning w[2 * IMAGING_MAX_FIELDS];
    const char *wp[2 * IMAGING_MAX_FIELDS];
    int nw = distort_report_warnings(&rq, &rep, w, 2 * IMAGING_MAX_FIELDS);
    for (int k = 0; k < nw; k++) {
        fprintf(stderr, "%s: warning: %s\n", prog, w[k]);
        wp[k] = w[k];
    }
    table_out_end(&t, wp, nw);
    if (rc == 0 && rep.not_imaged)
        rc = 2;
    distort_report_free(&rep);
    imaging_models_free(&models);
    return rc;
}
