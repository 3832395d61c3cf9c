/* lens-spot's option table (see spot_cli.h, options.h). */
#include "sparselens/spot_cli.h"

static const opt_choice patterns[] = {
    {"hexapolar", PUPIL_HEXAPOLAR}, {"grid", PUPIL_GRID}, {"random", PUPIL_RANDOM}, {NULL, 0}};

static const opt_spec spot_table[] = {
    {.type = OPT_GROUP, OPT_AT(spot_cli, im), .group = imaging_cli_field_table},
    {0, "pupil", NULL, OPT_CHOICE, OPT_AT(spot_cli, pattern), .choices = patterns,
     .help = "how rays sample the stop", .def = "hexapolar",
     .man =
     "hexapolar: the centre and rings k = 1..R at radius k/R with 6k points each; grid: a\n"
     "square grid clipped to the disc; random: uniform random points (seeded).\n"},
    {0, "rays", "N", OPT_INT, OPT_AT(spot_cli, rays), .lo = 1, .hi = 10000000,
     .help = "rays per field and wavelength", .def = "400",
     .man =
     "Hexapolar rounds up to whole rings.\n"},
    {0, "seed", "N", OPT_INT, OPT_AT(spot_cli, seed), .lo = 0, .hi = 4503599627370496.0,
     .help = "seed for --pupil random", .def = "1"},
    {0, "png", "FILE", OPT_STRING, OPT_AT(spot_cli, png), .help = "the spot diagram picture",
     .man =
     "PNG, or SVG or PDF (vector) when FILE ends in .svg or .pdf (drawn through cairo, in\n"
     "DejaVu Sans). The title names the lens, then the f-number, the object and where the\n"
     "sensor is focused; a wavelength a model cannot image at a field is named in its panel.\n"
     "One panel per field (one row per model), the landing points in a colour per\n"
     "wavelength, the chief ray as a cross, the Airy disc of the first wavelength as a grey\n"
     "circle, a scale bar in micrometres and the RMS radius under each panel.\n"
     "All panels share one scale and are centred on their pooled centroid.\n"
     "The file is written to a temporary name and renamed when complete.\n"},
    {0, "exr", "FILE", OPT_STRING, OPT_AT(spot_cli, exr), .help = "spot density as float images",
     .man =
     "Panels of 256 x 256 pixels laid out like the PNG, one channel per wavelength named\n"
     ".BI lambda_ NNN nm\n"
     "and their mean\n"
     ".BR density ,\n"
     "in rays per square micrometre per launched ray, so that each panel integrates to the\n"
     "fraction of rays that pass.\n"
     "The pixel size is printed as a comment line.\n"},
    {.type = OPT_GROUP, OPT_AT(spot_cli, out), .group = output_cli_table},
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
    o->out = (output_cli){0, 0};
}
