#ifndef SPARSELENS_EVAL_RUN_H
#define SPARSELENS_EVAL_RUN_H
/* The job of lens-eval as a library call: stream a sample file through a polynomial
 * system, writing predictions (a sample file) or the fitting-error report. */
#include <stddef.h>
#include <stdio.h>

#include "sparselens/eval_report.h"
#include "sparselens/poly.h"
#include "sparselens/samples.h"

typedef struct {
    int report; /* write the report (needs reference columns named as the outputs) */
    int raw;    /* predictions: the polynomial values also for rays the system blocks
                   (otherwise those rows get nan, and out_eta 0) */
    eval_report_options ropt;
    int json;       /* the report as JSON (table_out.h) */
    int precision;  /* the report's digits; 0: 6 */
    /* Called for each malformed row (FILE:LINE in err); its output row is nan. */
    void (*on_bad_row)(void *ctx, const lens_err *err);
    void *ctx;
} eval_run_options;

void eval_run_options_default(eval_run_options *opt);

typedef struct {
    size_t rows, bad_rows;
    size_t outside;           /* rows with an input outside the training domain */
    size_t outside_input[64]; /* per system input (the first 64) */
    /* With the report (the lens's reference known): of those rows, the ones the lens
     * passes, whose extrapolated values reach the picture; the rest only need blocking */
    int lens_known;
    size_t outside_passing, outside_passing_input[64];
    /* A system fitted at one wavelength (lambda not among its inputs, "meta lambda L"):
     * the rows whose lambda column holds another one, evaluated as at L all the same */
    double lambda;        /* L, or NAN */
    size_t other_lambda;
} eval_run_stats;

/* 0 on success (bad rows are counted, not fatal); -1 with err set when the inputs'
 * columns are missing, a report lacks reference columns, or writing fails. */
int eval_run(const poly_system *sys, samples_reader *in, FILE *out, const eval_run_options *opt,
             eval_run_stats *stats, lens_err *err);

#endif
