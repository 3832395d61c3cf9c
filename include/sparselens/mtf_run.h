#ifndef SPARSELENS_MTF_RUN_H
#define SPARSELENS_MTF_RUN_H
/* lens-mtf as a library call: diffraction and geometric MTF, tangential and sagittal,
 * per model, field and wavelength (and all wavelengths together), from 0 to the
 * sensor's Nyquist frequency; or through focus at one frequency. */
#include <stdio.h>

#include "sparselens/design_set.h"
#include "sparselens/mtf.h"

typedef struct {
    design_set set;
    int grid;                    /* pupil cells across */
    wavefront_method lens_method; /* the exact lens's wavefront: PATH (default) or RAYS */
    double pixel_um;             /* pixel pitch: Nyquist = 1000 / (2 pixel_um) cycles/mm */
    int steps;                   /* frequencies 0 .. Nyquist in `steps` intervals */
    double focus_freq;           /* > 0: through-focus MTF at this frequency instead */
    double focus_range;          /* mm either side of the sensor plane */
    int focus_steps;             /* planes across the range, odd so the plane itself is one */
    const char *png;
    const char *title;
} mtf_request;

/* rows (may be NULL) receives the rows (caller frees) and *nrows their count. */
int mtf_run(mtf_request *rq, table_out *out, mtf_row **rows, size_t *nrows, lens_err *err);

#endif
