/* lens-distort: distortion curve, relative illumination, grid map and OpenCV camera
 * model check of a lens or a polynomial system (man lens-distort). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "lens_cli_options.h"
#include "distort_run.h"
#include "outfile.h"

static const char *const prog = "lens-distort";

static const char *const usage =
    "usage: lens-distort LENS|SYSTEM.poly [options]\n"
    "Distortion of real chief rays (aimed through the stop centre) against f tan(theta)\n"
    "and the fisheye projections, relative illumination, grid map, OpenCV model fits.\n"
    "  --fields LIST          field angles in degrees, or object heights in mm with\n"
    "                         --object-distance; default 11 fields up to the largest\n"
    "  --object-distance MM   finite object, MM in front of the first vertex\n"
    "  --wavelengths LIST     um values or Fraunhofer names; the middle one is used\n"
    "                         (default d)\n"
    "  --focus file|paraxial|best   sensor plane (default file)\n"
    "  --illum-rays N         rays across a bundle for relative illumination (default 32;\n"
    "                         0 skips it)\n"
    "  --grid N               grid map points per side (default 17)\n"
    "  --mapping NAME         ideal projection of the grid map: rectilinear, equidistant,\n"
    "                         equisolid, stereographic, orthographic (default: the one\n"
    "                         the lens follows best)\n"
    "  --sensor WxH           sensor size in mm for the grid map (default: the lens\n"
    "                         header's, else a square inscribed in the largest field)\n"
    "  --exaggerate K         displacement factor in the picture (default: automatic)\n"
    "  --map FILE             write the grid displacement field as text ('-': stdout)\n"
    "  --png FILE             grid map picture\n"
    "  --opencv WxH           fit OpenCV's Brown-Conrady and fisheye models for a sensor\n"
    "                         of WxH pixels; prints coefficients and residuals\n"
    "  --compare SYSTEM.poly  also through a fitted system, beside the lens\n"
    "  --lens LENS            the lens of a SYSTEM.poly given as the first argument\n"
    LENS_CLI_OPTIONS_HELP
    "  --help\n";

int main(int argc, char **argv)
{
    const char *input = NULL, *fields_s = NULL, *dist_s = NULL, *wl_s = "d", *focus_s = "file",
               *illum_s = "32", *grid_s = "17", *mapping_s = NULL, *sensor_s = NULL, *exag_s = NULL,
               *map_path = NULL, *png = NULL, *opencv_s = NULL, *compare = NULL, *lens_path = NULL;
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
            cli_opt(prog, argc, argv, &i, "--illum-rays", &illum_s) ||
            cli_opt(prog, argc, argv, &i, "--grid", &grid_s) ||
            cli_opt(prog, argc, argv, &i, "--mapping", &mapping_s) ||
            cli_opt(prog, argc, argv, &i, "--sensor", &sensor_s) ||
            cli_opt(prog, argc, argv, &i, "--exaggerate", &exag_s) ||
            cli_opt(prog, argc, argv, &i, "--map", &map_path) ||
            cli_opt(prog, argc, argv, &i, "--png", &png) ||
            cli_opt(prog, argc, argv, &i, "--opencv", &opencv_s) ||
            cli_opt(prog, argc, argv, &i, "--compare", &compare) ||
            cli_opt(prog, argc, argv, &i, "--lens", &lens_path))
            continue;
        if (argv[i][0] == '-' && argv[i][1] != '\0')
            diag_die(prog, "unknown option '%s' (see --help)", argv[i]);
        if (input)
            diag_die(prog, "one lens or system expected, got '%s' and '%s'", input, argv[i]);
        input = argv[i];
    }
    if (!input)
        diag_die(prog, "no lens given (see --help)");
    lens_err err;
    double wl[IMAGING_MAX_WAVELENGTHS], field[IMAGING_MAX_FIELDS];
    int nl = wavelengths_parse(wl_s, wl, IMAGING_MAX_WAVELENGTHS, &err);
    if (nl < 0)
        diag_die(prog, "--wavelengths: %s", err.msg);
    distort_request rq = {.lambda = wl[nl / 2], .mapping = -1, .sensor_w = NAN, .sensor_h = NAN};
    if (focus_mode_parse(focus_s, &rq.focus) != 0)
        diag_die(prog, "--focus: '%s' is not file, paraxial or best", focus_s);
    rq.illum_rays = (int)cli_count(prog, "--illum-rays", illum_s, 0, 2000);
    int ng = (int)cli_count(prog, "--grid", grid_s, 2, 501);
    proj_kind mapping;
    if (mapping_s) {
        if (proj_parse(mapping_s, &mapping) != 0)
            diag_die(prog, "--mapping: '%s' is not rectilinear, equidistant, equisolid, "
                           "stereographic or orthographic", mapping_s);
        rq.mapping = (int)mapping;
    }
    if (sensor_s) {
        cli_pair(prog, "--sensor", sensor_s, 'x', &rq.sensor_w, &rq.sensor_h);
        if (!(rq.sensor_w > 0 && rq.sensor_h > 0))
            diag_die(prog, "--sensor: width and height must be positive");
    }
    double exag = exag_s ? cli_positive(prog, "--exaggerate", exag_s) : NAN;
    if (opencv_s) {
        double w, h;
        cli_pair(prog, "--opencv", opencv_s, 'x', &w, &h);
        if (!(w >= 16 && h >= 16 && w <= 100000 && h <= 100000) || w != floor(w) || h != floor(h))
            diag_die(prog, "--opencv: give the sensor size in whole pixels, e.g. 1920x1080");
        rq.cv_width = (int)w, rq.cv_height = (int)h;
    }
    double dist = dist_s ? cli_positive(prog, "--object-distance", dist_s) : INFINITY;
    if (opencv_s && isfinite(dist))
        diag_die(prog, "--opencv needs an object at infinity");
    rq.grid = png || map_path || opencv_s ? ng : 0;

    imaging_models models;
    int load_rc = imaging_models_load(input, compare, lens_path, lens_cli_options_get(&lopt),
                                      &models, &err);
    lens_cli_options_free(&lopt);
    if (load_rc != 0) {
        diag_print(prog, &err);
        return 1;
    }
    rq.nmodels = imaging_models_setup(&models, dist, rq.im, rq.model_names);
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
    distort_report_print(stdout, &rq, &rep);
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
        double factor = isfinite(exag) ? exag : distort_auto_factor(&rep);
        const char *base = strrchr(input, '/') ? strrchr(input, '/') + 1 : input;
        char title[300];
        snprintf(title, sizeof title, "%s  distortion grid map (%s ideal, %.4g um)",
                 models.lens.name[0] ? models.lens.name : base, proj_name(rep.mapping), rq.lambda);
        if (distort_write_png(png, title, rq.nmodels, rq.model_names, (const double *const *)rep.pts,
                              rep.grid, rep.grid, rep.sensor_w / 2, rep.sensor_h / 2, factor, &err) != 0) {
            diag_print(prog, &err);
            rc = 1;
        } else {
            printf("# grid map %s: %dx%d points over %gx%g mm, displacement exaggerated x%g\n", png,
                   rep.grid, rep.grid, rep.sensor_w, rep.sensor_h, factor);
        }
    }
    distort_report_free(&rep);
    imaging_models_free(&models);
    return rc;
}
