/* lens-eval: evaluates a polynomial system on rays, or reports its fitting error. The
 * work is eval_cli_run (src/app/eval_job.c). */
#include <stdio.h>
#include <string.h>

#include "sparselens/cli.h"
#include "sparselens/eval_cli.h"

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
    o.system = operand[0];
    o.input = nop > 1 ? operand[1] : "-";
    if (o.out.json && !o.run.report)
        diag_die(prog, "--json: only the report (--report) is written as JSON; predictions are "
                       "a sample file");
    /* an option of the other mode would be silently ignored: said instead (a value equal
     * to its default cannot be told from none, and changes nothing) */
    eval_report_options d;
    eval_report_options_default(&d);
    const char *report_only = o.run.ropt.nbins != d.nbins  ? "--bins"
                              : o.run.ropt.rmax != d.rmax   ? "--rmax"
                              : o.run.ropt.dirs != d.dirs   ? "--directions"
                                                            : NULL;
    if (report_only && (!o.run.report || o.emit_c))
        diag_die(prog, "%s: only for the report (--report)%s", report_only,
                 o.emit_c ? ", not with --emit" : "");
    if (o.run.raw && (o.run.report || o.emit_c))
        diag_die(prog, "--raw: only for predictions, not with %s", o.emit_c ? "--emit" : "--report");
    if (o.run.report && o.emit_c)
        diag_die(prog, "--report and --emit: one or the other");
    if (strcmp(o.system, "-") == 0 && strcmp(o.input, "-") == 0 && !o.emit_c)
        diag_die(prog, "the system and the rays cannot both come from stdin");
    cli_check_not_input(prog, o.output, o.input);
    cli_check_not_input(prog, o.output, o.system);
    lens_err err;
    eval_run_stats st;
    if (eval_cli_run(&o, stderr, &st, &err) != 0) {
        diag_print(prog, &err);
        return 1;
    }
    if (st.bad_rows) {
        fprintf(stderr, "%s: %zu of %zu rows malformed (%s)\n", prog, st.bad_rows, st.rows,
                o.run.report ? "left out of the report" : "written as nan");
        return 1;
    }
    return 0;
}
