#ifndef SPARSELENS_FIT_PART_H
#define SPARSELENS_FIT_PART_H
/* The samples of one fit_system_core call, prepared (fit.c), and the fits of its radial
 * parts (fit_part.c). Internal to src/fit. */
#include "fit/fit_internal.h"
#include "sparselens/fit.h"

typedef struct {
    int k;
    int *cand;
    double *coef;      /* final: QR on every row of the part */
    double hold_sse;   /* of the training-only fit, over held-out rows of the part's core */
    size_t hold_n;
    int steps, swaps;
} out_fit;

typedef struct {
    double rmin, rmax;
    size_t flo, fhi;   /* rows fitted: sorted positions [flo, fhi) */
    out_fit *o;
} part_fit;

typedef struct {
    int nparts;
    part_fit *p;
    double *rms;       /* per output, held-out, over all parts */
    double *jump;      /* per output, largest jump between neighbouring parts */
} sys_fit;

typedef struct {
    const fit_options *opt;
    fit_basis b;
    int nin, nout;
    size_t count;        /* rows given */
    size_t n;            /* usable rows */
    size_t nho;          /* of them held out */
    size_t ndistinct;    /* distinct rays among the usable rows (copies of a ray: one) */
    double *s;           /* n x nin scaled inputs */
    double *y;           /* n x nout outputs */
    unsigned char *hold; /* per usable row */
    double *rad;         /* sensor radius per usable row (NULL without x and y) */
    size_t *order;       /* usable rows by radius */
    double *lo, *hi;     /* per input: range over the usable rows */
    double *off, *scl;   /* per input: scaling to [-1, 1] */
    int ix, iy;          /* inputs x and y, -1 if absent */
    int threads;
} fit_ctx;

double fit_tol_of(const fit_options *opt, int o);
void sys_fit_free(sys_fit *f, int nout);
/* The fewest radial parts (up to opt->max_parts) that meet the tolerances, else the
 * best tried; opt->force_parts fixes the count. */
int fit_choose_parts(const fit_ctx *c, sys_fit *best, lens_err *err);

#endif
