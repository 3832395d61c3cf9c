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
    spot_report_print(stdout, &rq, &rep);
    if (rep.sensor_shift != 0)
        printf("# sensor plane moved %.9g mm along the axis (--focus %s)\n", rep.sensor_shift, focus_s);

    char title[256];
    const char *base = imaging_cli_basename(&o.im);
    snprintf(title, sizeof title, "%s  spot diagram  %s", models.lens.name[0] ? models.lens.name : base,
             isfinite(dist) ? "object at finite distance" : "object at infinity");
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
        } else {
            printf("# exr %s: %d x %d pixel panels (a column per field, a row per model), "
                   "%.6g um per pixel, centred on each field's centroid\n",
                   exr, panel, panel, um_px);
        }
    }
    spot_report_free(&rep);
    imaging_models_free(&models);
    return rc;
}
