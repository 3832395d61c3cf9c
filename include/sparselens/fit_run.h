#ifndef SPARSELENS_FIT_RUN_H
#define SPARSELENS_FIT_RUN_H
/* lens-fit as a library call: the samples read as the options say (columns, tolerances,
 * frame, wavelength transform), the system fitted, and what it remembers (its lens, the
 * wavelength, its passage) recorded in it. The command opens the files and prints. */
#include <stdio.h>

#include "sparselens/fit_cli.h"
#include "sparselens/poly.h"
#include "sparselens/samples.h"

typedef struct {
    size_t samples, blocked;   /* rows read, and those of rays the lens blocks */
    int nin, nout, threads;
    double seconds;            /* the fit's wall time */
    int no_lens_path;          /* the samples name no lens file (and --lens gave none) */
    char passage_gap[256];     /* why the system's passage is partial, or "" */
} fit_run_stats;

/* Reads the samples of in (named o->samples_path in messages) and fits them. log (NULL:
 * quiet) gets the line that announces the fit and the parts' progress. Returns the
 * system, or NULL with err set. */
poly_system *fit_run(const fit_cli *o, samples_reader *in, FILE *log, fit_run_stats *st,
                     lens_err *err);

/* Position errors past this (mm, held out) are visible in a spot diagram through the
 * system: a micrometre, the corpus target for every lens (reports/realworld.md). */
#define FIT_TERM_BUDGET_MM 1e-3

/* 1, with the warning in msg, when out_x or out_y used every one of max_terms terms and
 * still misses FIT_TERM_BUDGET_MM held out: a lens the default budget does not follow. */
int fit_run_term_budget(const poly_system *sys, int max_terms, char *msg, size_t n);

/* The summary after a fit: samples, parts and time, then a line per output (its terms,
 * degree and held-out error, as the system's meta lines record them). */
void fit_run_print_summary(FILE *f, const poly_system *sys, const fit_run_stats *st);

#endif
