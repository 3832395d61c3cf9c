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
    imaging_models models;
    double field[IMAGING_MAX_FIELDS];
    design_set_from_cli(prog, &o.im, &models, field, &rq.set);
    imaging_setup setup;
    char title[512];
    design_set_title(&o.im, &models, &rq.set, "ray fans", &setup, title, sizeof title);
    rq.title = title;
    table_out t;
    output_cli_begin(&o.out, &t, stdout, 6);
    lens_err err;
    int rc = fan_run(&rq, &t, NULL, &err);
    return design_cli_end(prog, &t, rc, &err, &setup, &models);
}
