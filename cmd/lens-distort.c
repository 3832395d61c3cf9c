/* lens-distort: distortion curve, relative illumination, grid map and OpenCV camera
 * model check of a lens or a polynomial system (man lens-distort). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/cli.h"
#include "sparselens/imaging_cli.h"
#include "sparselens/lens_cli_options.h"
#include "sparselens/distort_run.h"
#include "sparselens/outfile.h"

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

/* lens-distort's own flags, beside the shared ones of imaging_cli.h. */
typedef struct {
    const char *illum, *grid, *mapping, *sensor, *exag, *map, *opencv;
} distort_flags;

static int distort_flag(const char *p, int argc, char **argv, int *i, void *ctx)
{
    distort_flags *f = ctx;
    return cli_opt(p, argc, argv, i, "--illum-rays", &f->illum) ||
           cli_opt(p, argc, argv, i, "--grid", &f->grid) ||
           cli_opt(p, argc, argv, i, "--mapping", &f->mapping) ||
           cli_opt(p, argc, argv, i, "--sensor", &f->sensor) ||
           cli_opt(p, argc, argv, i, "--exaggerate", &f->exag) ||
           cli_opt(p, argc, argv, i, "--map", &f->map) ||
           cli_opt(p, argc, argv, i, "--opencv", &f->opencv);
}

int main(int argc, char **argv)
{
    distort_flags df = {.illum = "32", .grid = "17"};
    imaging_cli a = {.wavelengths = "d"};
    imaging_cli_parse(prog, usage, argc, argv, &a, distort_flag, &df);
    const char *input = a.input, *fields_s = a.fields, *mapping_s = df.mapping,
               *sensor_s = df.sensor, *exag_s = df.exag, *map_path = df.map, *png = a.png,
               *opencv_s = df.opencv;
    lens_err err;
    double field[IMAGING_MAX_FIELDS];
    distort_request rq = {.lambda = a.lambda[a.nl / 2], .mapping = -1, .sensor_w = NAN,
                          .sensor_h = NAN, .focus = a.focus_mode};
    rq.illum_rays = (int)cli_count(prog, "--illum-rays", df.illum, 0, 2000);
    int ng = (int)cli_count(prog, "--grid", df.grid, 2, 501);
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
    if (opencv_s && isfinite(a.object_distance))
        diag_die(prog, "--opencv needs an object at infinity");
    rq.grid = png || map_path || opencv_s ? ng : 0;

    imaging_models models;
    rq.nmodels = imaging_cli_load(prog, &a, &models, rq.im, rq.model_names);
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
        const char *base = imaging_cli_basename(&a);
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
