/* lens-field: field curves, distortion, lateral colour and focal shift (man lens-field). */
#include <stdio.h>

#include "sparselens/design_cli.h"
#include "sparselens/field_run.h"

static const char *const prog = "lens-field";

int main(int argc, char **argv)
{
    field_cli o;
    field_cli_default(&o);
    const char *operand[1];
    int nop = opt_parse(&field_command, argc, argv, &o, operand, 1);
    imaging_cli_finish(prog, &o.im, operand, nop);
    field_request rq = {.delta = o.delta, .focal_shift = (int)o.focal_shift, .png = o.im.png};
    design_run r;
    /* curves want more than the three default fields: 17 up to the largest */
    design_run_begin(prog, &r, &o.im, &o.out, 17,
                     rq.focal_shift ? "chromatic focal shift"
                                    : "field curves, distortion, lateral colour",
                     &rq.set);
    rq.title = r.title;
    lens_err err;
    return design_run_end(prog, &r, field_run(&rq, &r.t, NULL, &err), &err);
}
