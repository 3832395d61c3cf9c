#ifndef SPARSELENS_FAN_RUN_H
#define SPARSELENS_FAN_RUN_H
/* lens-fan as a library call: ray fans of every model, field and wavelength, printed as
 * a table, the models' difference and times, and optionally a picture. */
#include <stdio.h>

#include "sparselens/design_set.h"
#include "sparselens/ray_fan.h"

typedef struct {
    design_set set;
    int npts;           /* points per fan */
    const char *png;    /* picture, or NULL */
    const char *title;
} fan_request;

/* Errors of each fan are measured from its model's chief ray of the primary wavelength.
 * fans (may be NULL) receives the fans, [(m * nfields + f) * nl + l], for the caller
 * to free with fan_results_free; otherwise they are freed here. */
int fan_run(fan_request *rq, table_out *out, ray_fan **fans, lens_err *err);
void fan_results_free(ray_fan *fans, size_t n);

#endif
