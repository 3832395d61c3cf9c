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
    imaging_models models;
    double field[IMAGING_MAX_FIELDS];
    design_set_from_cli(prog, &o.im, &models, field, &rq.set);
    if (!o.im.fields) {
        /* curves want more than the three default fields: 17 up to the largest */
        double top = field[rq.set.nfields - 1];
        rq.set.nfields = top > 0 ? 17 : 1;
        for (int i = 0; i < rq.set.nfields; i++)
            field[i] = top * i / 16.0;
        rq.set.focused = 0; /* --focus best over these fields */
        lens_err e;
        if (design_set_focus(&rq.set, &e) != 0) {
            imaging_models_free(&models);
            diag_die(prog, "%s", e.msg);
        }
    }
    imaging_setup setup;
    char title[512];
    design_set_title(&o.im, &models, &rq.set,
                     rq.focal_shift ? "chromatic focal shift" : "field curves, distortion, lateral colour",
                     &setup, title, sizeof title);
    rq.title = title;
    table_out t;
    output_cli_begin(&o.out, &t, stdout, 6);
    lens_err err;
    int rc = field_run(&rq, &t, NULL, &err);
    return design_cli_end(prog, &t, rc, &err, &setup, &models);
}
