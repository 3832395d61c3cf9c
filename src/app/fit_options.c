/* lens-fit's option table (see fit_cli.h, options.h). */
#include "sparselens/fit_cli.h"

#include <string.h>

#include "sparselens/poly.h"

static void set_frame(const char *prog, const opt_spec *spec, const char *value, void *field)
{
    if (strcmp(value, "auto") != 0 && poly_frame_parse(value) < 0)
        opt_die(prog, spec, "'%s' is not auto, none or meridional", value);
    *(const char **)field = value;
}

static void set_lambda_transform(const char *prog, const opt_spec *spec, const char *value,
                                 void *field)
{
    if (strcmp(value, "auto") != 0 && poly_xform_parse(value) < 0)
        opt_die(prog, spec, "'%s' is not auto, identity or inverse-square", value);
    *(const char **)field = value;
}

static const opt_choice languages[] = {{"c", 1}, {NULL, 0}};

static const opt_spec fit_table[] = {
    {0, "terms", "N", OPT_INT, OPT_AT(fit_cli, fit.max_terms), .lo = 1, .hi = 10000,
     .help = "terms per output and part", .def = "40"},
    {0, "degree", "D", OPT_INT, OPT_AT(fit_cli, fit.max_degree), .lo = 0, .hi = POLY_MAX_DEGREE,
     .help = "candidates: all monomials up to degree D", .def = "11",
     .man =
     "At most 24.\n"},
    {0, "tolerance", "T", OPT_STRING, OPT_AT(fit_cli, tolerance),
     .help = "stop an output when its held-out RMS error <= T (output units, mm for "
             "positions); or name=T,... per output",
     .def = "0: off",
     .man =
     "With\n"
     ".IB name = T , name = T\n"
     "the outputs not named are not stopped by a tolerance.\n"},
    {0, "passage-tolerance", "F", OPT_DOUBLE, OPT_AT(fit_cli, fit.passage_tolerance), .lo = 0,
     .hi = 0.5,
     .help = "fit each passage hit (ap_x,ap_y, sN_x,sN_y) until its held-out RMS error <= F "
             "times its pass circle's radius; 0: as the other outputs",
     .def = "0.001",
     .man =
     "A tolerance given by name in\n"
     ".B \\-\\-tolerance\n"
     "wins. A looser passage has fewer terms and costs less to evaluate, and lets through\n"
     "rays the lens blocks and blocks rays it lets through: see PASSAGE for what each\n"
     "setting costs and buys.\n"},
    {0, "keep-circles", NULL, OPT_FLAG, OPT_AT(fit_cli, keep_circles),
     .help = "keep every passage pair sN_x,sN_y with its pass circle; by default one whose "
             "circle alone blocks none of the training rays the lens blocks is dropped",
     .man =
     "A circle can end up doing nothing: its radius is the furthest hit of the passing\n"
     "rays, and where a neighbouring surface vignettes first, that neighbour's circle\n"
     "already blocks every ray it would. The dropped pairs are named in the meta line\n"
     ".BR fit_dropped_circles ,\n"
     "and on stderr (also with\n"
     ".BR \\-q )\n"
     "when\n"
     ".B \\-\\-outputs\n"
     "named them; see PASSAGE.\n"},
    {0, "parts", "P", OPT_INT, OPT_AT(fit_cli, fit.max_parts), .lo = 1, .hi = 64,
     .help = "allow up to P radial parts where one polynomial misses T", .def = "1"},
    {0, "inputs", "LIST", OPT_STRING, OPT_AT(fit_cli, inputs),
     .help = "input columns; without lambda the samples must hold a single wavelength",
     .def = "x,y,u,v,lambda"},
    {0, "outputs", "LIST", OPT_STRING, OPT_AT(fit_cli, outputs),
     .help = "output columns, each once and none of them an input: each pair ap_x,ap_y and "
             "sN_x,sN_y (the passage columns of lens-trace), and out_x,out_y, gets a pass "
             "circle",
     .def = "out_x,out_y,out_u,out_v,out_eta and the pairs ap_x,ap_y and sN_x,sN_y the "
            "samples have",
     .man =
     "Leave out\n"
     ".B out_eta\n"
     "if transmittance is not needed; see PASSAGE for the pairs.\n"},
    {0, "frame", "F", OPT_CALL, OPT_AT(fit_cli, frame), .set = set_frame,
     .help = "meridional: fit in the frame of a rotationally symmetric lens (each ray turned "
             "about the axis so its sensor point lies on +x; one input fewer); none: as "
             "given; auto: meridional when the inputs hold x, y, u, v and the outputs come "
             "in pairs",
     .def = "auto",
     .man =
     ".B none\n"
     "is the form of files before frames existed.\n"},
    {0, "frame-except", "LIST", OPT_STRING, OPT_AT(fit_cli, frame_except),
     .help = "outputs fitted outside the frame: pairs that do not turn with the ray (every "
             "direction of lens-trace does, the outer pupil's u, v included)",
     .def = "none: every pair in the frame",
     .man =
     "Names not among the outputs are ignored. Give out_u,out_v for samples of earlier "
     "versions, whose outer-pupil frame did not turn with the ray.\n"},
    {0, "lambda-transform", "T", OPT_CALL, OPT_AT(fit_cli, lambda_transform),
     .set = set_lambda_transform,
     .help = "inverse-square: polynomials in 1/lambda^2 (dispersion is nearly linear in it); "
             "identity: in lambda; auto: inverse-square when lambda is an input",
     .def = "auto"},
    {0, "holdout", "F", OPT_DOUBLE, OPT_AT(fit_cli, fit.holdout), .lo = 0, .hi = 0.9,
     .help = "fraction of samples held out for stopping", .def = "0.2",
     .man =
     "0 uses the training error instead.\n"},
    {0, "seed", "S", OPT_INT, OPT_AT(fit_cli, fit.seed), .lo = 0, .hi = 4294967295.0,
     .help = "seed of the held-out split", .def = "1"},
    {0, "threads", "N", OPT_INT, OPT_AT(fit_cli, fit.threads), .lo = 1, .hi = 1024,
     .help = "threads; the result does not depend on it", .def = "all"},
    {0, "lens", "NAME|FILE", OPT_STRING, OPT_AT(fit_cli, lens),
     .help = "the lens recorded in the system: a name, or a lens file (its name header "
             "recorded, and the file as the lens-path, relative to the directory of -o FILE)",
     .def = "the samples' '# lens:' and '# lens-path:' lines, which lens-trace writes; else "
            "the sample file's base name",
     .man = "Without a lens path (samples without\n"
            ".BR \"# lens-path:\" )\n"
            "a note on stderr says that lens-spot and lens-distort will need their\n"
            ".BR \\-\\-lens .\n"
            "A relative lens path is made relative to the directory of\n"
            ".B \\-o\n"
            ".IR FILE ,\n"
            "so the system finds its lens from anywhere while the two stay where they are\n"
            ".RB ( lens-poly (5)).\n"},
    {0, "emit", NULL, OPT_CHOICE, OPT_AT(fit_cli, emit_c), .choices = languages,
     .help = "write C code (a function NAME(in, out)) instead of the system",
     .man =
     "Also its many-ray variant\n"
     ".IB NAME _batch\n"
     "(see\n"
     ".BR lens-eval (1)),\n"
     "which runs blocks of 8 rays that compilers vectorise, the meridional frame and the\n"
     "transforms (the defaults) included. With\n"
     ".BI \\-o \" FILE\" .c\n"
     "also the header\n"
     ".IB FILE .h\n"
     "(extern \\(dqC\\(dq for C++); every external symbol begins with\n"
     ".IR NAME ;\n"
     "names from the samples reach only comments, escaped (see\n"
     ".BR lens-eval (1)).\n"},
    {0, "name", "NAME", OPT_STRING, OPT_AT(fit_cli, name),
     .help = "for --emit c: the prefix of every symbol of the C file (a C identifier, not a "
             "keyword, not reserved, not a name of <math.h>)",
     .def = "lens_poly"},
    {'o', "output", "FILE", OPT_STRING, OPT_AT(fit_cli, out_path),
     .help = "output file (written whole or not at all; not the samples file)", .def = "standard output"},
    {'q', "quiet", NULL, OPT_FLAG, OPT_AT(fit_cli, quiet),
     .help = "no progress and summary on stderr"},
    {0}};

const opt_command fit_command = {
    "lens-fit", "[options] [FILE|-]",
    "Fits an adaptive sparse polynomial system (man 5 lens-poly) to a sample file (man 5 "
    "lens-samples) and writes it to standard output or -o FILE.",
    fit_table};

void fit_cli_default(fit_cli *o)
{
    memset(o, 0, sizeof *o);
    o->samples_path = "-";
    o->out_path = "-";
    o->inputs = "x,y,u,v,lambda";
    o->frame = "auto";
    o->frame_except = "";
    o->lambda_transform = "auto";
    o->name = "lens_poly";
    fit_options_default(&o->fit);
}
