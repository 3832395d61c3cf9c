#ifndef SPARSELENS_SPOT_CLI_H
#define SPARSELENS_SPOT_CLI_H
/* lens-spot's options: its option table (options.h) and the struct it fills. */
#include "sparselens/imaging_cli.h"
#include "sparselens/options.h"
#include "sparselens/output_cli.h"
#include "sparselens/spot.h"

typedef struct {
    imaging_cli im;          /* the flags lens-spot shares with lens-distort */
    pupil_pattern pattern;
    long rays;
    unsigned long long seed;
    const char *png, *exr;
    output_cli out;          /* --json, --precision */
} spot_cli;

extern const opt_command spot_command;

void spot_cli_default(spot_cli *o);

/* The whole of lens-spot (src/app/spot_job.c): the report (text or JSON) to out, the
 * pictures to their files; a picture that cannot be written and a field a model cannot
 * image are reported on log as "prog: ..." lines. Returns 0; 1 when a picture could not
 * be written; 2 when a field was not imaged; -1 with err set when nothing could be
 * computed (nothing written). */
int spot_cli_run(spot_cli *o, FILE *out, FILE *log, const char *prog, lens_err *err);

#endif
