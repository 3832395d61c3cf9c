#ifndef SPARSELENS_GLASS_H
#define SPARSELENS_GLASS_H
/* Optical media: air, a bare index, an (n_d, V_d) model glass, or a catalog glass
 * with a dispersion formula. Wavelengths are in micrometres everywhere; a wavelength
 * outside a glass's valid range is an error, never an extrapolation. */
#include "sparselens/diag.h"

#ifdef __cplusplus
extern "C" {
#endif

#define GLASS_D_LINE 0.5875618 /* helium d line, um */
#define GLASS_F_LINE 0.4861327 /* hydrogen F line, um */
#define GLASS_C_LINE 0.6562725 /* hydrogen C line, um */

typedef enum {
    GLASS_AIR,      /* n = 1: prescriptions give indices relative to air */
    GLASS_CONSTANT, /* a bare n_d: no dispersion */
    GLASS_NDVD,     /* model glass derived from n_d and V_d (see glass.c) */
    GLASS_FORMULA   /* catalog glass: AGF formula number `formula`, coefficients coef[] */
} glass_kind;

/* AGF formula numbers (Zemax's numbering); the shipped catalog uses GLASS_F_SELLMEIER1. */
enum {
    GLASS_F_SCHOTT = 1, GLASS_F_SELLMEIER1 = 2, GLASS_F_HERZBERGER = 3,
    GLASS_F_SELLMEIER2 = 4, GLASS_F_CONRADY = 5, GLASS_F_SELLMEIER3 = 6,
    GLASS_F_HANDBOOK1 = 7, GLASS_F_HANDBOOK2 = 8, GLASS_F_SELLMEIER4 = 9,
    GLASS_F_EXTENDED1 = 10, GLASS_F_SELLMEIER5 = 11, GLASS_F_EXTENDED2 = 12,
    GLASS_F_EXTENDED3 = 13
};

#define GLASS_MAX_COEF 12

typedef struct {
    glass_kind kind;
    int formula;                 /* GLASS_FORMULA only */
    char name[48];               /* catalog name, or "" */
    double nd, vd;               /* nominal values (vd = 0 when not dispersive) */
    double coef[GLASS_MAX_COEF];
    double lambda_min, lambda_max; /* valid range, um */
    int embedded;                /* of no catalog (a glass the design file defined, as a
                                    CODE V private glass): a lens file written with it
                                    carries its data ("# glass:" lines, lens(5)) */
} glass_t;

/* Refractive index at lambda (um). 0 on success; -1 when lambda is outside the
 * glass's range or the formula gives no real index (err says which). */
int glass_index(const glass_t *g, double lambda_um, double *n, lens_err *err);

/* The same without the range check: for hot loops whose wavelengths were checked once. */
double glass_index_unchecked(const glass_t *g, double lambda_um);

/* A glass from a table of indices at count wavelengths (um), 2 to 64 of them: the Schott
 * power series least-squares fitted to them (as many terms as points, up to six), valid
 * over the table's span; *max_residual the largest misfit of an index. -1 when the
 * table cannot make a glass (an index below 1, a wavelength not positive). */
int glass_fit_table(const double *lambda_um, const double *index, int count, glass_t *g,
                    double *max_residual);

/* One glass as a line of the .catalog format, "name formula c1 .. cN lambda_min
 * lambda_max nd vd" (lens(5), GLASS CATALOG): parsed (line is cut into words; 0, or -1
 * with err naming path:lineno) and written (every number to read back exactly). */
int glass_parse_catalog_line(char *line, const char *path, long lineno, glass_t *g,
                             lens_err *err);
void glass_format_catalog_line(const glass_t *g, char *buf, size_t n);

glass_t glass_air(void);
glass_t glass_constant(double nd);
glass_t glass_from_ndvd(double nd, double vd);

/* The largest n_d a glass given by numbers may have. The densest optical glasses and
 * crystals reach about 2.4 at the d line (diamond 2.42); 3 leaves room and still catches
 * a typo, a unit mix-up or a fuzzed number before it becomes a lens. */
#define GLASS_ND_MAX 3.0

/* Every reader's check of a glass given as numbers (nd/Vd, a bare nd, a CODE V code, a
 * Zemax model glass): 1 <= n_d <= GLASS_ND_MAX, and, unless vd is NAN (a bare index, no
 * dispersion), 0 < V_d < inf. 0 when usable; else -1 with err = "file:line: WHAT: n_d
 * 0.6 is below 1" (what names the material as the file writes it). */
int glass_check_ndvd(double nd, double vd, const char *what, const char *file, long line,
                     lens_err *err);

typedef struct glass_catalog glass_catalog;

/* Loads a catalog (the project's .catalog text format, or an AGF file). A catalog
 * may be extended by loading more files into it: pass *cat non-NULL. */
int glass_catalog_load(glass_catalog **cat, const char *path, lens_err *err);
const glass_t *glass_catalog_find(const glass_catalog *cat, const char *name);
size_t glass_catalog_size(const glass_catalog *cat);
const glass_t *glass_catalog_at(const glass_catalog *cat, size_t i);
/* The files loaded, comma separated, for "glass X not found in ..." messages. */
const char *glass_catalog_sources(const glass_catalog *cat);
void glass_catalog_free(glass_catalog *cat);

/* An empty catalog (NULL on allocation failure), and adding one glass to it (readers of
 * other catalog formats build on these). The glass is copied. Names may repeat across
 * files: glass_catalog_find returns the first one added, so catalogs loaded first take
 * precedence. Names are compared without regard to case. */
glass_catalog *glass_catalog_new(void);
int glass_catalog_add(glass_catalog *cat, const glass_t *g, lens_err *err);
/* Records a file name for glass_catalog_sources (readers of other formats). */
int glass_catalog_add_source(glass_catalog *cat, const char *path);

/* Vendors: each glass is its vendor's (the file's "vendor NAME" line, else the file
 * name up to its first '_', '.' or '-', upper case); glass_catalog_set_vendor sets the
 * vendor of the glasses added next. Names repeat across vendors. */
#define GLASS_VENDOR_MAX 24
void glass_catalog_set_vendor(glass_catalog *cat, const char *vendor);
const char *glass_catalog_vendor(const glass_catalog *cat, size_t i);
/* The index of a glass glass_catalog_find or glass_catalog_at returned; (size_t)-1
 * for one not in cat. */
size_t glass_catalog_index(const glass_catalog *cat, const glass_t *g);
/* An old name ("alias BK7 N-BK7"): the name of the glass it is read as, else NULL.
 * glass_catalog_find returns the first of a name in catalog order, alias or not. */
const char *glass_catalog_alias_of(const glass_catalog *cat, size_t i);
/* Why the glass cannot be used (its formula contradicts its own n_d: "in F, formula 2
 * (Sellmeier 1) gives n_d ... where the entry says ..."), else NULL. Such a glass stays
 * in the catalog so that naming it is an error naming it, while the rest of the catalog
 * stays usable. */
const char *glass_catalog_problem(const glass_catalog *cat, size_t i);

/* The shipped default catalog: $SPARSELENS_GLASS_CATALOG, else glass.catalog in the
 * shipped lens directories (data_path.h). NULL if not found. */
const char *glass_default_catalog_path(void);

#ifdef __cplusplus
}
#endif

#endif
