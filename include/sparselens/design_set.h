#ifndef SPARSELENS_DESIGN_SET_H
#define SPARSELENS_DESIGN_SET_H
/* What the designer commands (lens-fan, lens-field, lens-mtf, lens-layout) share: the
 * models (the exact lens, and a fitted system beside it or instead of it), fields,
 * wavelengths with a primary one, the sensor plane, and per model the time spent
 * imaging rays, so a system's figures come with their cost against the exact lens's. */
#include <stdio.h>

#include "sparselens/imaging_cli.h"
#include "sparselens/spot_run.h"
#include "sparselens/table_out.h"

typedef struct {
    imaging im[2];              /* models: the exact lens (or a system alone), a system */
    const char *names[2];       /* "lens", "poly" */
    int nmodels;
    const double *field;
    int nfields;
    const double *lambda;
    int nl;
    int primary;                /* index of the primary wavelength */
    focus_mode focus;           /* file, paraxial (primary wavelength) or best (least RMS
                                   spot over fields and wavelengths of the first model) */
    double sensor_shift;        /* set by design_set_focus, mm along +z */
    int focused;                /* design_set_focus has run */
    double seconds[2];          /* imaging time per model, summed by the analyses */
} design_set;

/* Moves every model's sensor plane to the focus asked for (the first model's plane for
 * all, so a system is judged where the lens is focused); once. -1 with err set. */
int design_set_focus(design_set *ds, lens_err *err);

/* The chief ray of a field at a wavelength through model m on its sensor plane; an
 * error of a system is prefixed with its name. */
int design_set_chief(const design_set *ds, int m, double field, double lambda, double s[4],
                     lens_err *err);

/* What every designer command prints after its tables: the sensor shift (when the
 * plane moved) and the time each model spent imaging `what`; text: comment lines
 * "# sensor plane moved ..." and "# time imaging WHAT: lens 0.0123 s, poly ... (x the
 * lens's)"; JSON: key tables "sensor" and "time". */
void design_set_print_footer(table_out *t, const design_set *ds, const char *what);

/* The models' largest differences: text, the line "# poly - lens: TEXT"; JSON, a key
 * table "difference" of the n keys and values. */
void design_set_print_difference(table_out *t, const design_set *ds, const char *text, int n,
                                 const char *const *keys, const double *values);

/* The field unit of the set's columns: "deg" (object at infinity) or "mm". */
const char *design_set_field_unit(const design_set *ds);

/* For the commands: loads the models imaging_cli_parse was given, parses --fields (or
 * takes the default fields) into field[IMAGING_MAX_FIELDS], fills ds and moves the sensor
 * plane (design_set_focus); the primary wavelength is the middle one. Fatal errors print
 * "prog: ..." and exit 1. */
void design_set_from_cli(const char *prog, imaging_cli *a, imaging_models *models, double *field,
                         design_set *ds);

/* What the numbers were taken with (f-number, object, sensor: imaging_cli_setup), and a
 * picture title: the lens's name (or the input's file name), what is shown, the setup. */
void design_set_title(const imaging_cli *a, const imaging_models *models, const design_set *ds,
                      const char *what, imaging_setup *setup, char *title, size_t size);

/* The end of a designer command: the setup (when the job succeeded), the end of the
 * output (valid JSON even after an error), the error on stderr; frees the models.
 * Returns the exit status. */
int design_cli_end(const char *prog, table_out *t, int rc, const lens_err *err,
                   const imaging_setup *setup, imaging_models *models);

#endif
