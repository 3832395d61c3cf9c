#ifndef SPARSELENS_LENS_IMPORT_H
#define SPARSELENS_LENS_IMPORT_H
/* Shared by the prescription readers (lens_native.c, import_*.c) and lens_load.c:
 * the readers' common signature, material look-up through glass catalogs, and
 * number formatting that reads back exactly. */
#include <stdio.h>

#include "sparselens/glass.h"
#include "sparselens/lens.h"

/* Every reader: parse f (named path in messages) into a lens that lens_finish accepted. */
typedef int (*lens_reader)(FILE *f, const char *path, const lens_load_options *opt,
                           lens_t *lens, lens_err *err);

int lens_read_fx(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                 lens_err *err);
int lens_read_pbrt(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                   lens_err *err);

/* Glass names are looked up, in order, in the catalogs of lens_load_options, then in
 * glass.catalog beside the lens file, then in glass_default_catalog_path(). The catalogs
 * are read on the first look-up only, so lenses without glass names never need one. */
typedef struct {
    const lens_load_options *opt;
    const char *lens_path;
    glass_catalog *cat;
    int loaded;
} material_ctx;

void material_ctx_init(material_ctx *m, const lens_load_options *opt, const char *lens_path);
void material_ctx_free(material_ctx *m);
/* 0: found (*g points into the catalog); 1: not found, and `searched` holds the
 * catalogs searched ("a, b", or "none found"); -1: a catalog failed to
 * load (err says where). */
int material_lookup(material_ctx *m, const char *name, const glass_t **g, const char **searched,
                    lens_err *err);

/* The shortest %g form of v that reads back to the same double; "inf"/"-inf". */
void lens_fmt_double(double v, char buf[32]);

/* Appends a line to lens->notes (written as "# note:" lines); truncates when full. */
void lens_add_note(lens_t *lens, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
