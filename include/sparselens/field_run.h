#ifndef SPARSELENS_FIELD_RUN_H
#define SPARSELENS_FIELD_RUN_H
/* lens-field as a library call: field curves (tangential and sagittal focus against
 * field), distortion and lateral colour against field, or the chromatic focal shift
 * against wavelength, for every model, with the models' difference and times. */
#include <stdio.h>

#include "sparselens/design_set.h"
#include "sparselens/field_curves.h"

typedef struct {
    design_set set;
    double delta;        /* close-ray separation, fraction of the stop radius */
    int focal_shift;     /* > 1: the focal shift at this many wavelengths across the
                            set's range instead of the field curves */
    const char *png;
    const char *title;
} field_request;

/* rows (may be NULL) receives the field rows [(m * nfields + f) * nl + l] (freed by the
 * caller with free) when the field curves were asked for. */
int field_run(field_request *rq, table_out *out, field_row **rows, lens_err *err);

/* Focal shift of one model: the axial close-ray focus (field 0, the sagittal pair) at
 * each of n wavelengths, minus that at ref_lambda, in mm along +z. */
int field_focal_shift(const imaging *im, const double *lambda, int n, double ref_lambda,
                      double delta, double *shift, double *seconds, lens_err *err);

#endif
