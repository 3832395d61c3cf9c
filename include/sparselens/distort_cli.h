#ifndef SPARSELENS_DISTORT_CLI_H
#define SPARSELENS_DISTORT_CLI_H
/* lens-distort's options: its option table (options.h) and the struct it fills. */
#include "sparselens/cli.h"
#include "sparselens/imaging_cli.h"
#include "sparselens/options.h"
#include "sparselens/output_cli.h"

typedef struct {
    imaging_cli im;         /* the flags lens-distort shares with lens-spot */
    int illum_rays, grid;
    int mapping;            /* proj_kind, or -1: the one the lens follows best */
    cli_size sensor;        /* mm; NAN: the lens header's */
    double exaggerate;      /* NAN: automatic */
    const char *map, *png;
    cli_size opencv;        /* pixels; 0: no OpenCV fits */
    output_cli out;         /* --json, --precision */
} distort_cli;

extern const opt_command distort_command;

void distort_cli_default(distort_cli *o);

#endif
