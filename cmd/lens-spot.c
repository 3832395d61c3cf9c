/* lens-spot: spot diagrams of a lens or a polynomial system (man lens-spot). The work
 * is spot_cli_run (src/app/spot_job.c). */
#include <stdio.h>

#include "sparselens/cli.h"
#include "sparselens/spot_cli.h"

static const char *const prog = "lens-spot";

int main(int argc, char **argv)
{
    spot_cli o;
    spot_cli_default(&o);
    const char *operand[1];
    int nop = opt_parse(&spot_command, argc, argv, &o, operand, 1);
    imaging_cli_finish(prog, &o.im, operand, nop);
    cli_check_output(prog, o.exr);
    cli_check_output(prog, o.png);
    lens_err err;
    int rc = spot_cli_run(&o, stdout, stderr, prog, &err);
    if (rc < 0)
        diag_print(prog, &err);
    const char *written[] = {o.png, o.exr};
    if (rc >= 0 && cli_end_stdout(prog, written, 2))
        rc = 1;
    return rc < 0 ? 1 : rc;
}
