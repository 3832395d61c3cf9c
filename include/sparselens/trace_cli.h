#ifndef SPARSELENS_TRACE_CLI_H
#define SPARSELENS_TRACE_CLI_H
/* lens-trace's options: its option table (options.h) and the struct it fills. */
#include "sparselens/cli.h"
#include "sparselens/lens_cli_options.h"
#include "sparselens/options.h"
#include "sparselens/sampling.h"
#include "sparselens/trace.h"

typedef struct {
    const char *lens_path, *out_path;
    int from_stdin;           /* trace the rays on standard input ("-") */
    long count;
    unsigned long seed;
    sampling_strategy strategy;
    double lambda[2];         /* um: uniform in [0]..[1] */
    cli_size sensor;          /* mm; NAN: the lens header's */
    trace_target target;
    int all, threads, quiet;
    int passing_only;         /* --passing-only (--all is the default) */
    int stop_columns, clip_columns, no_passage_columns;
    const char *clip_list;    /* --clip-surfaces, or NULL */
    double fnumber;           /* --fnumber: stop the lens down to it; NAN: as it is */
    lens_cli_options lens;
} trace_cli;

extern const opt_command trace_command;

void trace_cli_default(trace_cli *o);

#endif
