/* lens-fan: ray fans of a lens or a polynomial system (man lens-fan). */
#include <stdio.h>

#include "sparselens/design_cli.h"
#include "sparselens/fan_run.h"

static const char *const prog = "lens-fan";

int main(int argc, char **argv)
{
    fan_cli o;
    fan_cli_default(&o);
    const char *operand[1];
    int nop = opt_parse(&fan_command, argc, argv, &o, operand, 1);
    imaging_cli_finish(prog, &o.im, operand, nop);
    fan_request rq = {.npts = (int)o.points, .png = o.im.png};
    design_run r;
    design_run_begin(prog, &r, &o.im, &o.out, 0, "ray fans", &rq.set);
    rq.title = r.title;
    lens_err err;
    return design_run_end(prog, &r, fan_run(&rq, &r.t, NULL, &err), &err);
}
