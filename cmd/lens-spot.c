/* lens-spot: spot diagrams of a lens or a polynomial system (man lens-spot). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/cli.h"
#include "sparselens/spot_cli.h"
#include "sparselens/spot_run.h"

static const char *const prog = "lens-spot";

int main(int argc, char **argv)
{
    spot_cli o;
    spot_cli_default(&o);
    const char *operand[1];
    int nop = opt_parse(&spot_command, argc, argv, &o, operand, 1);
    imaging_cli_finish(prog, &o.im, operand, nop);
    const char *exr = o.exr, *png = o.png, *fields_s = o.im.fields, *focus_s = o.im.focus;
    const double *lambda = o.im.lambda;
    cli_check_output(prog, exr);
    cli_check_output(prog, png);
    int nl = o.im.nl;
    double dist = o.im.object_distance;

    spot_request rq = {.focus = o.im.focus_mode, .pattern = o.pattern, .rays = (size_t)o.rays,
                       .seed = o.seed};
    lens_err err;
    double field[IMAGING_MAX_FIELDS];
    imaging_models models;
    rq.nmodels = imaging_cli_load(prog, &o.im, &models, rq.im, rq.model_names);
    rq.lambda = lambda, rq.nl = nl, rq.primary = nl / 2;
    int nf = fields_s ? numbers_parse(fields_s, "field", field, IMAGING_MAX_FIELDS, &err)
                      : imaging_default_fields(&rq.im[0], lambda, nl, field, &err);
    if (nf < 0) {
        diag_die(prog, "%s%s", fields_s ? "--fields: " : "", err.msg);
    }
    rq.field = field, rq.nfields = nf;

    spot_report rep;
    if (spot_run(&rq, &rep, &err) != 0) {
        imaging_models_free(&models);
        diag_print(prog, &err);
        return 1;
    }
    imaging_setup setup;
    imaging_cli_setup(&o.im, &models, lambda[rq.primary], rep.sensor_shift, &setup);
    table_out t;
    output_cli_begin(&o.out, &t, stdout, 6);
    spot_report_print(&t, &rq, &rep, focus_s);
    imaging_setup_print(&t, &setup, &models);

    char title[512];
    const char *base = imaging_cli_basename(&o.im);
    snprintf(title, sizeof title, "%s  spot diagram  %s", models.lens.name[0] ? models.lens.name : base,
             setup.text);
    spot_figure fig = {.nmodels = rq.nmodels, .nfields = nf, .nl = nl, .model_names = rq.model_names,
                       .spots = rep.spots, .title = title, .finite = isfinite(dist)};
    int rc = 0;
    if (png && spot_write_png(&fig, png, &err) != 0) {
        diag_print(prog, &err);
        rc = 1;
    }
    double um_px;
    int panel;
    if (rc == 0 && exr) {
        if (spot_write_exr(&fig, exr, &um_px, &panel, &err) != 0) {
            diag_print(prog, &err);
            rc = 1;
        } else if (!t.json) {
            printf("# exr %s: %d x %d pixel panels (a column per field, a row per model), "
                   "%.6g um per pixel, centred on each field's centroid\n",
                   exr, panel, panel, um_px);
        } else {
            table_out_keys(&t, "exr", NULL);
            table_out_str(&t, "file");
            table_out_str(&t, exr);
            table_out_row_end(&t);
            table_out_str(&t, "panel_px");
            table_out_int(&t, panel);
            table_out_row_end(&t);
            table_out_str(&t, "um_per_px");
            table_out_num(&t, um_px, 0);
            table_out_row_end(&t);
        }
    }
    /* a field a model cannot image: the table is whole (nan rows), the status says so */
    report_warning w[2 * IMAGING_MAX_FIELDS];
    const char *wp[2 * IMAGING_MAX_FIELDS];
    int nw = spot_report_warnings(&rq, &rep, w, 2 * IMAGING_MAX_FIELDS);
    for (int k = 0; k < nw; k++) {
        fprintf(stderr, "%s: warning: %s\n", prog, w[k]);
        wp[k] = w[k];
    }
    table_out_end(&t, wp, nw);
    if (rc == 0 && rep.not_imaged)
        rc = 2;
    spot_report_free(&rep);
    imaging_models_free(&models);
    return rc;
}
