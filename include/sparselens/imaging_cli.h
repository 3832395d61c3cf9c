#ifndef SPARSELENS_IMAGING_CLI_H
#define SPARSELENS_IMAGING_CLI_H
/* The command line lens-spot and lens-distort share: one LENS or SYSTEM.poly, the flags
 *   --fields LIST  --object-distance MM  --wavelengths LIST  --focus file|paraxial|best
 *   --compare SYSTEM.poly  --lens LENS  --png FILE
 * and the lens-loading flags of lens_cli_options.h; then the models loaded and set up.
 * Each command adds its own flags through a callback, so both spell, check and report
 * the shared ones the same way. Errors print "prog: ..." and exit 1. */
#include "sparselens/imaging.h"
#include "sparselens/lens_cli_options.h"
#include "sparselens/spot_run.h"

typedef struct {
    const char *input;          /* LENS or SYSTEM.poly */
    const char *fields;         /* --fields as given, or NULL */
    const char *wavelengths;    /* set the command's default before parsing */
    const char *focus;          /* as given ("file" by default) */
    const char *compare, *lens, *png;
    double object_distance;     /* mm; INFINITY when not given */
    focus_mode focus_mode;
    double lambda[IMAGING_MAX_WAVELENGTHS];
    int nl;
    lens_cli_options lopt;
} imaging_cli;

/* The command's own flags: returns 1 when argv[*i] was one (consumed, *i advanced past its
 * value, as cli_opt does), 0 when not. */
typedef int (*imaging_cli_flag)(const char *prog, int argc, char **argv, int *i, void *ctx);

/* Parses argv: --help prints usage, own() is asked about every flag that is not shared,
 * an unknown flag or a second input is fatal. On return the wavelengths, focus and
 * object distance are parsed and checked. a->wavelengths holds the default on entry. */
void imaging_cli_parse(const char *prog, const char *usage, int argc, char **argv,
                       imaging_cli *a, imaging_cli_flag own, void *ctx);

/* Loads the input (and --compare, --lens) into models, sets up im[] and names[] for the
 * object distance, and returns the number of models; fatal on a load error. Frees the
 * lens-loading options, which are not needed after. */
int imaging_cli_load(const char *prog, imaging_cli *a, imaging_models *models, imaging im[2],
                     const char *names[2]);

/* The input's file name without its directories, for picture titles. */
const char *imaging_cli_basename(const imaging_cli *a);

#endif
