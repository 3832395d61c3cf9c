#ifndef SPARSELENS_IMPORT_SEQ_H
#define SPARSELENS_IMPORT_SEQ_H
/* What the CODE V .seq reader keeps while it reads (import_seq.c) and builds the lens
 * from afterwards (import_seq_build.c). Internal to that reader. */
#include "lens/import_common.h"

#define SEQ_INFINITE_OBJECT 1e9 /* CODE V writes 1e10 or more for an object at infinity */
#define SEQ_MAX_LIST LENS_MAX_WAVES /* wavelengths, fields */
#define SEQ_MAX_PWL LENS_MAX_WAVES  /* wavelengths of a private glass; more is an error */
#define SEQ_MAX_PRIVATE 32      /* private glasses */

typedef struct {
    long line;
    int kind; /* 'O' object, 'S' surface, 'I' image */
    double curv, thick, cir, conic;
    double radius;    /* as written, when given_radius (0: flat) */
    int given_radius; /* radius mode: keep the written radius exact */
    double asph[LENS_ASPHERE_TERMS]; /* A B C D E: r^4 .. r^12 */
    int stop;
    char glass[48];
    long glass_line;
    char refuse[160];
    long refuse_line;
} qsurf;

typedef struct {
    char name[48];
    double nd, vd; /* vd 0: no F and C indices, a bare index */
    int tabulated;  /* glass is the formula fitted to the table (glass_fit_table) */
    glass_t glass;
    double residual; /* its largest misfit of a tabulated index */
    char why[80];  /* non-empty: cannot be used, and why */
} seq_private_glass;

typedef struct {
    import_system sys; /* path, lens, skips, unit, epd, fno */
    qsurf *s;
    size_t ns, cap;
    int curvature_mode;
    double wl[SEQ_MAX_LIST];
    int nwl, ref;
    double wtw[SEQ_MAX_LIST]; /* WTW: the wavelengths' weights */
    int nwtw;
    double yan[SEQ_MAX_LIST];
    int nyan;
    char field_kind[32];
    lens_field_kind fkind;
    /* private glass catalog (PRV ... END): indices at the PWL wavelengths */
    int in_prv;
    double pwl[SEQ_MAX_PWL];
    int npwl;
    seq_private_glass prv[SEQ_MAX_PRIVATE];
    int nprv;
} seq_state;

/* The lens from what was read (state: a seq_state). 0, or -1 with err set. */
int seq_build(void *state, const lens_load_options *opt, lens_err *err);

#endif
