/* lens-layout: the meridional section of a lens with traced rays (man lens-layout). */
#include <stdio.h>

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
    layout_request rq = {.rays = (int)o.rays, .png = o.im.png, .svg = o.svg, .width = o.width};
    imaging_models models;
    double field[IMAGING_MAX_FIELDS];
    design_set_from_cli(prog, &o.im, &models, field, &rq.set);
    imaging_setup setup;
    char title[512];
    design_set_title(&o.im, &models, &rq.set, "meridional section", &setup, title, sizeof title);
    rq.title = title;
    table_out t;
    output_cli_begin(&o.out, &t, stdout, 6);
    lens_err err;
    int rc = layout_run(&rq, &t, &err);
    return design_cli_end(prog, &t, rc, &err, &setup, &models);
}
