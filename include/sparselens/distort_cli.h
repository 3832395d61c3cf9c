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

/* The whole of lens-distort (src/app/distort_job.c): the report (text or JSON) to out, the
 * map and the grid picture to their files; a file that cannot be written and a field a
 * model cannot image are reported on log as "prog: ..." lines. Returns 0; 1 when a file
 * could not be written; 2 when a field was not imaged; -1 with err set when nothing could
 * be computed (nothing written). */
int distort_cli_run(distort_cli *o, FILE *out, FILE *log, const char *prog, lens_err *err);

#endif
