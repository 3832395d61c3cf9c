#ifndef SPARSELENS_FIT_CLI_H
#define SPARSELENS_FIT_CLI_H
/* lens-fit's options: its option table (options.h) and the struct it fills. */
#include "sparselens/fit.h"
#include "sparselens/options.h"

typedef struct {
    const char *samples_path;  /* "-": standard input */
    const char *out_path;      /* "-": standard output */
    const char *inputs;        /* comma-separated column names */
    const char *outputs;       /* NULL: the default outputs and the samples' clip pairs */
    const char *tolerance;     /* T, or name=T,...; NULL: off */
    const char *frame;         /* auto, none or meridional */
    const char *frame_except;  /* outputs fitted outside the frame */
    const char *lambda_transform; /* auto, identity or inverse-square */
    const char *lens;          /* lens name recorded; NULL: the samples' base name */
    int emit_c;                /* write C code instead of the system */
    const char *name;          /* the C function's name */
    int quiet;
    int keep_circles;          /* --keep-circles: fit.drop_circles off */
    fit_options fit;
} fit_cli;

extern const opt_command fit_command;

void fit_cli_default(fit_cli *o);

#endif
