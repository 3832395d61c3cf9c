/* lens-spot: spot diagrams of a lens or a polynomial system (man lens-spot). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/cli.h"
#include "sparselens/imaging_cli.h"
#include "sparselens/lens_cli_options.h"
#include "sparselens/spot_run.h"

static const char *const prog = "lens-spot";

static const char *const usage =
    "usage: lens-spot LENS|SYSTEM.poly [options]\n"
    "Spot diagrams: centroid, RMS and maximum radius about the chief ray and about the\n"
    "centroid, vignetted fraction, per field and wavelength, and pooled per field.\n"
    "  --fields LIST          field angles in degrees (object at infinity) or object\n"
    "                         heights in mm (--object-distance); default 0, 0.7, 1 x max\n"
    "  --object-distance MM   finite object, MM in front of the first vertex\n"
    "  --wavelengths LIST     um values or Fraunhofer names (default F,d,C); the middle\n"
    "                         one is the primary\n"
    "  --focus file|paraxial|best   sensor plane (default file: as in the lens)\n"
    "  --pupil hexapolar|grid|random  stop sampling (default hexapolar)\n"
    "  --rays N               rays per field and wavelength (default 400)\n"
    "  --seed N               seed for --pupil random (default 1)\n"
    "  --compare SYSTEM.poly  also trace through a fitted system, shown beside the lens\n"
    "  --lens LENS            the lens of a SYSTEM.poly given as the first argument\n"
    "  --png FILE             spot diagram picture\n"
    "  --exr FILE             spot density as float images\n"
    LENS_CLI_OPTIONS_HELP
    "  --help\n";

/* lens-spot's own flags, beside the shared ones of imaging_cli.h. */
typedef struct {
    const char *pupil, *rays, *seed, *exr;
} spot_flags;

static int spot_flag(const char *p, int argc, char **argv, int *i, void *ctx)
{
    spot_flags *f = ctx;
    return cli_opt(p, argc, argv, i, "--pupil", &f->pupil) ||
           cli_opt(p, argc, argv, i, "--rays", &f->rays) ||
           cli_opt(p, argc, argv, i, "--seed", &f->seed) ||
           cli_opt(p, argc, argv, i, "--exr", &f->exr);
}

int main(int argc, char **argv)
{
    spot_flags sf = {"hexapolar", "400", "1", NULL};
    imaging_cli a = {.wavelengths = "F,d,C"};
    imaging_cli_parse(prog, usage, argc, argv, &a, spot_flag, &sf);
    const char *exr = sf.exr, *png = a.png, *fields_s = a.fields, *focus_s = a.focus;
    const double *lambda = a.lambda;
    int nl = a.nl;
    double dist = a.object_distance;

    spot_request rq = {.seed = 1, .focus = a.focus_mode};
    lens_err err;
    double field[IMAGING_MAX_FIELDS];
    if (pupil_pattern_parse(sf.pupil, &rq.pattern) != 0)
        diag_die(prog, "--pupil: '%s' is not hexapolar, grid or random", sf.pupil);
    rq.rays = (size_t)cli_count(prog, "--rays", sf.rays, 1, 10000000);
    rq.seed = (unsigned long long)cli_count(prog, "--seed", sf.seed, 0, 1L << 52);

    imaging_models models;
    rq.nmodels = imaging_cli_load(prog, &a, &models, rq.im, rq.model_names);
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
    const char *base = imaging_cli_basename(&a);
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
