/* lens-trace: generates sample rays and traces them through a lens, or traces the rays
 * given on stdin; writes a sample file (lens-samples(5)). The work is trace_run
 * (src/app/trace_run.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sparselens/outfile.h"
#include "sparselens/trace_run.h"

static const char *const prog = "lens-trace";

static void on_bad_row(void *ctx, const lens_err *err)
{
    (void)ctx;
    diag_print(prog, err);
}

static void progress(void *ctx, long written, long total, long traced)
{
    *(int *)ctx = 1;
    fprintf(stderr, "\r%s: %ld / %ld rays written (%ld traced)", prog, written, total, traced);
}

int main(int argc, char **argv)
{
    trace_cli o;
    trace_cli_default(&o);
    const char *operand[2];
    int nop = opt_parse(&trace_command, argc, argv, &o, operand, 2);
    for (int k = 0; k < nop; k++) {
        if (strcmp(operand[k], "-") == 0)
            o.from_stdin = 1;
        else if (o.lens_path)
            diag_die(prog, "one lens at a time ('%s' and '%s')", o.lens_path, operand[k]);
        else
            o.lens_path = operand[k];
    }
    if (!o.lens_path)
        diag_die(prog, "no lens given (see --help)");
    lens_t lens;
    cli_load_lens(prog, o.lens_path, lens_cli_options_get(&o.lens), &lens);
    lens_cli_options_free(&o.lens);
    lens_err err;
    if (!isnan(o.fnumber) && lens_set_fnumber(&lens, o.fnumber, &err) != 0) {
        diag_print(prog, &err);
        lens_free(&lens);
        return 1;
    }

    int shown = 0;
    trace_run_hooks hooks = {on_bad_row, NULL, &shown};
    if (!o.quiet && cli_progress_wanted() && o.count > 200000)
        hooks.progress = progress;
    samples_reader *in = NULL;
    outfile *of = NULL;
    long bad_rows = 0;
    int rc = (o.from_stdin && !(in = samples_open("-", &err))) ||
             !(of = outfile_open(o.out_path, &err)) ||
             trace_run(&o, &lens, in, outfile_stream(of), &hooks, &bad_rows, &err) != 0;
    if (shown)
        fputc('\n', stderr);
    if (rc && of)
        outfile_abort(of);
    else if (!rc && outfile_commit(of, &err) != 0)
        rc = 1;
    if (rc)
        diag_print(prog, &err);
    if (bad_rows)
        fprintf(stderr, "%s: %ld bad input rows (written as nan)\n", prog, bad_rows);
    if (in)
        samples_close(in);
    lens_free(&lens);
    return rc || bad_rows ? 1 : 0;
}
