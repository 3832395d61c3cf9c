/* lens-info's option table (see info_cli.h, options.h). */
#include "sparselens/info_cli.h"

#include <math.h>
#include <string.h>

#include "sparselens/glass.h"

/* --focus MM or inf. */
static void set_focus(const char *prog, const opt_spec *spec, const char *value, void *field)
{
    double *focus = field;
    if (strcmp(value, "inf") == 0) {
        *focus = INFINITY;
        return;
    }
    opt_spec as_number = *spec;
    as_number.type = OPT_POSITIVE;
    as_number.offset = 0;
    opt_store(prog, &as_number, value, focus);
}

static const opt_choice formats[] = {{"keys", 0}, {"lens", 1}, {NULL, 0}};

static const opt_spec info_table[] = {
    {0, "wavelength", "UM", OPT_POSITIVE, OPT_AT(info_cli, lambda),
     .help = "wavelength in micrometres", .def = "the d line, 0.5875618"},
    {0, "sensor", "WxH", OPT_CALL, OPT_AT(info_cli, sensor), .set = cli_set_size,
     .help = "sensor size in mm for field_of_view_deg",
     .def = "the lens header's, else the one the design file's largest field implies (lens-trace(1))"},
    {0, "format", NULL, OPT_CHOICE, OPT_AT(info_cli, as_lens), .choices = formats,
     .help = "lens: print the lens in the project's format instead (converts importers' files)",
     .def = "keys"},
    {0, "focus", "MM", OPT_CALL, OPT_AT(info_cli, focus), .set = set_focus,
     .help = "print the lens refocused on an object MM in front of its first surface ('inf' for "
             "infinity): the last thickness changes"},
    {0, "seidel", NULL, OPT_FLAG, OPT_AT(info_cli, seidel),
     .help = "print the paraxial marginal and chief rays surface by surface and the Seidel sums "
             "S_I..S_V each surface contributes (object at infinity) instead of the keys"},
    {0, "field", "DEG", OPT_DOUBLE, OPT_AT(info_cli, seidel_field), .lo = -89.9, .hi = 89.9,
     .help = "with --seidel: the chief ray's angle in object space", .def = "half the field of view"},
    {.type = OPT_GROUP, OPT_AT(info_cli, out), .group = output_cli_table},
    {.type = OPT_GROUP, OPT_AT(info_cli, lens), .group = lens_cli_table},
    {0}};

const opt_command info_command = {
    "lens-info", "LENS [options]",
    "Prints first-order data of LENS (.lens, .fx, .dat, .zmx, .seq) as 'key value' lines.",
    info_table};

void info_cli_default(info_cli *o)
{
    o->lens_path = NULL;
    o->lambda = GLASS_D_LINE;
    o->sensor = (cli_size){NAN, NAN};
    o->as_lens = 0;
    o->focus = NAN;
    o->seidel = 0;
    o->seidel_field = NAN;
    o->out = (output_cli){0, 0};
    lens_cli_options_init(&o->lens);
}
