/* lens-spot's option table (see spot_cli.h, options.h). */
#include "sparselens/spot_cli.h"

static const opt_choice patterns[] = {
    {"hexapolar", PUPIL_HEXAPOLAR}, {"grid", PUPIL_GRID}, {"random", PUPIL_RANDOM}, {NULL, 0}};

static const opt_spec spot_table[] = {
    {0, "fields", "LIST", OPT_STRING, OPT_AT(spot_cli, im.fields),
     .help = "field angles in degrees (object at infinity) or object heights in mm "
             "(--object-distance)",
     .def = "0, 0.7 and 1 times the largest"},
    {0, "wavelengths", "LIST", OPT_STRING, OPT_AT(spot_cli, im.wavelengths),
     .help = "um values or Fraunhofer names; the middle one is the primary", .def = "F,d,C"},
    {0, "pupil", NULL, OPT_CHOICE, OPT_AT(spot_cli, pattern), .choices = patterns,
     .help = "how rays sample the stop", .def = "hexapolar"},
    {0, "rays", "N", OPT_INT, OPT_AT(spot_cli, rays), .lo = 1, .hi = 10000000,
     .help = "rays per field and wavelength", .def = "400"},
    {0, "seed", "N", OPT_INT, OPT_AT(spot_cli, seed), .lo = 0, .hi = 4503599627370496.0,
     .help = "seed for --pupil random", .def = "1"},
    {0, "png", "FILE", OPT_STRING, OPT_AT(spot_cli, png), .help = "the spot diagram picture"},
    {0, "exr", "FILE", OPT_STRING, OPT_AT(spot_cli, exr), .help = "spot density as float images"},
    {.type = OPT_GROUP, OPT_AT(spot_cli, im), .group = imaging_cli_table},
    {0}};

const opt_command spot_command = {
    "lens-spot", "LENS|SYSTEM.poly [options]",
    "Spot diagrams: centroid, RMS and maximum radius about the chief ray and about the "
    "centroid, vignetted fraction, per field and wavelength, and pooled per field.",
    spot_table};

void spot_cli_default(spot_cli *o)
{
    imaging_cli_default(&o->im, "F,d,C");
    o->pattern = PUPIL_HEXAPOLAR;
    o->rays = 400;
    o->seed = 1;
    o->png = o->exr = NULL;
}
