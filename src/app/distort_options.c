/* lens-distort's option table (see distort_cli.h, options.h). */
#include "sparselens/distort_cli.h"

#include <math.h>

#include "sparselens/projection.h"

static const opt_choice mappings[] = {
    {"rectilinear", PROJ_RECTILINEAR}, {"equidistant", PROJ_EQUIDISTANT},
    {"equisolid", PROJ_EQUISOLID},     {"stereographic", PROJ_STEREOGRAPHIC},
    {"orthographic", PROJ_ORTHOGRAPHIC}, {NULL, 0}};

/* --opencv WxH: whole pixels, 16..100000 each. */
static void set_pixels(const char *prog, const opt_spec *spec, const char *value, void *field)
{
    cli_size *s = field;
    cli_pair(prog, spec, value, 'x', &s->w, &s->h);
    if (!(s->w >= 16 && s->h >= 16 && s->w <= 100000 && s->h <= 100000) || s->w != floor(s->w) ||
        s->h != floor(s->h))
        opt_die(prog, spec, "give the sensor size in whole pixels, e.g. 1920x1080");
}

static const opt_spec distort_table[] = {
    {0, "fields", "LIST", OPT_STRING, OPT_AT(distort_cli, im.fields),
     .help = "field angles in degrees, or object heights in mm with --object-distance",
     .def = "11 fields up to the largest"},
    {0, "wavelengths", "LIST", OPT_STRING, OPT_AT(distort_cli, im.wavelengths),
     .help = "um values or Fraunhofer names; the middle one is used", .def = "d"},
    {0, "illum-rays", "N", OPT_INT, OPT_AT(distort_cli, illum_rays), .lo = 0, .hi = 512,
     .help = "relative illumination from 8N x 8N sensor directions a field; 0 skips it", .def = "32",
     .man =
     "The directions span the disc that can pass (about 0.8 of the square); 0 also drops the column.\n"},
    {0, "grid", "N", OPT_INT, OPT_AT(distort_cli, grid), .lo = 2, .hi = 501,
     .help = "grid map points per side", .def = "17"},
    {0, "mapping", NULL, OPT_CHOICE, OPT_AT(distort_cli, mapping), .choices = mappings,
     .help = "the ideal projection of the grid map", .def = "the one the lens follows best"},
    {0, "sensor", "WxH", OPT_CALL, OPT_AT(distort_cli, sensor), .set = cli_set_size,
     .help = "sensor size in mm for the grid map",
     .def = "the lens header's, else a square inscribed in the largest field",
     .man =
     "Also for the OpenCV check.\n"},
    {0, "exaggerate", "K", OPT_POSITIVE, OPT_AT(distort_cli, exaggerate),
     .help = "displacement factor in the picture", .def = "automatic",
     .man =
     "The automatic factor is the round one (at least 1) that draws the largest displacement\n"
     "at about a tenth of the half width.\n"},
    {0, "map", "FILE", OPT_STRING, OPT_AT(distort_cli, map),
     .help = "write the grid displacement field as text ('-': standard output)"},
    {0, "png", "FILE", OPT_STRING, OPT_AT(distort_cli, png), .help = "the grid map picture",
     .man = "PNG, or SVG or PDF (vector) when FILE ends in .svg or .pdf. With\n"
            ".BR \\-\\-compare ,\n"
            "the lens's grid is drawn wide, solid and blue and the system's over it thin, dashed\n"
            "and red, so both stay visible, with a legend of the two styles above the map; the\n"
            "title names the lens, the mapping and the wavelength, then the f-number, the object\n"
            "and where the sensor is focused.\n"},
    {0, "opencv", "WxH", OPT_CALL, OPT_AT(distort_cli, opencv), .set = set_pixels,
     .help = "fit OpenCV's Brown-Conrady and fisheye models for a sensor of WxH pixels; "
             "prints coefficients and residuals",
     .man =
     "Object at infinity only.\n"},
    {.type = OPT_GROUP, OPT_AT(distort_cli, out), .group = output_cli_table},
    {.type = OPT_GROUP, OPT_AT(distort_cli, im), .group = imaging_cli_table},
    {0}};

const opt_command distort_command = {
    "lens-distort", "LENS|SYSTEM.poly [options]",
    "Distortion of real chief rays (aimed through the stop centre) against f tan(theta) and "
    "the fisheye projections, relative illumination, grid map, OpenCV model fits.",
    distort_table};

void distort_cli_default(distort_cli *o)
{
    imaging_cli_default(&o->im, "d");
    o->illum_rays = 32;
    o->grid = 17;
    o->mapping = -1;
    o->sensor = (cli_size){NAN, NAN};
    o->exaggerate = NAN;
    o->map = o->png = NULL;
    o->opencv = (cli_size){0, 0};
    o->out = (output_cli){0, 0};
}
