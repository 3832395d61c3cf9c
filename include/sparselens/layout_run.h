#ifndef SPARSELENS_LAYOUT_RUN_H
#define SPARSELENS_LAYOUT_RUN_H
/* lens-layout as a library call: the surfaces as a table, the drawing's rays counted,
 * a system's rays beside the lens's (their largest distance on the sensor and the
 * time), and the pictures. */
#include <stdio.h>

#include "sparselens/design_set.h"
#include "sparselens/layout.h"

typedef struct {
    design_set set;
    int rays;            /* per field */
    int full_stop;       /* rays over the whole stop, not only its passing part */
    const char *png, *svg;
    int width;           /* PNG pixels */
    const char *title;
} layout_request;

int layout_run(layout_request *rq, table_out *out, lens_err *err);

#endif
