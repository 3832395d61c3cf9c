/* lens-spot: spot diagrams of a lens or a polynomial system (man lens-spot). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "lens_cli_options.h"
#include "spot_run.h"

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

int main(int argc, char **argv)
{
    const char *input = NULL, *fields_s = NULL, *dist_s = NULL, *wl_s = "F,d,C", *focus_s = "file",
               *pupil_s = "hexapolar", *rays_s = "400", *seed_s = "1", *compare = NULL,
               *lens_path = NULL, *png = NULL, *exr = NULL;
    lens_cli_options lopt;
    lens_cli_options_init(&lopt);
    for (int i = 1; i < argc; i++) {
        if (lens_cli_options_take(prog, argc, argv, &i, &lopt))
            continue;
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            cli_help(usage);
        if (cli_opt(prog, argc, argv, &i, "--fields", &fields_s) ||
            cli_opt(prog, argc, argv, &i, "--object-distance", &dist_s) ||
            cli_opt(prog, argc, argv, &i, "--wavelengths", &wl_s) ||
            cli_opt(prog, argc, argv, &i, "--focus", &focus_s) ||
            cli_opt(prog, argc, argv, &i, "--pupil", &pupil_s) ||
            cli_opt(prog, argc, argv, &i, "--rays", &rays_s) ||
            cli_opt(prog, argc, argv, &i, "--seed", &seed_s) ||
            cli_opt(prog, argc, argv, &i, "--compare", &compare) ||
            cli_opt(prog, argc, argv, &i, "--lens", &lens_path) ||
            cli_opt(prog, argc, argv, &i, "--png", &png) ||
            cli_opt(prog, argc, argv, &i, "--exr", &exr))
            continue;
        if (argv[i][0] == '-' && argv[i][1] != '\0')
            diag_die(prog, "unknown option '%s' (see --help)", argv[i]);
        if (input)
            diag_die(prog, "one lens or system expected, got '%s' and '%s'", input, argv[i]);
        input = argv[i];
    }
    if (!input)
        diag_die(prog, "no lens given (see --help)");

    spot_request rq = {.seed = 1};
    lens_err err;
    double lambda[IMAGING_MAX_WAVELENGTHS], field[IMAGING_MAX_FIELDS];
    int nl = wavelengths_parse(wl_s, lambda, IMAGING_MAX_WAVELENGTHS, &err);
    if (nl < 0)
        diag_die(prog, "--wavelengths: %s", err.msg);
    if (focus_mode_parse(focus_s, &rq.focus) != 0)
        diag_die(prog, "--focus: '%s' is not file, paraxial or best", focus_s);
    if (pupil_pattern_parse(pupil_s, &rq.pattern) != 0)
        diag_die(prog, "--pupil: '%s' is not hexapolar, grid or random", pupil_s);
    rq.rays = (size_t)cli_count(prog, "--rays", rays_s, 1, 10000000);
    rq.seed = (unsigned long long)cli_count(prog, "--seed", seed_s, 0, 1L << 52);
    double dist = dist_s ? cli_positive(prog, "--object-distance", dist_s) : INFINITY;

    imaging_models models;
    int load_rc = imaging_models_load(input, compare, lens_path, lens_cli_options_get(&lopt),
                                      &models, &err);
    lens_cli_options_free(&lopt);
    if (load_rc != 0) {
        diag_print(prog, &err);
        return 1;
    }
    rq.nmodels = imaging_models_setup(&models, dist, rq.im, rq.model_names);
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
    const char *base = strrchr(input, '/') ? strrchr(input, '/') + 1 : input;
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
