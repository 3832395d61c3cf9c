/* lens-eval: evaluates a polynomial system on rays, or reports its fitting error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/eval_cli.h"
#include "sparselens/outfile.h"
#include "sparselens/poly.h"
#include "sparselens/samples.h"

static const char *prog = "lens-eval";

static void on_bad_row(void *ctx, const lens_err *err)
{
    (void)ctx;
    diag_print(prog, err);
}

int main(int argc, char **argv)
{
    eval_cli o;
    eval_cli_default(&o);
    o.run.on_bad_row = on_bad_row;
    const char *operand[2];
    int nop = opt_parse(&eval_command, argc, argv, &o, operand, 2);
    if (nop < 1)
        diag_die(prog, "no SYSTEM.poly given (see --help)");
    const char *sys_path = operand[0], *in_path = nop > 1 ? operand[1] : "-",
               *out_path = o.output, *name = o.name;
    int emit = o.emit_c;
    eval_run_options opt = o.run;
    opt.json = o.out.json, opt.precision = (int)o.out.precision;
    if (opt.json && !opt.report)
        diag_die(prog, "--json: only the report (--report) is written as JSON; predictions are "
                       "a sample file");
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
