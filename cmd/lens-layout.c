/* lens-layout: the meridional section of a lens with traced rays (man lens-layout). */
#include <stdio.h>

#include "sparselens/cli.h"
#include "sparselens/design_cli.h"
#include "sparselens/layout_run.h"

static const char *const prog = "lens-layout";

int main(int argc, char **argv)
{
    layout_cli o;
    layout_cli_default(&o);
    const char *operand[1];
    int nop = opt_parse(&layout_command, argc, argv, &o, operand, 1);
    imaging_cli_finish(prog, &o.im, operand, nop);
    cli_check_output(prog, o.svg);
    layout_request rq = {.rays = (int)o.rays, .full_stop = o.full_stop, .png = o.im.png, .svg = o.svg, .width = o.width};
    design_run r;
    design_run_begin(prog, &r, &o.im, &o.out, 0, "meridional section", &rq.set);
    rq.title = r.title;
    r.written[1] = o.svg;
    lens_err err;
    return design_run_end(prog, &r, layout_run(&rq, &r.t, &err), &err);
}
