#ifndef SPARSELENS_EVAL_CLI_H
#define SPARSELENS_EVAL_CLI_H
/* lens-eval's options: its option table (options.h) and the struct it fills. */
#include "sparselens/eval_run.h"
#include "sparselens/options.h"
#include "sparselens/output_cli.h"

typedef struct {
    const char *system;   /* SYSTEM.poly */
    const char *input;    /* the sample file ("-": standard input) */
    const char *output;   /* "-": standard output */
    int emit_c;           /* write the system as C instead of reading rays */
    const char *name;     /* the C function's name */
    eval_run_options run;
    output_cli out;       /* --json, --precision (of the report) */
} eval_cli;

extern const opt_command eval_command;

void eval_cli_default(eval_cli *o);

/* The whole of lens-eval (src/app/eval_job.c): reads o->system, then writes it as C
 * (o->emit_c) or evaluates the rays of o->input ("-": standard input) into o->output,
 * which is written whole or not at all. log (may be NULL) gets the line that counts the
 * rays outside the training domain. 0, or -1 with err set; bad rows are counted in st
 * (and passed to o->run.on_bad_row), not errors. */
int eval_cli_run(const eval_cli *o, FILE *log, eval_run_stats *st, lens_err *err);

#endif
