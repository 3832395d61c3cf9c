#ifndef SPARSELENS_FIT_H
#define SPARSELENS_FIT_H
/* Adaptive sparse polynomial regression (lens-fit): greedy forward selection scored by
 * the exact drop in residual, an exchange pass, held-out stopping, and radial
 * partitioning where one polynomial cannot meet the tolerance. */
#include <stddef.h>

#include "sparselens/diag.h"
#include "sparselens/poly.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int max_terms;      /* per output and part (default 40) */
    int max_degree;     /* candidates: all monomials up to this total degree (default 11) */
    double tolerance;   /* stop an output when its held-out RMS error <= tolerance (output units); 0 = off */
    const double *output_tolerance; /* per output (noutputs values) instead of tolerance; NULL: none */
    int max_parts;      /* radial parts allowed when one polynomial misses the tolerance (default 1) */
    double holdout;     /* fraction of samples held out for stopping (default 0.2) */
    unsigned long seed; /* for the held-out split */
    int threads;        /* <= 0: OpenMP default */
    int verbose;        /* progress lines on stderr */
    unsigned no_offset; /* bit i: scale input i without an offset (a radius >= 0 whose
                           polynomial is odd or even in it) */
    int frame;          /* POLY_FRAME_*: fit in the meridional frame of a rotationally
                           symmetric lens (needs inputs x, y, u, v); default none */
    const unsigned char *frame_plain; /* per output (noutputs): 1 = fitted outside the
                           frame (directions that do not turn with the ray, as the
                           outer-pupil u, v); NULL: all in it */
    int lambda_transform; /* POLY_XFORM_* for the input lambda; default identity */
    const double *scaling; /* NULL, or per input (offset, scale) pairs to use instead of
                              the automatic ones (nan: automatic); for two fits sharing
                              one system */
    int force_parts;    /* > 0: exactly this many radial parts, no tolerance search */
    double passage_tolerance; /* hits that only decide passage (fit_is_passage_output)
                           without a tolerance of their own in output_tolerance: stop at
                           this fraction of the pass circle's radius (default 1e-3;
                           0: the tolerance of the others) */
    int drop_circles;   /* 1: after the fit, drop the pass circles of surfaces sN (and
                           their outputs) that alone block none of the training rows the
                           lens blocks (fit_circles.c): fit_system's system then has
                           fewer outputs than asked for; default 0 */
} fit_options;

void fit_options_default(fit_options *opt);

/* 1 for the outputs that only decide passage: hits on the stop (ap_x, ap_y) and on a
 * surface N (sN_x, sN_y), lens-trace's passage columns. fit_system fits them on every
 * row where they are finite, blocked rays included (the hits are taken with every rim
 * extended, so a fit sees both sides of each rim), with a single part and their own
 * tolerance; their pass circles hold the hits of the passing rows. */
int fit_is_passage_output(const char *name);

/* Whether a system with these outputs, fitted to samples whose writer described their
 * passage columns by `note` (the "# passage:" line lens-trace writes; NULL if none),
 * of which `unfitted` passage columns were left out of the outputs, with `blocked`
 * blocked rows, models passage in full: NULL if so, else the reason, in buf. */
const char *fit_passage_gap(const char *note, int nout, const char *const *outputs,
                            int unfitted, size_t blocked, char *buf, size_t len);

/* Fits every output on the rows whose outputs are all finite (rays that pass); the
 * passage outputs above on the rows where they are finite.
 * in: count x ninputs, out: count x noutputs (row-major). Returns NULL with err set on
 * degenerate input (too few usable rows, a constant input column, non-finite inputs). */
poly_system *fit_system(const char *lens_name, int ninputs, const char *const *inputs,
                        int noutputs, const char *const *outputs, size_t count, const double *in,
                        const double *out, const fit_options *opt, lens_err *err);

/* fit_system on the columns named inputs and outputs of a sample file (man 5
 * lens-samples; path "-": stdin), such as lens-trace writes: every row (a malformed row,
 * or an input that is not finite, is an error with FILE:LINE); the system records the
 * lens the file names ("# lens:", "# lens-path:"), "unknown" if none. lens-fit does more
 * (the passage columns it finds, the frame and wavelength transform the samples ask
 * for): this is the plain fit. NULL with err set. */
poly_system *fit_system_file(const char *path, int ninputs, const char *const *inputs,
                             int noutputs, const char *const *outputs, const fit_options *opt,
                             lens_err *err);

#ifdef __cplusplus
}
#endif

#endif
