#ifndef SPARSELENS_LENS_MATERIAL_H
#define SPARSELENS_LENS_MATERIAL_H
/* Inside the lens stage: what every prescription reader (lens_native.c, import_*.c)
 * shares: material look-up through glass catalogs, notes, and number formatting that
 * reads back exactly (lens_material.c). */
#include <stdio.h>

#include "sparselens/glass.h"
#include "sparselens/lens.h"

/* Glass names are looked up, in order, in the catalogs of lens_load_options, then in
 * glass.catalog beside the lens file, then in glass_default_catalog_path(). The catalogs
 * are read on the first look-up only, so lenses without glass names never need one. */
typedef struct {
    const lens_load_options *opt;
    const char *lens_path;
    glass_catalog *cat;
    size_t shipped_from; /* index of the first glass of the shipped catalog */
    int loaded;
    glass_catalog *own;  /* the lens file's own glasses ("# glass:" lines), searched first */
} material_ctx;

/* A glass the lens file defines itself; 0, or -1 with err set. */
int material_add_own(material_ctx *m, const glass_t *g, lens_err *err);

void material_ctx_init(material_ctx *m, const lens_load_options *opt, const char *lens_path);
void material_ctx_free(material_ctx *m);
/* 0: found (*g points into the catalog); 1: not found, and `searched` holds the
 * catalogs searched ("a, b", or "none found"); -1: a catalog failed to
 * load (err says where). */
int material_lookup(material_ctx *m, const char *name, const glass_t **g, const char **searched,
                    lens_err *err);

/* The shortest %g form of v that reads back to the same double; "inf"/"-inf". */
void lens_fmt_double(double v, char buf[32]);

/* Appends a line to lens->notes (written as "# note:" lines); when they are full, what
 * does not fit is cut and the notes end in "...". */
void lens_add_note(lens_t *lens, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
