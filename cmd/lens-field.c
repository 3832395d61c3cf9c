/* lens-field: field curves, distortion, lateral colour and focal shift (man lens-field). */
#include <stdio.h>
#include <stdlib.h>

#include "sparselens/cli.h"
#include "sparselens/field_run.h"

static const char *const prog = "lens-field";

static const char *const usage =
    "usage: lens-field LENS|SYSTEM.poly [options]\n"
    "Field curves from real rays: tangential and sagittal focus against field (mm from\n"
    "the sensor plane), astigmatism, Petzval focus, distortion and lateral colour; or\n"
    "the chromatic focal shift against wavelength.\n"
    "  --fields LIST          field angles in degrees (object at infinity) or object\n"
    "                         heights in mm; default 17 fields from 0 to the largest\n"
    "  --object-distance MM   finite object, MM in front of the first vertex\n"
    "  --wavelengths LIST     um values or Fraunhofer names (default F,d,C); the middle\n"
    "                         one is the primary\n"
    "  --focus file|paraxial|best   sensor plane (default file: as in the lens)\n"
    "  --delta D              close rays at D x the stop radius from the chief ray\n"
    "                         (default 0.01)\n"
    "  --focal-shift N        instead: the focal shift at N wavelengths spanning\n"
    "                         --wavelengths\n"
    "  --compare SYSTEM.poly  also through a fitted system: its curves, difference, time\n"
    "  --lens LENS            the lens of a SYSTEM.poly given as the first argument\n"
    "  --png FILE             picture\n"
    LENS_CLI_OPTIONS_HELP
    "  --help\n";

typedef struct {
    const char *delta, *shift;
} field_flags;

static int field_flag(const char *p, int argc, char **argv, int *i, void *ctx)
{
    field_flags *f = ctx;
    return cli_opt(p, argc, argv, i, "--delta", &f->delta) ||
           cli_opt(p, argc, argv, i, "--focal-shift", &f->shift);
}

int main(int argc, char **argv)
{
    field_flags ff = {"0.01", NULL};
    imaging_cli a = {.wavelengths = "F,d,C"};
    imaging_cli_parse(prog, usage, argc, argv, &a, field_flag, &ff);
    field_request rq = {.delta = cli_positive(prog, "--delta", ff.delta)};
    if (rq.delta > 0.5)
        diag_die(prog, "--delta: %s is more than half the stop radius", ff.delta);
    if (ff.shift)
        rq.focal_shift = (int)cli_count(prog, "--focal-shift", ff.shift, 2, 10000);
    imaging_models models;
    double field[IMAGING_MAX_FIELDS];
    design_set_from_cli(prog, &a, &models, field, &rq.set);
    if (!a.fields) {
        /* curves want more than the three default fields */
        double top = field[rq.set.nfields - 1];
        rq.set.nfields = top > 0 ? 17 : 1;
        for (int i = 0; i < rq.set.nfields; i++)
            field[i] = top * i / 16.0;
    }
    char title[256];
    design_set_title(&a, &models, rq.focal_shift ? "chromatic focal shift" : "field curves, distortion, lateral colour",
                     title, sizeof title);
    rq.png = a.png, rq.title = title;
    lens_err err;
    int rc = field_run(&rq, stdout, NULL, &err);
    if (rc != 0)
        diag_print(prog, &err);
    imaging_models_free(&models);
    return rc != 0;
}
