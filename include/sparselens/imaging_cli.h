#ifndef SPARSELENS_IMAGING_CLI_H
#define SPARSELENS_IMAGING_CLI_H
/* The command line lens-spot and lens-distort share: one LENS or SYSTEM.poly, the flags
 *   --object-distance MM  --focus file|paraxial|best  --compare SYSTEM.poly  --lens LENS
 *   --png FILE
 * and the lens-loading flags of lens_cli_options.h, as one option table (imaging_cli_table,
 * a group in each command's table); --fields and --wavelengths as lens-spot and the
 * designer commands take them (imaging_cli_field_table; lens-distort has its own); then
 * the models loaded and set up. Errors print "prog: ..." and exit 1. */
#include "sparselens/imaging.h"
#include "sparselens/lens_cli_options.h"
#include "sparselens/options.h"
#include "sparselens/spot_run.h"
#include "sparselens/table_out.h"

typedef struct {
    const char *input;          /* LENS or SYSTEM.poly */
    const char *fields;         /* --fields as given, or NULL */
    const char *wavelengths;    /* the command's default before parsing */
    const char *focus;          /* as given ("file" by default) */
    const char *compare, *lens, *png;
    double object_distance;     /* mm; INFINITY when not given */
    double fnumber;             /* --fnumber: stop the lens down to it; NAN: as it is */
    focus_mode focus_mode;
    double lambda[IMAGING_MAX_WAVELENGTHS];
    int nl;
    int primary;                /* index into lambda of the primary wavelength */
    const char *wavelengths_default; /* the command's default: not given when still it */
    lens_cli_options lopt;
} imaging_cli;

extern const opt_spec imaging_cli_table[], imaging_cli_field_table[];

/* The defaults, with the command's default wavelengths. */
void imaging_cli_default(imaging_cli *a, const char *wavelengths);

/* After opt_parse: the operands (one input), the wavelengths, focus and object distance
 * parsed and checked. */
void imaging_cli_finish(const char *prog, imaging_cli *a, const char *const *operands, int n);

/* Loads the input (and --compare, --lens) into models (without --wavelengths, the lens's
 * design file's wavelengths become lambda, its primary the primary: all of them, or the
 * primary alone for a command whose default is one), stops the lens down (--fnumber),
 * sets up im[] and names[] for the object distance, and returns the number of models, or
 * -1 with err set (models then freed). Frees the lens-loading options, which are not
 * needed after. */
int imaging_cli_models(imaging_cli *a, imaging_models *models, imaging im[2],
                       const char *names[2], lens_err *err);
/* The same for commands: fatal on a load error. */
int imaging_cli_load(const char *prog, imaging_cli *a, imaging_models *models, imaging im[2],
                     const char *names[2]);

/* What a picture title and a result must say for its numbers to be read right: the
 * f-number (paraxial, of the lens as stopped by --fnumber), the object, and where the
 * sensor is (the file's plane and the object distance it is focused on, or the paraxial
 * or best focus and how far it moved). */
typedef struct {
    double fnumber;
    double file_focus_distance; /* mm in front of the first surface the file's sensor is
                                   focused on; INFINITY */
    char text[256];             /* "f/1.75, object at infinity, sensor as in the file
                                   (focused at 77.2 mm)" */
} imaging_setup;
void imaging_cli_setup(const imaging_cli *a, const imaging_models *m, double lambda,
                       double sensor_shift, imaging_setup *s);
/* The setup as a key table "setup" (JSON), or as one comment line (text). */
void imaging_setup_print(table_out *t, const imaging_setup *s, const imaging_models *m);

/* The input's file name without its directories, for picture titles. */
const char *imaging_cli_basename(const imaging_cli *a);

/* A warning (into *w, returns 1; else 0) when the system shown or compared was fitted to
 * another lens than the one loaded: neither its recorded lens name nor its lens file's
 * base name is the lens's name or file's base name (a system fitted with no name known,
 * "unknown", is not questioned). */
int imaging_cli_model_warning(const imaging_models *m, report_warning *w);

/* Ends a spot, distortion or designer table: each warning (a field a model cannot image) goes to
 * `log` as "prog: warning: ..." and into the table's end (JSON carries them too). */
void imaging_cli_end_table(table_out *t, FILE *log, const char *prog,
                           report_warning *warnings, int nwarnings);

#endif
