#ifndef SPARSELENS_DESIGN_SET_H
#define SPARSELENS_DESIGN_SET_H
/* What the designer commands (lens-fan, lens-field, lens-mtf, lens-layout) share: the
 * models (the exact lens, and a fitted system beside it or instead of it), fields,
 * wavelengths with a primary one, the sensor plane, and per model the time spent
 * imaging rays, so a system's figures come with their cost against the exact lens's. */
#include <stdio.h>

#include "sparselens/imaging_cli.h"
#include "sparselens/output_cli.h"
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
    /* fields a model cannot image (design_set_imaged): one line each, "MODEL: WHY; TAIL" */
    report_warning warning[2 * IMAGING_MAX_FIELDS];
    int nwarnings;
} design_set;

/* Moves every model's sensor plane to the focus asked for (the first model's plane for
 * all, so a system is judged where the lens is focused); once. -1 with err set. */
int design_set_focus(design_set *ds, lens_err *err);

/* The chief ray of a field at a wavelength through model m on its sensor plane; an
 * error of a system is prefixed with its name. 1 when no chief ray reaches the sensor,
 * -1 on other errors (err set both times). */
int design_set_chief(const design_set *ds, int m, double field, double lambda, double s[4],
                     lens_err *err);

/* Whether model m images field f: its chief ray reaches the sensor at every wavelength
 * of the set (all_lambda) or at the primary one. 0 when it does; 1 when it does not,
 * with a warning "MODEL: field F deg: ...; TAIL" added to the set (the command then
 * keeps the field's rows as nan and exits 2: design_run_end); -1 with err set on other
 * errors. */
int design_set_imaged(design_set *ds, int m, int f, int all_lambda, const char *tail, lens_err *err);

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

/* A designer command's run around its job (cmd/lens-fan.c and the like): the models,
 * fields, setup and picture title it works with, and the output table. */
typedef struct {
    imaging_models models;
    double field[IMAGING_MAX_FIELDS];
    imaging_setup setup;        /* what the numbers were taken with (imaging_cli_setup) */
    char title[512];            /* the lens's name (or the input's), WHAT, the setup */
    table_out t;
    design_set *set;            /* the job's set, for its warnings */
    const char *written[2];     /* the pictures the job writes (--png, --svg), or NULL */
} design_run;

/* Loads the models of a, takes the fields of --fields, or without it the default fields
 * (imaging_default_fields; with spread > 0, spread fields evenly from 0 to the largest
 * of them), fills set (the middle wavelength primary), moves the sensor plane
 * (design_set_focus), makes the title for `what` and begins the output (--json,
 * --precision, 6 digits by default). Fatal errors print "prog: ..." and exit 1. */
void design_run_begin(const char *prog, design_run *r, imaging_cli *a, const output_cli *out,
                      int spread, const char *what, design_set *set);

/* The end of a designer command whose job returned rc: the setup (when the job
 * succeeded), the set's warnings ("prog: warning: ..." on stderr, and the JSON's
 * "warnings"), the end of the output (valid JSON even after an error), the error on
 * stderr; frees the models. Returns the exit status: 1 after an error (standard output
 * that cannot be written too: the pictures written are then removed, cli_end_stdout),
 * 2 when a model could not image a field, else 0. */
int design_run_end(const char *prog, design_run *r, int rc, const lens_err *err);

#endif
