/* lens-trace's option table (see trace_cli.h, options.h). */
#include "sparselens/trace_cli.h"

#include <math.h>
#include <string.h>

/* --lambda A:B or L */
static void set_lambda(const char *prog, const opt_spec *spec, const char *value, void *field)
{
    double *l = field;
    if (strchr(value, ':')) {
        cli_pair(prog, spec, value, ':', &l[0], &l[1]);
    } else {
        opt_spec as_number = *spec;
        as_number.type = OPT_DOUBLE;
        as_number.offset = 0;
        opt_store(prog, &as_number, value, l);
        l[1] = l[0];
    }
    if (!(l[0] > 0 && l[1] >= l[0]))
        opt_die(prog, spec, "need 0 < A <= B (micrometres), got '%s'", value);
}

static const opt_choice strategies[] = {{"pupil", SAMPLING_PUPIL}, {"rear", SAMPLING_REAR}, {NULL, 0}};
static const opt_choice targets[] = {{"outer", TRACE_TO_OUTER}, {"stop", TRACE_TO_STOP}, {NULL, 0}};

static const opt_spec trace_table[] = {
    {'n', NULL, "N", OPT_INT, OPT_AT(trace_cli, count), .lo = 1, .hi = 1e9,
     .help = "rays to write: passing rays, or all rays with --all", .def = "10000"},
    {0, "seed", "S", OPT_INT, OPT_AT(trace_cli, seed), .lo = 0, .hi = 4e15,
     .help = "random seed; the same seed gives the same file", .def = "1"},
    {0, "sampling", NULL, OPT_CHOICE, OPT_AT(trace_cli, strategy), .choices = strategies,
     .help = "pupil: directions that pass from each sensor point; rear: aimed at the rear "
             "element (the usual way, a baseline)",
     .def = "pupil"},
    {0, "lambda", "A:B|L", OPT_CALL, OPT_AT(trace_cli, lambda), .set = set_lambda,
     .help = "wavelengths uniform in A..B um, or one wavelength L", .def = "0.4:0.7",
     .man =
     "A wavelength outside a glass's range is an error, not an extrapolation.\n"},
    {0, "to", NULL, OPT_CHOICE, OPT_AT(trace_cli, target), .choices = targets,
     .help = "the output frame: the outer pupil or the aperture stop", .def = "outer",
     .man =
     "See\n"
     ".BR lens-samples (5).\n"},
    {0, "all", NULL, OPT_FLAG, OPT_AT(trace_cli, all),
     .help = "also write rays that do not pass (out_eta 0, other outputs nan)"},
    {0, "stop-columns", NULL, OPT_FLAG, OPT_AT(trace_cli, stop_columns),
     .help = "add columns ap_x ap_y: the ray's hit on the aperture stop (nan when it does not "
             "get through to the stop); lens-fit then fits a stop pass circle",
     .man =
     "The columns come after the default ten; the hit is in mm of the lens frame, whatever the\n"
     ".B \\-\\-to\n"
     "frame, and\n"
     ".B nan\n"
     "when the ray is clipped in the rear group or blocked at the stop itself. A ray that\n"
     "reaches the stop may still be blocked in front of it\n"
     ".RI ( out_eta\n"
     "0). Works in generation and with\n"
     ".BR \\- .\n"
     "Without the option the output is exactly the ten default columns.\n"},
    {0, "clip-columns", NULL, OPT_FLAG, OPT_AT(trace_cli, clip_columns),
     .help = "ap_x ap_y, plus sN_x sN_y for every other surface N (numbered as in lens-info) "
             "that blocks >= 0.5% of a pilot trace of 65536 rays (same sampling, fixed seed): "
             "the hit on surface N, nan when the ray does not get there within its "
             "semi-diameter; lens-fit fits a pass circle for each",
     .man =
     "The hit on surface\n"
     ".I N\n"
     "is taken before refraction there, in mm of the lens frame;\n"
     ".B nan\n"
     "when the ray died at a surface nearer the sensor, or at\n"
     ".I N\n"
     "itself. The pilot uses the sensor and wavelengths of the run but a fixed seed, so a\n"
     "training and a test set traced with different\n"
     ".B \\-\\-seed\n"
     "get the same columns. The front surface is left out in the outer frame (out_x, out_y\n"
     "is its hit already). A comment line before the header lists the surfaces chosen and\n"
     "their blocked shares, and the stop's.\n"
     ".BR lens-fit (1)\n"
     "fits every such pair by default, so the system also blocks rays clipped by inner\n"
     "element rims (on fisheye-ii, rear sampling, its false passes drop from 13708 to 291 of\n"
     "100000 rays against the stop circle alone: reports/vignetting.md). Each pair is one\n"
     "more fitted output to evaluate.\n"},
    {0, "clip-surfaces", "LIST", OPT_STRING, OPT_AT(trace_cli, clip_list),
     .help = "as --clip-columns, for the surfaces N,N,... given (no pilot)",
     .man =
     "The stop's own number is ignored: it has\n"
     ".IR \"ap_x ap_y\" .\n"
     "Needed with\n"
     ".B \\-\n"
     "when the lens header has no sensor size and\n"
     ".B \\-\\-sensor\n"
     "is not given.\n"},
    {0, "sensor", "WxH", OPT_CALL, OPT_AT(trace_cli, sensor), .set = cli_set_size,
     .help = "sensor size in mm", .def = "the lens header's"},
    {0, "fnumber", "N", OPT_POSITIVE, OPT_AT(trace_cli, fnumber),
     .help = "stop the lens down to f-number N (efl over entrance pupil diameter, paraxial, "
             "object at infinity) by scaling the aperture stop's semi-diameter",
     .def = "the lens's own",
     .man = "A comment line of the samples records it\n"
            ".RB ( \"# fnumber: N\" ).\n"
            "A lens opens no wider than its stop allows (an error).\n"},
    {0, "threads", "T", OPT_INT, OPT_AT(trace_cli, threads), .lo = 1, .hi = 1024,
     .help = "threads", .def = "all"},
    {'o', "output", "FILE", OPT_STRING, OPT_AT(trace_cli, out_path),
     .help = "write FILE (complete or not at all) instead of standard output",
     .man =
     "The file is written through a temporary name and renamed when complete: an error or an\n"
     "interrupt leaves no partial file.\n"},
    {'q', "quiet", NULL, OPT_FLAG, OPT_AT(trace_cli, quiet),
     .help = "no progress line on stderr (shown only on a terminal, for more than 200000 rays)"},
    {.type = OPT_GROUP, OPT_AT(trace_cli, lens), .group = lens_cli_table},
    {0}};

const opt_command trace_command = {
    "lens-trace", "LENS [options] [-]",
    "Generates N rays from the sensor and traces them through LENS, writing a sample file "
    "(man 5 lens-samples) with columns x y u v lambda out_x out_y out_u out_v out_eta. With "
    "'-', traces the rays read from standard input (columns x y u v lambda, found by name) "
    "instead: one output row per input row, rays that do not pass with out_eta 0, bad rows "
    "as nan (exit status 1).",
    trace_table};

void trace_cli_default(trace_cli *o)
{
    memset(o, 0, sizeof *o);
    o->out_path = "-";
    o->count = 10000;
    o->seed = 1;
    o->strategy = SAMPLING_PUPIL;
    o->lambda[0] = 0.4, o->lambda[1] = 0.7;
    o->sensor = (cli_size){NAN, NAN};
    o->fnumber = NAN;
    o->target = TRACE_TO_OUTER;
    lens_cli_options_init(&o->lens);
}
