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

#endif
