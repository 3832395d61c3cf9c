#ifndef SPARSELENS_POLY_H
#define SPARSELENS_POLY_H
/* Adaptive sparse polynomial systems (man 5 lens-poly): per output a sparse polynomial
 * in scaled inputs, optionally one system per part of a partition of the ray space.
 * This header is the interface other modules (spot, distort, render) rely on. */
#include <stddef.h>
#include <stdio.h>

#include "diag.h"

typedef struct poly_system poly_system;

int poly_read(const char *path, poly_system **sys, lens_err *err);
int poly_write(FILE *f, const poly_system *sys);
void poly_free(poly_system *sys);

const char *poly_lens_name(const poly_system *sys); /* the lens it was fitted to */
const char *poly_lens_path(const poly_system *sys); /* as recorded, may be "" */
int poly_ninputs(const poly_system *sys);
int poly_noutputs(const poly_system *sys);
const char *poly_input_name(const poly_system *sys, int i);
const char *poly_output_name(const poly_system *sys, int i);
int poly_input_index(const poly_system *sys, const char *name);  /* -1 if absent */
int poly_output_index(const poly_system *sys, const char *name); /* -1 if absent */

/* Evaluates all outputs at in[ninputs] (the system's input order, unscaled units).
 * Returns 1 if the system says the ray passes the lens, 0 if not (out still filled). */
int poly_eval(const poly_system *sys, const double *in, double *out);
/* Outputs and their partial derivatives: jac[o * ninputs + i] = d out_o / d in_i. */
int poly_eval_jacobian(const poly_system *sys, const double *in, double *out, double *jac);
/* count rays; in row-major count x ninputs, out count x noutputs; pass may be NULL. */
void poly_eval_batch(const poly_system *sys, size_t count, const double *in, double *out,
                     unsigned char *pass);
/* 1 when in lies inside the input ranges seen in training (extrapolation check). */
int poly_in_domain(const poly_system *sys, const double *in);

#endif
