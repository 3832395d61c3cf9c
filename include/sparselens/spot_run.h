#ifndef SPARSELENS_SPOT_RUN_H
#define SPARSELENS_SPOT_RUN_H
/* lens-spot as a library call (the command only parses arguments and prints). */
#include <stdio.h>

#include "sparselens/spot.h"
#include "sparselens/table_out.h"

typedef enum { FOCUS_FILE, FOCUS_PARAXIAL, FOCUS_BEST } focus_mode;

/* "file", "paraxial" or "best" (the --focus values of lens-spot and lens-distort);
 * -1 for anything else. */
int focus_mode_parse(const char *s, focus_mode *mode);

typedef struct {
    imaging im[2];              /* the models: the exact lens, and optionally a system */
    const char *model_names[2]; /* "lens", "poly" */
    int nmodels;
    const double *field;
    int nfields;
    const double *lambda;
    int nl;
    int primary;                /* index of the primary wavelength (paraxial focus, chief ray
                                   of the pooled spot, Airy disc) */
    focus_mode focus;           /* file: the lens's sensor plane; paraxial: its paraxial focus
                                   at the primary wavelength; best: the plane of least summed
                                   RMS spot radius over fields and wavelengths (of the first
                                   model; every model is shown on that plane) */
    pupil_pattern pattern;
    size_t rays;
    unsigned long long seed;
} spot_request;

typedef struct {
    int nmodels, nfields, nl;
    spot *spots;   /* (m * nfields + f) * nl + l */
    spot *pooled;  /* m * nfields + f: all wavelengths of a field */
    double sensor_shift; /* mm along +z from the file's sensor plane */
    /* Fields a model cannot image (no chief ray reaches the sensor, e.g. 98 degrees
     * through a fisheye's system): their rows are nan; why[m * nfields + f] says why,
     * empty for the fields imaged. */
    int not_imaged;
    lens_err *why;
} spot_report;

int spot_run(const spot_request *rq, spot_report *rep, lens_err *err);
/* lens-spot's and lens-distort's runs: an error of model m > 0 (a fitted system beside
 * the lens) is prefixed with its name ("poly: ..."); the lens's own (m 0) is left as is. */
void run_error_model(lens_err *err, int m, const char *name);
void spot_report_free(spot_report *rep);
/* "MODEL: why; its rows are nan" for each field not imaged, at most max of them, into
 * w[]; returns how many. */
/* a warning quotes at most 480 bytes of a field's failure (which names no path) */
typedef char report_warning[640];
int spot_report_warnings(const spot_request *rq, const spot_report *rep, report_warning *w, int max);
/* The table "spots" (text: header line, then a row per model, field and wavelength, and a
 * row "all" per field, the pooled wavelengths, when there are several), and how the
 * sensor plane was placed (text: a comment when it moved; JSON: "sensor"). */
void spot_report_print(table_out *t, const spot_request *rq, const spot_report *rep,
                       const char *focus_name);

#endif
