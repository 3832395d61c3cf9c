#ifndef SPARSELENS_IMAGING_CLI_H
#define SPARSELENS_IMAGING_CLI_H
/* The command line lens-spot and lens-distort share: one LENS or SYSTEM.poly, the flags
 *   --object-distance MM  --focus file|paraxial|best  --compare SYSTEM.poly  --lens LENS
 *   --png FILE
 * and the lens-loading flags of lens_cli_options.h, as one option table (imaging_cli_table,
 * a group in each command's table; --fields and --wavelengths, whose defaults differ, are
 * in the commands' own tables); then the models loaded and set up. Errors print
 * "prog: ..." and exit 1. */
#include "sparselens/imaging.h"
#include "sparselens/lens_cli_options.h"
#include "sparselens/options.h"
#include "sparselens/spot_run.h"

typedef struct {
    const char *input;          /* LENS or SYSTEM.poly */
    const char *fields;         /* --fields as given, or NULL */
    const char *wavelengths;    /* the command's default before parsing */
    const char *focus;          /* as given ("file" by default) */
    const char *compare, *lens, *png;
    double object_distance;     /* mm; INFINITY when not given */
    focus_mode focus_mode;
    double lambda[IMAGING_MAX_WAVELENGTHS];
    int nl;
    lens_cli_options lopt;
} imaging_cli;

extern const opt_spec imaging_cli_table[];

/* The defaults, with the command's default wavelengths. */
void imaging_cli_default(imaging_cli *a, const char *wavelengths);

/* After opt_parse: the operands (one input), the wavelengths, focus and object distance
 * parsed and checked. */
void imaging_cli_finish(const char *prog, imaging_cli *a, const char *const *operands, int n);

/* Loads the input (and --compare, --lens) into models, sets up im[] and names[] for the
 * object distance, and returns the number of models; fatal on a load error. Frees the
 * lens-loading options, which are not needed after. */
int imaging_cli_load(const char *prog, imaging_cli *a, imaging_models *models, imaging im[2],
                     const char *names[2]);

/* The input's file name without its directories, for picture titles. */
const char *imaging_cli_basename(const imaging_cli *a);

#endif
