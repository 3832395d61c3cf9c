#ifndef SPARSELENS_DESIGN_CLI_H
#define SPARSELENS_DESIGN_CLI_H
/* The options of the designer commands (lens-fan, lens-field, lens-mtf, lens-layout):
 * their option tables (options.h) and the structs they fill. Each shares the flags of
 * imaging_cli.h (with --fields and --wavelengths as lens-spot has them) and --png through
 * design_cli_table. */
#include "sparselens/imaging_cli.h"
#include "sparselens/options.h"
#include "sparselens/output_cli.h"
#include "sparselens/wavefront.h"

extern const opt_spec design_cli_table[]; /* for an imaging_cli */

typedef struct {
    imaging_cli im;
    long points;
    output_cli out;         /* --json, --precision */
} fan_cli;

typedef struct {
    imaging_cli im;
    double delta;
    long focal_shift;
    output_cli out;         /* --json, --precision */
} field_cli;

typedef struct {
    imaging_cli im;
    double pixel_um, through_focus, focus_range;
    long steps, grid, focus_steps;
    int wavefront;          /* wavefront_method */
    output_cli out;         /* --json, --precision */
} mtf_cli;

typedef struct {
    imaging_cli im;
    long rays;
    int full_stop;
    const char *svg;
    int width;
    output_cli out;         /* --json, --precision */
} layout_cli;

extern const opt_command fan_command, field_command, mtf_command, layout_command;

void fan_cli_default(fan_cli *o);
void field_cli_default(field_cli *o);
void mtf_cli_default(mtf_cli *o);
void layout_cli_default(layout_cli *o);

#endif
