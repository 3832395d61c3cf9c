/* --json and --precision (see output_cli.h). */
#include "sparselens/output_cli.h"

const opt_spec output_cli_table[] = {
    {0, "json", NULL, OPT_FLAG, OPT_AT(output_cli, json),
     .help = "write the results as one JSON object (tables as arrays of objects keyed by "
             "column name, warnings as a list) instead of text",
     .man = "The numbers are those of the text output; nan and inf become null.\n"},
    {0, "precision", "N", OPT_INT, OPT_AT(output_cli, precision), .lo = 1, .hi = 17,
     .help = "significant digits of the numbers written", .def = "the command's",
     .man = "17 digits read back to the same double.\n"},
    {0}};

void output_cli_begin(const output_cli *o, table_out *t, FILE *f, int default_precision)
{
    table_out_begin(t, f, o->json, (int)o->precision, default_precision);
}
