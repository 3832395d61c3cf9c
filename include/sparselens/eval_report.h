#ifndef SPARSELENS_EVAL_REPORT_H
#define SPARSELENS_EVAL_REPORT_H
/* The fitting-error report of lens-eval --report (man 1 lens-eval): how far a
 * polynomial system's predictions are from the exact (traced) outputs.
 *
 * Errors are absolute differences |predicted - reference| over the rays both the lens
 * and the system let through. Per output: rms, mean, p99 (nearest rank: the
 * ceil(0.99 n)-th smallest) and max, in the output's unit: mm for positions (names
 * ending in x or y), 1 for direction components (ending in u or v) and for out_eta.
 * Direction components get a second row in arcminutes: the angle between the
 * reference direction and the one with only this component predicted. Then the same
 * by sensor radius bins, then the passage counts. */
#include <stdio.h>

#include "sparselens/poly.h"
#include "sparselens/table_out.h"

typedef enum {
    EVAL_DIR_UNIT,  /* (u, v) are components of a unit vector (outer-pupil frame) */
    EVAL_DIR_SLOPE, /* the direction is proportional to (u, v, 1) (sensor, stop) */
} eval_dir_kind;

typedef struct {
    int nbins;          /* sensor radius bins (default 8) */
    double rmax;        /* outer edge of the last bin; <= 0: the largest radius seen */
    eval_dir_kind dirs; /* how to turn (u, v) into an angle */
} eval_report_options;

void eval_report_options_default(eval_report_options *opt);

typedef struct eval_report eval_report;

eval_report *eval_report_new(const poly_system *sys, const eval_report_options *opt);
/* One ray: in[ninputs], the prediction pred[noutputs] with the system's pass flag, the
 * reference ref[noutputs] with the lens's. */
int eval_report_add(eval_report *r, const double *in, const double *pred, int sys_pass,
                    const double *ref, int lens_pass);
/* The rays outside the training domain and those of them the lens passes, as the caller
 * counted them (eval_run, which counts them for its stderr line): the passage keys
 * outside_domain and outside_domain_lens_passes; 0 unless set. */
void eval_report_set_outside(eval_report *r, size_t outside, size_t lens_passes);
/* The report as tables (table_out.h; man lens-eval, THE REPORT): "error" (a row per
 * output and unit, keyed out_x_mm, out_u, out_u_arcmin, ...), "error_by_radius",
 * "part_jumps" (systems with parts), "passage" (key-value) and "passage_by_ring". */
int eval_report_print(table_out *t, const eval_report *r);
/* The same as text to f, 6 digits. */
int eval_report_write(FILE *f, const eval_report *r);
void eval_report_free(eval_report *r);

/* Whether the lens passes a ray by its reference outputs: all finite, and out_eta (if
 * the system has that output) > 0. */
int eval_reference_passes(const poly_system *sys, const double *ref);

#endif
