#ifndef SPARSELENS_INFO_CLI_H
#define SPARSELENS_INFO_CLI_H
/* lens-info's options: its option table (options.h) and the struct it fills. */
#include "sparselens/cli.h"
#include "sparselens/lens_cli_options.h"
#include "sparselens/options.h"
#include "sparselens/output_cli.h"

typedef struct {
    const char *lens_path;
    double lambda;        /* um */
    cli_size sensor;      /* mm; NAN: the lens header's */
    int as_lens;          /* print the lens in the project's format instead of keys */
    double focus;         /* refocus on an object this far (mm, or INFINITY); NAN: no */
    int seidel;           /* the paraxial ray table and Seidel sums instead of the keys */
    double seidel_field;  /* the chief ray's angle, degrees; NAN: half the field of view */
    output_cli out;       /* --json, --precision */
    lens_cli_options lens;
} info_cli;

extern const opt_command info_command;

void info_cli_default(info_cli *o);

#endif
