/* lens-fit: fits an adaptive sparse polynomial system to a sample file (see
 * man lens-fit). The work is fit_run (src/app/fit_run.c); here the files are opened,
 * the system written (or its C code), and the figures printed. */
#include <errno.h>
#include <stdio.h>

#include "sparselens/cli.h"
#include "sparselens/emit_files.h"
#include "sparselens/fit_run.h"
#include "sparselens/outfile.h"

static const char *const prog = "lens-fit";

int main(int argc, char **argv)
{
    fit_cli o;
    fit_cli_default(&o);
    const char *operand[1];
    if (opt_parse(&fit_command, argc, argv, &o, operand, 1) == 1)
        o.samples_path = operand[0];
    cli_check_output(prog, o.out_path);
    cli_check_not_input(prog, o.out_path, o.samples_path);
    lens_err err;
    if (o.emit_c && poly_c_name_check(o.name, &err) != 0) { /* before the fit, not after it */
        diag_print(prog, &err);
        return 2;
    }
    fit_run_stats st;
    poly_system *sys = NULL;
    samples_reader *in = samples_open(o.samples_path, &err);
    if (in)
        sys = fit_run(&o, in, o.quiet ? NULL : stderr, &st, &err);
    if (in)
        samples_close(in);
    if (!sys) {
        diag_print(prog, &err);
        return 1;
    }
    if (st.no_lens_path && !o.quiet)
        fprintf(stderr, "%s: note: the samples name no lens file (no '# lens-path:' line; "
                        "--lens FILE gives one): lens-spot and lens-distort will need --lens\n",
                prog);
    if (st.passage_gap[0])
        fprintf(stderr, "%s: warning: passage partial: %s\n", prog, st.passage_gap);
    const char *dropped = poly_get_meta(sys, "fit_dropped_circles");
    if (o.outputs && dropped && o.quiet) /* outputs named and not kept; without -q the
                                          * summary says it */
        fprintf(stderr, "%s: note: pass circles dropped with their outputs, as deciding "
                        "nothing (--keep-circles keeps them): %s\n", prog, dropped);
    int rc = 0;
    outfile *of = o.emit_c ? NULL : outfile_open(o.out_path, &err);
    if (o.emit_c) {
        rc = emit_poly_c_files(sys, o.out_path, o.name, &err) != 0;
    } else if (!of) {
        rc = 1;
    } else if (poly_write(outfile_stream(of), sys) != 0) {
        outfile_abort_write_error(of, errno, &err);
        rc = 1;
    } else if (outfile_commit(of, &err) != 0) {
        rc = 1;
    }
    char budget[256]; /* after the output, as one line that does not hide an error */
    if (rc)
        diag_print(prog, &err);
    else if (fit_run_term_budget(sys, o.fit.max_terms, budget, sizeof budget))
        fprintf(stderr, "%s: warning: %s\n", prog, budget);
    if (!rc && !o.quiet)
        fit_run_print_summary(stderr, sys, &st);
    poly_free(sys);
    return rc;
}
