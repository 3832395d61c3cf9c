#ifndef SPARSELENS_APP_FIT_INPUT_H
#define SPARSELENS_APP_FIT_INPUT_H
/* lens-fit's samples checked in the user's terms before the fit (fit_input.c): each
 * value as it is read, with its file and line; then, over the usable rows (rays that
 * pass), the inputs and the meridional frame's inputs the fitter would find constant,
 * named by column and unit rather than in the fitter's scaled and framed variables. */
#include <stddef.h>

#include "sparselens/diag.h"

/* The largest magnitude of a value lens-fit takes (and 1 / it, the smallest wavelength). */
#define FIT_MAX_MAGNITUDE 1e100

typedef struct {
    double lo, hi;
} fit_spread;

typedef struct {
    int nin;
    const char *const *in_names;
    size_t usable;                /* usable rows so far */
    long first_line, last_line;   /* their first and last lines */
    fit_spread *in;               /* per input */
    fit_spread frame[3];          /* r, u', v' of the meridional frame */
    int ix, iy, iu, iv;           /* the frame's inputs, -1 when absent */
} fit_input_check;

/* 0, or -1 (err: out of memory). in_names is kept, not copied. */
int fit_input_check_init(fit_input_check *c, int nin, const char *const *in_names,
                         lens_err *err);
void fit_input_check_free(fit_input_check *c);

/* Why a value of column name cannot be fitted (not finite, beyond +-FIT_MAX_MAGNITUDE, a
 * wavelength not in [1/FIT_MAX_MAGNITUDE, FIT_MAX_MAGNITUDE] um), or NULL. Outputs may
 * be nan (a blocked ray). */
const char *fit_input_bad_value(const char *name, double v, int output);

/* A usable row's inputs, read at line. */
void fit_input_check_row(fit_input_check *c, const double *in, long line);

/* -1 (err at path and the first usable line) when no row of the count read is usable, or
 * an input does not vary over the usable rows (the fitter's test, fit.c). */
int fit_input_check_columns(const fit_input_check *c, const char *path, size_t count,
                            lens_err *err);
/* -1 (err) when r, u' or v' of the meridional frame does not vary over the usable rows. */
int fit_input_check_frame(const fit_input_check *c, const char *path, lens_err *err);

#endif
