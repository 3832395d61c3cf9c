/* lens-mtf: diffraction and geometric MTF of a lens or a polynomial system (man lens-mtf). */
#include <stdio.h>

#include "sparselens/design_cli.h"
#include "sparselens/mtf_run.h"

static const char *const prog = "lens-mtf";

int main(int argc, char **argv)
{
    mtf_cli o;
    mtf_cli_default(&o);
    const char *operand[1];
    int nop = opt_parse(&mtf_command, argc, argv, &o, operand, 1);
    imaging_cli_finish(prog, &o.im, operand, nop);
    mtf_request rq = {.grid = (int)o.grid, .lens_method = (wavefront_method)o.wavefront,
                      .pixel_um = o.pixel_um, .steps = (int)o.steps, .focus_freq = o.through_focus,
                      .focus_range = o.focus_range, .focus_steps = (int)o.focus_steps, .png = o.im.png};
    design_run r;
    design_run_begin(prog, &r, &o.im, &o.out, 0,
                     rq.focus_freq > 0 ? "MTF through focus" : "MTF", &rq.set);
    rq.title = r.title;
    lens_err err;
    return design_run_end(prog, &r, mtf_run(&rq, &r.t, NULL, NULL, &err), &err);
}
