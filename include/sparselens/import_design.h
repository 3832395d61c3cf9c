#ifndef SPARSELENS_IMPORT_DESIGN_H
#define SPARSELENS_IMPORT_DESIGN_H
/* Importers, one header per family (the rule): import_design.h for the files of lens
 * design programs, import_table.h for the prescription tables of lens sets; the one
 * entry point every command uses is lens_load() (lens.h), and the machinery the readers
 * share stays inside src/lens/ (lens/lens_material.h: glass look-up and notes, for every
 * reader; lens/import_common.h: decoding, tokens and systems, for design files).
 *
 * This family: prescriptions written by lens design programs, Zemax OpticStudio .zmx
 * and CODE V .seq (see lens-import(5) for the subset read).
 *
 * Both give a lens_t in millimetres whatever the file's units. What sparselens does
 * not model but does not change the first-order optics (coatings, tolerances, solves,
 * fields, display settings) is listed in lens->notes ("skipped: ..."); the commands
 * print those notes as a warning. What the optics depend on (mirrors, coordinate
 * breaks, decentres, tilts, unsupported surface types) is refused with a message
 * naming the surface and the reason. Glass names are looked up in opt->catalogs first,
 * then in the shipped catalog; opt->ndvd_fallback lets a glass the file gives with
 * n_d and V_d fall back to the nd/Vd model. */
#include <stddef.h>
#include <stdio.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"

/* lens_load()'s readers: the whole stream f, named path. */
int lens_read_zmx(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                  lens_err *err);
int lens_read_seq(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                  lens_err *err);

/* The same from a buffer already in memory (any of the encodings the files use);
 * path is used only in messages. For fuzzing and tests. */
int lens_parse_zmx(const char *data, size_t len, const char *path,
                   const lens_load_options *opt, lens_t *lens, lens_err *err);
int lens_parse_seq(const char *data, size_t len, const char *path,
                   const lens_load_options *opt, lens_t *lens, lens_err *err);

#endif
