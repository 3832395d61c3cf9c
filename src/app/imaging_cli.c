/* The shared command line of lens-spot and lens-distort (see imaging_cli.h). */
#include "sparselens/imaging_cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/cli.h"

const opt_spec imaging_cli_table[] = {
    {0, "object-distance", "MM", OPT_POSITIVE, OPT_AT(imaging_cli, object_distance),
     .help = "a finite object, MM in front of the first vertex", .def = "infinity"},
    {0, "focus", "file|paraxial|best", OPT_STRING, OPT_AT(imaging_cli, focus),
     .help = "the sensor plane: as in the lens file, the paraxial focus, or the plane of "
             "least RMS spot radius",
     .def = "file",
     .man =
     "The paraxial focus is that of the primary wavelength for the object distance; the best\n"
     "plane minimises the sum over fields and wavelengths of the squared RMS radius about the\n"
     "centroid (closed form, since every ray moves linearly with the plane).\n"
     "With\n"
     ".BR \\-\\-compare ,\n"
     "both models are shown on the lens's plane.\n"},
    {0, "compare", "SYSTEM.poly", OPT_STRING, OPT_AT(imaging_cli, compare),
     .help = "also through a fitted system, shown beside the lens",
     .man =
     "Its inputs must be x y u v lambda and its outputs include out_x out_y out_u out_v.\n"},
    {0, "lens", "LENS", OPT_STRING, OPT_AT(imaging_cli, lens),
     .help = "the lens of a SYSTEM.poly given as the first argument",
     .man =
     "Use it when the path the system records is not right. Without it the system's\n"
     ".B lens-path\n"
     "is loaded (as written, else relative to the\n"
     ".I .poly\n"
     "file's directory,\n"
     ".BR lens-poly (5));\n"
     "when that file is not found the message names the lens and the path.\n"},
    {.type = OPT_GROUP, OPT_AT(imaging_cli, lopt), .group = lens_cli_table},
    {0}};

void imaging_cli_default(imaging_cli *a, const char *wavelengths)
{
    memset(a, 0, sizeof *a);
    a->wavelengths = wavelengths;
    a->focus = "file";
    a->object_distance = INFINITY;
    lens_cli_options_init(&a->lopt);
}

void imaging_cli_finish(const char *prog, imaging_cli *a, const char *const *operands, int n)
{
    if (n == 0)
        diag_die(prog, "no lens given (see --help)");
    a->input = operands[0];
    lens_err err;
    a->nl = wavelengths_parse(a->wavelengths, a->lambda, IMAGING_MAX_WAVELENGTHS, &err);
    if (a->nl < 0)
        diag_die(prog, "--wavelengths: %s", err.msg);
    if (focus_mode_parse(a->focus, &a->focus_mode) != 0)
        diag_die(prog, "--focus: '%s' is not file, paraxial or best", a->focus);
}

int imaging_cli_load(const char *prog, imaging_cli *a, imaging_models *models, imaging im[2],
                     const char *names[2])
{
    lens_err err;
    int rc = imaging_models_load(a->input, a->compare, a->lens, lens_cli_options_get(&a->lopt),
                                 models, &err);
    lens_cli_options_free(&a->lopt);
    if (rc != 0) {
        diag_print(prog, &err);
        exit(1);
    }
    return imaging_models_setup(models, a->object_distance, im, names);
}

const char *imaging_cli_basename(const imaging_cli *a)
{
    const char *slash = strrchr(a->input, '/');
    return slash ? slash + 1 : a->input;
}
