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
    imaging_models models;
    double field[IMAGING_MAX_FIELDS];
    design_set_from_cli(prog, &o.im, &models, field, &rq.set);
    imaging_setup setup;
    char title[512];
    design_set_title(&o.im, &models, &rq.set, rq.focus_freq > 0 ? "MTF through focus" : "MTF", &setup, title, sizeof title);
    rq.title = title;
    table_out t;
    output_cli_begin(&o.out, &t, stdout, 6);
    lens_err err;
    int rc = mtf_run(&rq, &t, NULL, NULL, &err);
    return design_cli_end(prog, &t, rc, &err, &setup, &models);
}
