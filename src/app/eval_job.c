/* lens-eval's job as a whole (eval_cli.h): the system read, then emitted as C or
 * evaluated by eval_run (eval_run.c) into an output file that appears only when
 * complete. */
#include "sparselens/eval_cli.h"

#include <errno.h>
#include <string.h>

#include "sparselens/emit_files.h"
#include "sparselens/outfile.h"

/* " NAME COUNT" per input with a count. */
static void print_per_input(FILE *log, const poly_system *sys, const size_t *count)
{
    for (int i = 0; i < poly_ninputs(sys) && i < 64; i++)
        if (count[i])
            fprintf(log, " %s %zu", poly_input_name(sys, i), count[i]);
}

/* With the lens's reference known, how many of those rays it passes: a test set over the
 * whole ray space (--sampling full) has many blocked rays beyond a training set's range,
 * which the system need only block (the report's passage lines say whether it does). */
static void print_outside(FILE *log, const poly_system *sys, const eval_run_stats *st)
{
    fprintf(log, "lens-eval: %zu of %zu rays outside the training domain (extrapolated):",
            st->outside, st->rows);
    print_per_input(log, sys, st->outside_input);
    if (st->lens_known) {
        fprintf(log, "; the lens passes %zu of them", st->outside_passing);
        if (st->outside_passing)
            fputc(':', log);
        print_per_input(log, sys, st->outside_passing_input);
    }
    fputc('\n', log);
}

int eval_cli_run(const eval_cli *o, FILE *log, eval_run_stats *st, lens_err *err)
{
    memset(st, 0, sizeof *st);
    eval_run_options opt = o->run;
    opt.json = o->out.json, opt.precision = (int)o->out.precision;
    poly_system *sys;
    if (o->emit_c && poly_c_name_check(o->name, err) != 0)
        return -1;
    if (poly_read(o->system, &sys, err) != 0)
        return -1;
    if (o->emit_c) {
        int rc = emit_poly_c_files(sys, o->output, o->name, err);
        poly_free(sys);
        return rc;
    }
    outfile *of = outfile_open(o->output, err);
    samples_reader *rd = NULL;
    int rc = -1;
    if (of && (rd = samples_open(o->input, err)) &&
             eval_run(sys, rd, outfile_stream(of), &opt, st, err) == 0)
        rc = outfile_commit(of, err);
    else if (of && rd && ferror(outfile_stream(of)))
        outfile_abort_write_error(of, errno, err); /* eval_run's report, with the file */
    else if (of)
        outfile_abort(of);
    if (rd)
        samples_close(rd);
    if (rc == 0 && st->outside && log)
        print_outside(log, sys, st);
    if (rc == 0 && st->other_lambda && log)
        fprintf(log, "lens-eval: %zu of %zu rays at another wavelength than the system's "
                "%.6g um (lambda is not among its inputs: evaluated as at %.6g um)\n",
                st->other_lambda, st->rows, st->lambda, st->lambda);
    poly_free(sys);
    return rc;
}
