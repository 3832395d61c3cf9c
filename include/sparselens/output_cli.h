#ifndef SPARSELENS_OUTPUT_CLI_H
#define SPARSELENS_OUTPUT_CLI_H
/* The flags of commands whose results scripts read (lens-info, lens-eval --report,
 * lens-spot, lens-distort), as one option-table group (options.h):
 *   --json          one JSON object instead of the text tables (table_out.h)
 *   --precision N   significant digits of the numbers (default: the command's)
 * In a command's table: {.type = OPT_GROUP, OPT_AT(my_options, out), .group =
 * output_cli_table}. */
#include "sparselens/options.h"
#include "sparselens/table_out.h"

typedef struct {
    int json;
    long precision; /* 0: the command's default */
} output_cli;

extern const opt_spec output_cli_table[];

/* table_out_begin with these flags. */
void output_cli_begin(const output_cli *o, table_out *t, FILE *f, int default_precision);

#endif
