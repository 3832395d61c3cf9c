#ifndef SPARSELENS_FIT_INTERNAL_H
#define SPARSELENS_FIT_INTERNAL_H
/* Internals of lens-fit, shared by the files of src/fit and the unit tests. Nothing here
 * is part of the library's public interface.
 *
 * Monomials of nvar variables with total degree <= M are numbered in lexicographic
 * order of their exponent tuples (a_0 first, each ascending). That order is the order
 * of nested loops over the exponents, so the moment sums of fit_moments.c come out
 * already numbered, and a parent (a minus one unit of the last non-zero exponent)
 * always precedes its child. */
#include <stddef.h>

enum { FIT_MAX_VARS = 16, FIT_MAX_DEG = 24, FIT_BLOCK = 128 }; /* moments to degree 2 * FIT_MAX_DEG */

/* Numbering of the monomials of degree <= M in nvar variables. */
typedef struct {
    int nvar, M;
    size_t count;  /* C(M + nvar, nvar) */
    size_t *off;   /* off[(v * (M + 1) + used) * (M + 1) + e]: rank contribution of a_v = e */
} fit_lex;

int fit_lex_init(fit_lex *lx, int nvar, int M);
void fit_lex_free(fit_lex *lx);
/* Index of exponent tuple a (sum(a) <= M). */
static inline size_t fit_lex_rank(const fit_lex *lx, const int *a)
{
    size_t r = 0;
    int used = 0, M1 = lx->M + 1;
    for (int v = 0; v < lx->nvar; v++) {
        r += lx->off[((size_t)v * M1 + used) * M1 + a[v]];
        used += a[v];
    }
    return r;
}
/* Fills exps (count x nvar) with every tuple in rank order. */
void fit_lex_tuples(const fit_lex *lx, int *exps);

/* Powers of the scaled inputs of n samples: pw[(v * (maxe + 1) + e) * stride + i] = s_iv^e.
 * Sample-major rows so that blocks of samples are contiguous. */
typedef struct {
    size_t n, stride; /* stride: n rounded up to FIT_BLOCK, the padding is zero */
    int nvar, maxe;
    double *pw;
} fit_powers;

/* s: rows of scaled inputs (stride nvar), only rows idx[0..n-1] (idx NULL: 0..n-1). */
int fit_powers_init(fit_powers *p, size_t n, int nvar, int maxe, const double *s,
                    const size_t *idx);
void fit_powers_free(fit_powers *p);
static inline const double *fit_pow_row(const fit_powers *p, int v, int e)
{
    return p->pw + ((size_t)v * (p->maxe + 1) + e) * p->stride;
}
/* The dot product of a and b (n each), summed the same way wherever it is used. */
static inline double fit_dot(const double *a, const double *b, size_t n)
{
    double s = 0;
#pragma omp simd reduction(+ : s)
    for (size_t i = 0; i < n; i++)
        s += a[i] * b[i];
    return s;
}
/* Column of monomial a over the samples into col[n]. */
void fit_column(const fit_powers *p, const int *a, double *col);

/* Sums over the samples of w_i * s_i^a for every a of lx (M <= p->maxe), in rank
 * order; w NULL means 1. Deterministic for any thread count. */
void fit_moments(const fit_lex *lx, const fit_powers *p, const double *w, double *out,
                 int threads);

/* The candidate set and the moment tables of one sample set. */
typedef struct {
    int nvar, D;
    fit_lex cand;     /* degree <= D: the candidates */
    fit_lex mom;      /* degree <= 2D: the moments */
    int *exps;        /* cand.count x nvar */
    int *deg;         /* total degree per candidate */
    size_t *gdiag;    /* moment index of 2a per candidate */
} fit_basis;

int fit_basis_init(fit_basis *b, int nvar, int D);
void fit_basis_free(fit_basis *b);

typedef struct {
    int max_terms;
    double tolerance;   /* error at which to stop; never below 1e-10 of the RMS of y */
    int patience;       /* forward steps past the budget without a new held-out minimum */
    int exchange_passes; /* rounds of exchange and floating moves, at most */
} fit_select_opt;

typedef struct {
    int nterms;
    int *cand;          /* chosen candidates, in the order of the final fit */
    double *coef;       /* coefficients (scaled monomials) fitted on the training rows */
    double train_rms;
    double hold_rms;    /* held-out RMS of those coefficients; without held-out rows
                           the training RMS */
    int steps;          /* forward steps taken */
    int swaps;          /* exchanges made */
} fit_selection;

void fit_selection_free(fit_selection *s);

/* Term selection for one output (fit_select.c): greedy forward selection with exact
 * residual-drop scores to twice the budget, backward elimination, held-out stopping,
 * exchange and floating moves, over a ladder of degree caps. Works in the moment
 * metric only: mom are the moments of the training rows (b->mom order), by the sums of
 * y * monomial over them (b->cand order); train and ytrain give the row count and
 * |y|^2. hold may be NULL (or have n = 0). 0 on success. */
int fit_select(const fit_basis *b, const double *mom, const double *by,
               const fit_powers *train, const double *ytrain, const fit_powers *hold,
               const double *yhold, const fit_select_opt *o, fit_selection *res);

/* Least squares by Householder QR (LAPACK dgels) of y on the columns of the chosen
 * monomials over the samples of p: coef[k]. Columns are equilibrated first. 0 on
 * success, -1 when the columns are rank deficient. */
int fit_lsq(const fit_basis *b, const fit_powers *p, const double *y, int k, const int *cand,
            double *coef);

/* Evaluates sum coef_t * s^a_t at sample i of p. */
double fit_eval_sample(const fit_basis *b, const fit_powers *p, size_t i, int k,
                       const int *cand, const double *coef);

/* fit_system without the frame and transforms (fit.c): fits the inputs as given. With
 * opt->frame meridional the inputs are the frame's, without y (x holds the radius, which
 * then also drives the radial parts); fit_system (fit_frame.c) prepares them. */
#include "sparselens/fit.h"
poly_system *fit_system_core(const char *lens_name, int ninputs, const char *const *inputs,
                             int noutputs, const char *const *outputs, size_t count,
                             const double *in, const double *out, const fit_options *opt,
                             lens_err *err);

/* fit_options.drop_circles: sys without the pass circles of surfaces sN that alone
 * block none of the rows in (count x its inputs) whose lens_pass[r] is 0 (the lens
 * blocks them), the one that alone blocks most rows the lens passes first, the others
 * counted again after each (the meta fit_dropped_circles says which): a new system (sys
 * freed), or sys itself when every circle counts, when no row is blocked, or when every
 * output is a passage hit (then lens_pass says nothing). NULL when out of memory (sys
 * untouched). */
#include "sparselens/poly.h"
poly_system *fit_drop_circles(poly_system *sys, size_t count, const double *in,
                              const unsigned char *lens_pass);

#endif
