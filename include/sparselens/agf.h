#ifndef SPARSELENS_AGF_H
#define SPARSELENS_AGF_H
/* Zemax AGF glass catalogs (see lens-import(5)): NM (name, formula, n_d, V_d),
 * CD (dispersion coefficients, in the file's order, into glass_t.coef), LD (valid
 * wavelength range, um). Other records (thermal, transmission, comments) are skipped:
 * they do not change the index at 20 C. Each glass read is handed to add(); a non-zero
 * return from add stops the reading with that error. Both UTF-16 (with BOM) and 8-bit
 * files are read. */
#include <stddef.h>

#include "sparselens/diag.h"
#include "sparselens/glass.h"

typedef int (*agf_add_fn)(void *ctx, const glass_t *g, lens_err *err);

int agf_parse(const char *data, size_t len, const char *path, agf_add_fn add, void *ctx,
              lens_err *err);
int agf_read(const char *path, agf_add_fn add, void *ctx, lens_err *err);

/* 1 when path names an AGF catalog: extension .agf (any case). */
int agf_is_agf_path(const char *path);

#endif
