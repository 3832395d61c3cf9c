/* lens-eval's option table (see eval_cli.h, options.h). */
#include "sparselens/eval_cli.h"

static const opt_choice directions[] = {
    {"unit", EVAL_DIR_UNIT}, {"slope", EVAL_DIR_SLOPE}, {NULL, 0}};
static const opt_choice languages[] = {{"c", 1}, {NULL, 0}};

static const opt_spec eval_table[] = {
    {0, "report", NULL, OPT_FLAG, OPT_AT(eval_cli, run.report),
     .help = "write the fitting-error report instead: needs reference columns named as the "
             "outputs (a lens-trace test set)"},
    {0, "bins", "N", OPT_INT, OPT_AT(eval_cli, run.ropt.nbins), .lo = 1, .hi = 10000,
     .help = "sensor radius bins of the report", .def = "8"},
    {0, "rmax", "MM", OPT_POSITIVE, OPT_AT(eval_cli, run.ropt.rmax),
     .help = "outer radius of the last bin", .def = "the largest seen"},
    {0, "directions", NULL, OPT_CHOICE, OPT_AT(eval_cli, run.ropt.dirs), .choices = directions,
     .help = "unit: (u, v) are unit-vector components (outer pupil); slope: the direction is "
             "proportional to (u, v, 1) (sensor, stop)",
     .def = "unit"},
    {0, "raw", NULL, OPT_FLAG, OPT_AT(eval_cli, run.raw),
     .help = "write the polynomial values also for rays the system blocks (otherwise nan, "
             "and out_eta 0)"},
    {0, "emit", NULL, OPT_CHOICE, OPT_AT(eval_cli, emit_c), .choices = languages,
     .help = "write the system as a C function instead (no rays read)"},
    {0, "name", "NAME", OPT_STRING, OPT_AT(eval_cli, name), .help = "the C function's name",
     .def = "lens_poly_eval"},
    {'o', "output", "FILE", OPT_STRING, OPT_AT(eval_cli, output),
     .help = "output file, never left half-written", .def = "standard output"},
    {0}};

const opt_command eval_command = {
    "lens-eval", "SYSTEM.poly [FILE|-] [options]",
    "Evaluates a polynomial system (man 5 lens-poly) on the rays of a sample file (man 5 "
    "lens-samples; standard input if FILE is - or absent), finding the system's input columns "
    "by name, and writes the inputs and predicted outputs as a sample file. A malformed row "
    "writes a row of nan, is reported as FILE:LINE on stderr, and makes the exit status 1 at "
    "the end. Rays outside the training domain are evaluated (extrapolated) and counted on "
    "stderr.",
    eval_table};

void eval_cli_default(eval_cli *o)
{
    o->system = NULL;
    o->input = "-";
    o->output = "-";
    o->emit_c = 0;
    o->name = "lens_poly_eval";
    eval_run_options_default(&o->run);
}
