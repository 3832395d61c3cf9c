#ifndef SPARSELENS_EMIT_FILES_H
#define SPARSELENS_EMIT_FILES_H
/* A generated C file and its header, written as one output: X.c and X.h beside it (a
 * path not ending in ".c" gets ".h" added), both complete or neither. Standard output
 * ("-") gets the C file alone. */
#include <stdio.h>

#include "sparselens/diag.h"
#include "sparselens/poly.h"

/* Writes the C file by body(f, ctx) and the header by header(f, ctx); each returns 0 or
 * -1 (err set, or a write error on f). 0, or -1 with err and nothing left behind. */
int emit_c_files(const char *path, int (*body)(FILE *f, void *ctx, lens_err *err),
                 int (*header)(FILE *f, void *ctx, lens_err *err), void *ctx, lens_err *err);

/* A system as C (poly_emit_c) into path, and its header (poly_emit_c_header). */
int emit_poly_c_files(const poly_system *sys, const char *path, const char *name,
                      lens_err *err);

/* The header's path for a C file's (as above) into buf; -1 when it does not fit. */
int emit_header_path(const char *path, char *buf, size_t len);

#endif
