#ifndef SPARSELENS_IMPORT_TABLE_H
#define SPARSELENS_IMPORT_TABLE_H
/* Importers of the prescription tables of lens sets: the .fx files of the 2016 lens set
 * and pbrt's .dat files (lens-import(5)). One header per importer family; see
 * import_design.h for the rule. Each reads the whole stream f (named path in messages)
 * into a lens that lens_finish accepted: 0, or -1 with err set. */
#include <stdio.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"

int lens_read_fx(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                 lens_err *err);
int lens_read_pbrt(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                   lens_err *err);

#endif
