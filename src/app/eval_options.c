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
     .def = "unit",
     .man =
     "How the report turns (u, v) into an angle; see THE REPORT above.\n"},
    {0, "raw", NULL, OPT_FLAG, OPT_AT(eval_cli, run.raw),
     .help = "write the polynomial values also for rays the system blocks (otherwise nan, "
             "and out_eta 0)"},
    {0, "emit", NULL, OPT_CHOICE, OPT_AT(eval_cli, emit_c), .choices = languages,
     .help = "write the system as a C function instead (no rays read)",
     .man =
     "The function is\n"
     ".IP\n"
     ".nf\n"
     "int NAME(const double in[NIN], double out[NOUT])\n"
     ".fi\n"
     ".IP\n"
     "with the inputs and outputs in the order of the system's\n"
     ".B inputs\n"
     "and\n"
     ".B outputs\n"
     "lines, returning 1 if the ray passes. The code scales the inputs, selects the part by\n"
     "sensor radius, computes every power and shared monomial once, and sums the terms in the\n"
     "same order as\n"
     ".BR lens-eval ,\n"
     "so compiled without floating-point contraction (the default of\n"
     ".B cc \\-std=c99\n"
     "or\n"
     ".BR \\-std=c11 )\n"
     "it gives the same values bit for bit. A second function\n"
     ".IP\n"
     ".nf\n"
     "void NAME_batch(size_t n, const double *in, double *out, unsigned char *pass)\n"
     ".fi\n"
     ".IP\n"
     "evaluates n rays (rows of inputs and outputs; pass may be NULL) with the same values,\n"
     "in blocks of 8 rays that the compiler vectorises, the frame and transforms included;\n"
     "GCC on x86-64 also compiles it for AVX-512 and AVX2 and picks a clone when the program\n"
     "loads.\n"
     "Measured on lens-fit's 5 \\(mu 40 term fisheye-ii system\n"
     "(\\-\\-outputs out_x,out_y,out_u,out_v,out_eta;\n"
     "meridional frame, 1/\\(*l\\(ha2; one thread of a Xeon with AVX-512, GCC 12;\n"
     ".BR \"make bench\" ,\n"
     "reports/bench.md): 19 ns per ray at\n"
     ".B \\-O2\n"
     "and 20 at\n"
     ".BR \"\\-O3 \\-march=native\" ,\n"
     "the time of liblens's own batch kernel (20 ns); a call of NAME per ray takes\n"
     "63 and 64 ns (NAME is compiled with GCC's generic tuning: the tuning of\n"
     ".B \\-march=native\n"
     "for these cores kept its sums' doubles in integer registers, 77 ns). Systems with\n"
     "several parts go through NAME ray by ray. The code\n"
     "needs only\n"
     ".I <math.h>\n"
     "and\n"
     ".IR <stddef.h> ,\n"
     "compiles as C11 (also with\n"
     ".BR \"\\-Wall \\-Wextra \\-Werror \\-pedantic\" )\n"
     "and as C++, its functions with C linkage either way. With\n"
     ".BI \\-o \" FILE\" .c\n"
     "the header\n"
     ".IB FILE .h\n"
     "is written beside it (both whole or neither; a path without .c gets .h added;\n"
     "standard output gets the C file alone): the two declarations inside\n"
     ".BR \"extern \\(dqC\\(dq\" .\n"
     "Every external symbol begins with\n"
     ".IR NAME ,\n"
     "so systems of several lenses link into one program. The names of the system (its lens,\n"
     "inputs and outputs) appear only in comments, every byte outside printable ASCII and\n"
     "every '*', '\\e' and \"??\" written as\n"
     ".BR \\exNN ;\n"
     "the lens file appears by its base name only.\n"},
    {0, "name", "NAME", OPT_STRING, OPT_AT(eval_cli, name),
     .help = "the prefix of every symbol of the C file (a C identifier, not a keyword, not "
             "reserved, not a name of <math.h>)",
     .def = "lens_poly"},
    {'o', "output", "FILE", OPT_STRING, OPT_AT(eval_cli, output),
     .help = "output file, never left half-written (not the input or the system)", .def = "standard output"},
    {.type = OPT_GROUP, OPT_AT(eval_cli, out), .group = output_cli_table},
    {0}};

const opt_command eval_command = {
    "lens-eval", "SYSTEM.poly [FILE|-] [options]\nSYSTEM.poly --emit c [--name NAME] [-o FILE]",
    "Evaluates a polynomial system (man 5 lens-poly) on the rays of a sample file (man 5 "
    "lens-samples; standard input if FILE is - or absent), finding the system's input columns "
    "by name, and writes the inputs and predicted outputs as a sample file. A malformed row "
    "writes a row of nan, is reported as FILE:LINE on stderr, and makes the exit status 1 at "
    "the end. Rays outside the training domain are evaluated (extrapolated) and counted on "
    "stderr; with --report also how many of them the lens passes (the others need only be "
    "blocked). So are rays at another wavelength than a single-wavelength system's.",
    eval_table};

void eval_cli_default(eval_cli *o)
{
    o->system = NULL;
    o->input = "-";
    o->output = "-";
    o->emit_c = 0;
    o->name = "lens_poly";
    o->out = (output_cli){0, 0};
    eval_run_options_default(&o->run);
}
