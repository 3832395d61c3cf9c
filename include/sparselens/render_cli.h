#ifndef SPARSELENS_RENDER_CLI_H
#define SPARSELENS_RENDER_CLI_H
/* lens-render's options: its option table (options.h) and the struct it fills. */
#include "sparselens/lens_cli_options.h"
#include "sparselens/options.h"
#include "sparselens/render_run.h"

typedef struct {
    render_options run;
    int quiet;
    lens_cli_options lens;
} render_cli;

extern const opt_command render_command;

void render_cli_default(render_cli *o);

#endif
