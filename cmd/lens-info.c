/* lens-info: first-order data of a lens as "key value" lines, or the lens itself in
 * the project's format (--format lens), optionally refocused (--focus MM). The work is
 * info_prepare and info_run (src/app/info_run.c). */
#include <math.h>
#include <stdio.h>

#include "sparselens/info_run.h"

static const char *const prog = "lens-info";

int main(int argc, char **argv)
{
    info_cli o;
    info_cli_default(&o);
    const char *operand[1];
    if (opt_parse(&info_command, argc, argv, &o, operand, 1) == 0)
        diag_die(prog, "no lens given (see --help)");
    const char *path = operand[0];
    lens_t lens;
    lens_err err;
    cli_load_lens(prog, path, lens_cli_options_get(&o.lens), &lens);
    lens_cli_options_free(&o.lens);
    int as_lens = info_prepare(&o, &lens, &err);
    if (as_lens == 1 && o.seidel) {
        lens_free(&lens);
        diag_die(prog, "--seidel: the sums are printed for the lens as it is; --format lens and --focus "
                       "print the lens itself");
    }
    if (!o.seidel && !isnan(o.seidel_field)) {
        lens_free(&lens);
        diag_die(prog, "--field: the chief ray's angle of --seidel, which is not given");
    }
    if (as_lens == 1 && o.out.json) { /* it would be ignored: the lens is not a table */
        lens_free(&lens);
        diag_die(prog, "--json: only the key values are written as JSON; the lens (--format "
                       "lens, --focus) is written in the project's format");
    }
    if (as_lens == 1) {
        lens_write(stdout, &lens);
        lens_free(&lens);
        return 0; /* stdout is checked at exit (diag_guard_stdout) */
    }
    info_report rep;
    if (as_lens < 0 || info_run(&o, &lens, &rep, &err) != 0) {
        diag_print(prog, &err);
        lens_free(&lens);
        return 1;
    }
    for (int k = 0; k < rep.nwarnings; k++)
        fprintf(stderr, "%s: warning: %s: %s\n", prog, path, rep.warnings[k]);
    if (o.seidel) {
        int rc = info_seidel_print(stdout, &lens, &o, &rep, &err);
        if (rc != 0)
            diag_print(prog, &err);
        lens_free(&lens);
        return rc != 0;
    }
    info_report_print(stdout, &lens, &rep, &o.out);
    lens_free(&lens);
    return 0; /* stdout is checked at exit (diag_guard_stdout) */
}
