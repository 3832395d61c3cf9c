#ifndef SPARSELENS_TRACE_RUN_H
#define SPARSELENS_TRACE_RUN_H
/* lens-trace as a library call: generate and trace rays, or trace the rays of a sample
 * stream, into a sample file (lens-samples(5)). The command opens the files and prints. */
#include <stdio.h>

#include "sparselens/samples.h"
#include "sparselens/trace_cli.h"

typedef struct {
    /* A bad input row of a stream (FILE:LINE in err): its output row is nan. */
    void (*on_bad_row)(void *ctx, const lens_err *err);
    /* Generation: rays written of total, and traced, after each chunk. */
    void (*progress)(void *ctx, long written, long total, long traced);
    void *ctx;
} trace_run_hooks;

/* Writes to out the sample file o asks for, from the lens (loaded; o->lens_path names it
 * in the file): o->count generated rays, or, with o->from_stdin, one row per row of in
 * (x y u v lambda found by name; other columns passed through). hooks may be NULL.
 * *bad_rows gets the number of bad input rows (each written as nan). 0 on success;
 * -1 with err set, out then holds a partial file for the caller to discard. */
int trace_run(const trace_cli *o, const lens_t *lens, samples_reader *in, FILE *out,
              const trace_run_hooks *hooks, long *bad_rows, lens_err *err);

/* The wavelength band lens-trace draws from without --lambda: 0.4..0.7 um widened to
 * hold the design file's wavelengths, and narrowed to where every glass has data (but
 * never past the file's wavelengths). */
void trace_default_band(const lens_t *lens, double *lo, double *hi);

#endif
