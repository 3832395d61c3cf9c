/* lens-fan: ray fans of a lens or a polynomial system (man lens-fan). */
#include <stdio.h>

#include "sparselens/cli.h"
#include "sparselens/fan_run.h"

static const char *const prog = "lens-fan";

static const char *const usage =
    "usage: lens-fan LENS|SYSTEM.poly [options]\n"
    "Ray fans: transverse ray error (um) on the sensor against the normalised pupil\n"
    "coordinate, tangential (ey against py) and sagittal (ex against px), per field and\n"
    "wavelength, from the chief ray of the primary (middle) wavelength.\n"
    "  --fields LIST          field angles in degrees (object at infinity) or object\n"
    "                         heights in mm (--object-distance); default 0, 0.7, 1 x max\n"
    "  --object-distance MM   finite object, MM in front of the first vertex\n"
    "  --wavelengths LIST     um values or Fraunhofer names (default F,d,C)\n"
    "  --focus file|paraxial|best   sensor plane (default file: as in the lens)\n"
    "  --points N             rays per fan (default 21)\n"
    "  --compare SYSTEM.poly  also through a fitted system: its fans, difference and time\n"
    "  --lens LENS            the lens of a SYSTEM.poly given as the first argument\n"
    "  --png FILE             picture: a row of tangential and sagittal fans per field\n"
    LENS_CLI_OPTIONS_HELP
    "  --help\n";

static int fan_flag(const char *p, int argc, char **argv, int *i, void *ctx)
{
    return cli_opt(p, argc, argv, i, "--points", (const char **)ctx);
}

int main(int argc, char **argv)
{
    const char *points = "21";
    imaging_cli a = {.wavelengths = "F,d,C"};
    imaging_cli_parse(prog, usage, argc, argv, &a, fan_flag, &points);
    fan_request rq = {.npts = (int)cli_count(prog, "--points", points, 2, 100001)};
    imaging_models models;
    double field[IMAGING_MAX_FIELDS];
    design_set_from_cli(prog, &a, &models, field, &rq.set);
    char title[256];
    design_set_title(&a, &models, "ray fans", title, sizeof title);
    rq.png = a.png, rq.title = title;
    lens_err err;
    int rc = fan_run(&rq, stdout, NULL, &err);
    if (rc != 0)
        diag_print(prog, &err);
    imaging_models_free(&models);
    return rc != 0;
}
