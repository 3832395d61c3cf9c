/* lens-eval: evaluates a polynomial system on rays, or reports its fitting error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/cli.h"
#include "sparselens/eval_run.h"
#include "sparselens/outfile.h"
#include "sparselens/poly.h"
#include "sparselens/samples.h"

static const char *prog = "lens-eval";

static const char *usage =
    "usage: lens-eval SYSTEM.poly [FILE|-] [--report] [-o FILE] [options]\n"
    "Evaluates a polynomial system (man 5 lens-poly) on the rays of a sample file\n"
    "(man 5 lens-samples; stdin if FILE is - or absent), finding the system's input\n"
    "columns by name, and writes the inputs and predicted outputs as a sample file.\n"
    "A malformed row writes a row of nan, is reported as FILE:LINE on stderr, and\n"
    "makes the exit status 1 at the end. Rays outside the training domain are\n"
    "evaluated (extrapolated) and counted on stderr.\n"
    "  --report            write the fitting-error report instead: needs reference\n"
    "                      columns named as the outputs (a lens-trace test set)\n"
    "  --bins N            sensor radius bins of the report (default 8)\n"
    "  --rmax R            outer radius of the last bin, mm (default: largest seen)\n"
    "  --directions KIND   unit: (u, v) are unit-vector components (outer pupil, the\n"
    "                      default); slope: direction ~ (u, v, 1) (sensor, stop)\n"
    "  --raw               write the polynomial values also for rays the system\n"
    "                      blocks (default: nan, and out_eta 0)\n"
    "  --emit c            write the system as a C function instead (no rays read)\n"
    "  --name NAME         the C function's name (default lens_poly_eval)\n"
    "  -o FILE             output file (default stdout), never left half-written\n"
    "  --help              this text\n";

static void on_bad_row(void *ctx, const lens_err *err)
{
    (void)ctx;
    diag_print(prog, err);
}

int main(int argc, char **argv)
{
    const char *sys_path = NULL, *in_path = NULL, *out_path = "-", *emit = NULL;
    const char *name = "lens_poly_eval", *v;
    eval_run_options opt;
    eval_run_options_default(&opt);
    opt.on_bad_row = on_bad_row;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
            cli_help(usage);
        else if (strcmp(a, "--report") == 0)
            opt.report = 1;
        else if (strcmp(a, "--raw") == 0)
            opt.raw = 1;
        else if (cli_opt(prog, argc, argv, &i, "--bins", &v))
            opt.ropt.nbins = (int)cli_count(prog, "--bins", v, 1, 10000);
        else if (cli_opt(prog, argc, argv, &i, "--rmax", &v))
            opt.ropt.rmax = cli_positive(prog, "--rmax", v);
        else if (cli_opt(prog, argc, argv, &i, "--directions", &v)) {
            if (strcmp(v, "unit") == 0)
                opt.ropt.dirs = EVAL_DIR_UNIT;
            else if (strcmp(v, "slope") == 0)
                opt.ropt.dirs = EVAL_DIR_SLOPE;
            else
                diag_die(prog, "--directions: '%s' is not unit or slope", v);
        } else if (cli_opt(prog, argc, argv, &i, "--emit", &v)) {
            if (strcmp(v, "c") != 0)
                diag_die(prog, "--emit: only 'c' is supported, not '%s'", v);
            emit = v;
        } else if (cli_opt(prog, argc, argv, &i, "--name", &v))
            name = v;
        else if (cli_opt(prog, argc, argv, &i, "-o", &v) ||
                 cli_opt(prog, argc, argv, &i, "--output", &v))
            out_path = v;
        else if (a[0] == '-' && a[1] != '\0')
            diag_die(prog, "unknown option '%s' (see --help)", a);
        else if (!sys_path)
            sys_path = a;
        else if (!in_path)
            in_path = a;
        else
            diag_die(prog, "too many arguments: '%s' (see --help)", a);
    }
    if (!sys_path)
        diag_die(prog, "no SYSTEM.poly given (see --help)");
    if (!in_path)
        in_path = "-";
    if (strcmp(sys_path, "-") == 0 && strcmp(in_path, "-") == 0 && !emit)
        diag_die(prog, "the system and the rays cannot both come from stdin");

    lens_err err;
    poly_system *sys;
    if (poly_read(sys_path, &sys, &err) != 0) {
        diag_print(prog, &err);
        return 1;
    }
    outfile *of = outfile_open(out_path, &err);
    if (!of) {
        diag_print(prog, &err);
        poly_free(sys);
        return 1;
    }
    if (emit) {
        if (poly_emit_c(outfile_stream(of), sys, name) != 0) {
            outfile_abort(of);
            poly_free(sys);
            diag_die(prog, "--name: '%s' is not a C identifier, or writing failed", name);
        }
        poly_free(sys);
        if (outfile_commit(of, &err) != 0) {
            diag_print(prog, &err);
            return 1;
        }
        return 0;
    }
    samples_reader *rd = samples_open(in_path, &err);
    if (!rd) {
        diag_print(prog, &err);
        outfile_abort(of);
        poly_free(sys);
        return 1;
    }
    eval_run_stats st;
    int rc = eval_run(sys, rd, outfile_stream(of), &opt, &st, &err);
    samples_close(rd);
    if (rc != 0) {
        diag_print(prog, &err);
        outfile_abort(of);
        poly_free(sys);
        return 1;
    }
    if (outfile_commit(of, &err) != 0) {
        diag_print(prog, &err);
        poly_free(sys);
        return 1;
    }
    if (st.outside) {
        fprintf(stderr, "%s: %zu of %zu rays outside the training domain (extrapolated):", prog,
                st.outside, st.rows);
        for (int i = 0; i < poly_ninputs(sys) && i < 64; i++)
            if (st.outside_input[i])
                fprintf(stderr, " %s %zu", poly_input_name(sys, i), st.outside_input[i]);
        fputc('\n', stderr);
    }
    poly_free(sys);
    if (st.bad_rows) {
        fprintf(stderr, "%s: %zu of %zu rows malformed (written as nan)\n", prog, st.bad_rows,
                st.rows);
        return 1;
    }
    return 0;
}
