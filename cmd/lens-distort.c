/* lens-distort: distortion curve, relative illumination, grid map and OpenCV camera
 * model check of a lens or a polynomial system (man lens-distort). The work is
 * distort_cli_run (src/app/distort_job.c). */
#include <stdio.h>

#include "sparselens/cli.h"
#include "sparselens/distort_cli.h"

static const char *const prog = "lens-distort";

int main(int argc, char **argv)
{
    distort_cli o;
    distort_cli_default(&o);
    const char *operand[1];
    int nop = opt_parse(&distort_command, argc, argv, &o, operand, 1);
    imaging_cli_finish(prog, &o.im, operand, nop);
    cli_check_output(prog, o.map);
    cli_check_output(prog, o.png);
    lens_err err;
    int rc = distort_cli_run(&o, stdout, stderr, prog, &err);
    if (rc < 0)
        diag_print(prog, &err);
    const char *written[] = {o.png, o.map};
    if (rc >= 0 && cli_end_stdout(prog, written, 2))
        rc = 1;
    return rc < 0 ? 1 : rc;
}
