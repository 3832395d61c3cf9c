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

static const opt_choice strategies[] = {
    {"pupil", SAMPLING_PUPIL}, {"rear", SAMPLING_REAR}, {"full", SAMPLING_FULL}, {NULL, 0}};
static const opt_choice targets[] = {{"outer", TRACE_TO_OUTER}, {"stop", TRACE_TO_STOP}, {NULL, 0}};

static const opt_spec trace_table[] = {
    {'n', NULL, "N", OPT_INT, OPT_AT(trace_cli, count), .lo = 1, .hi = 1e9,
     .help = "rays to write, as drawn: blocked ones too (out_eta 0, other outputs nan), so "
             "that fits and tests see both sides of each rim",
     .def = "10000"},
    {0, "seed", "S", OPT_INT, OPT_AT(trace_cli, seed), .lo = 0, .hi = 4e15,
     .help = "random seed; the same seed gives the same file", .def = "1"},
    {0, "sampling", NULL, OPT_CHOICE, OPT_AT(trace_cli, strategy), .choices = strategies,
     .help = "pupil: directions that pass from each sensor point; rear: aimed at the rear "
             "element (the usual way, a baseline); full: uniform over every direction that "
             "can pass (test sets that measure passage as a share of the light)",
     .def = "pupil"},
    {0, "lambda", "A:B|L", OPT_CALL, OPT_AT(trace_cli, lambda), .set = set_lambda,
     .help = "wavelengths uniform in A..B um, or one wavelength L",
     .def = "0.4:0.7, widened to the design file's wavelengths and narrowed to the glasses' "
            "data",
     .man =
     "A wavelength outside a glass's range is an error, not an extrapolation.\n"},
    {0, "to", NULL, OPT_CHOICE, OPT_AT(trace_cli, target), .choices = targets,
     .help = "the output frame: the outer pupil or the aperture stop", .def = "outer",
     .man =
     "See\n"
     ".BR lens-samples (5).\n"},
    {0, "passing-only", NULL, OPT_FLAG, OPT_AT(trace_cli, passing_only),
     .help = "write N rays that pass, leaving the blocked ones out",
     .man = "A lens that passes fewer than one in 1000 of the first 65536 rays traced is\n"
            "refused before anything is written.\n"},
    {0, "all", NULL, OPT_FLAG, OPT_AT(trace_cli, all),
     .help = "the default (N rays as drawn); kept for old scripts"},
    {0, "stop-columns", NULL, OPT_FLAG, OPT_AT(trace_cli, stop_columns),
     .help = "of the passage columns only ap_x ap_y, the ray's hit on the aperture stop (no "
             "pilot)"},
    {0, "clip-columns", NULL, OPT_FLAG, OPT_AT(trace_cli, clip_columns),
     .help = "the default passage columns (see PASSAGE in lens-trace(1)); kept for old "
             "scripts"},
    {0, "clip-surfaces", "LIST", OPT_STRING, OPT_AT(trace_cli, clip_list),
     .help = "ap_x ap_y and the surfaces N,N,... given (no pilot)",
     .man =
     "The stop's own number is ignored: it has\n"
     ".IR \"ap_x ap_y\" .\n"},
    {0, "no-passage-columns", NULL, OPT_FLAG, OPT_AT(trace_cli, no_passage_columns),
     .help = "no passage columns: the ten default columns alone"},
    {0, "sensor", "WxH", OPT_CALL, OPT_AT(trace_cli, sensor), .set = cli_set_size,
     .help = "sensor size in mm",
     .def = "the lens header's, else the one the design file's largest field implies",
     .man =
     "A Zemax or CODE V file states fields, not a sensor: the sensor is then 3:2 with its\n"
     "corner 3% beyond where the largest field's chief ray lands, so that a system fitted\n"
     "to the samples images every field of the file.\n"},
    {0, "fnumber", "N", OPT_POSITIVE, OPT_AT(trace_cli, fnumber),
     .help = "stop the lens down to f-number N (efl over entrance pupil diameter, paraxial, "
             "object at infinity) by scaling the aperture stop's semi-diameter",
     .def = "the lens's own",
     .man = "A comment line of the samples records it\n"
            ".RB ( \"# fnumber: N\" ).\n"
            "A lens opens no wider than its stop allows, and is stopped down to f/10000 at\n"
            "most (outside that range an error gives it).\n"},
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
    "(man 5 lens-samples) with columns x y u v lambda out_x out_y out_u out_v out_eta and the "
    "passage columns ap_x ap_y sN_x sN_y (the hits on the surfaces that limit the beam). With "
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
    o->lambda[0] = o->lambda[1] = NAN; /* the file's, else 0.4:0.7 (trace_run) */
    o->sensor = (cli_size){NAN, NAN};
    o->fnumber = NAN;
    o->target = TRACE_TO_OUTER;
    lens_cli_options_init(&o->lens);
}
