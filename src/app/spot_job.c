/* lens-spot's job as a whole (spot_cli.h): the models loaded, the fields chosen,
 * spot_run, then the report and the pictures. */
#include "sparselens/outfile.h"
#include "sparselens/spot_cli.h"

#include <math.h>
#include <stdio.h>

#include "sparselens/spot_run.h"

int spot_cli_run(spot_cli *o, FILE *out, FILE *log, const char *prog, lens_err *err)
{
    const char *exr = o->exr, *png = o->png, *fields_s = o->im.fields, *focus_s = o->im.focus;
    const double *lambda = o->im.lambda;
    double dist = o->im.object_distance;

    spot_request rq = {.focus = o->im.focus_mode, .pattern = o->pattern, .rays = (size_t)o->rays,
                       .seed = o->seed};
    double field[IMAGING_MAX_FIELDS];
    imaging_models models;
    if ((rq.nmodels = imaging_cli_models(&o->im, &models, rq.im, rq.model_names, err)) < 0)
        return -1;
    int nl = o->im.nl; /* the file's wavelengths may have replaced the default */
    rq.lambda = lambda, rq.nl = nl, rq.primary = o->im.primary;
    int nf = fields_s ? numbers_parse(fields_s, "field", field, IMAGING_MAX_FIELDS, err)
                      : imaging_default_fields(&rq.im[0], lambda, nl, field, err);
    if (nf < 0 && fields_s) {
        lens_err e = *err;
        lens_errf(err, NULL, 0, "--fields: %s", e.msg);
    }
    rq.field = field, rq.nfields = nf;
    spot_report rep;
    if (nf < 0 || spot_run(&rq, &rep, err) != 0) {
        imaging_models_free(&models);
        return -1;
    }
    imaging_setup setup;
    imaging_cli_setup(&o->im, &models, lambda[rq.primary], rep.sensor_shift, &setup);
    table_out t;
    output_cli_begin(&o->out, &t, out, 6);
    spot_report_print(&t, &rq, &rep, focus_s);
    imaging_setup_print(&t, &setup, &models);

    char title[512];
    const char *base = imaging_cli_basename(&o->im);
    snprintf(title, sizeof title, "%s  spot diagram  %s", models.lens.name[0] ? models.lens.name : base,
             setup.text);
    spot_figure fig = {.nmodels = rq.nmodels, .nfields = nf, .nl = nl, .model_names = rq.model_names,
                       .spots = rep.spots, .title = title, .finite = isfinite(dist)};
    int rc = 0;
    if (png && spot_write_png(&fig, png, err) != 0) {
        fprintf(log, "%s: %s\n", prog, err->msg);
        rc = 1;
    }
    double um_px;
    int panel;
    if (rc == 0 && exr) {
        if (spot_write_exr(&fig, exr, &um_px, &panel, err) != 0) {
            fprintf(log, "%s: %s\n", prog, err->msg);
            outfile_remove(png); /* the run failed: none of its pictures stays */
            rc = 1;
        } else if (!t.json) {
            fprintf(out, "# exr %s: %d x %d pixel panels (a column per field, a row per model), "
                   "%.6g um per pixel, centred on each field's centroid\n",
                   exr, panel, panel, um_px);
        } else {
            table_out_keys(&t, "exr", NULL);
            table_out_key_str(&t, "file", exr);
            table_out_key_int(&t, "panel_px", panel);
            table_out_key_num(&t, "um_per_px", um_px);
        }
    }
    /* a field a model cannot image: the table is whole (nan rows), the status says so */
    report_warning w[2 * IMAGING_MAX_FIELDS];
    int nw = imaging_cli_model_warning(&models, w);
    nw += spot_report_warnings(&rq, &rep, w + nw, 2 * IMAGING_MAX_FIELDS - nw);
    imaging_cli_end_table(&t, log, prog, w, nw);
    if (rc == 0 && rep.not_imaged)
        rc = 2;
    spot_report_free(&rep);
    imaging_models_free(&models);
    return rc;
}
