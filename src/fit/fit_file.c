/* fit_system_file (fit.h): the named columns of a sample file read into memory, then
 * fit_system; the lens the samples record (lens-trace's "# lens:" and "# lens-path:"
 * lines) recorded in the system. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/fit.h"
#include "sparselens/samples.h"

/* Appends one row of n values to *buf (count rows so far, capacity *cap rows). */
static int push_row(double **buf, size_t *cap, size_t count, const double *row, int n)
{
    if (count == *cap) {
        size_t c = *cap ? 2 * *cap : 1024;
        double *b = realloc(*buf, c * (size_t)n * sizeof *b);
        if (!b) return -1;
        *buf = b, *cap = c;
    }
    memcpy(*buf + count * (size_t)n, row, (size_t)n * sizeof *row);
    return 0;
}

poly_system *fit_system_file(const char *path, int ninputs, const char *const *inputs,
                             int noutputs, const char *const *outputs, const fit_options *opt,
                             lens_err *err)
{
    if (ninputs < 1 || noutputs < 1 || ninputs > POLY_MAX_INPUTS || noutputs > POLY_MAX_OUTPUTS) {
        lens_errf(err, path, 0, "give 1 to %d inputs and 1 to %d outputs", POLY_MAX_INPUTS,
                  POLY_MAX_OUTPUTS);
        return NULL;
    }
    samples_reader *r = samples_open(path, err);
    if (!r) return NULL;
    int map[POLY_MAX_INPUTS + POLY_MAX_OUTPUTS], ncols = samples_ncols(r);
    double *vals = malloc((size_t)ncols * sizeof *vals), *in = NULL, *out = NULL;
    size_t count = 0, cap_in = 0, cap_out = 0;
    poly_system *sys = NULL;
    if (!vals) {
        lens_errf(err, path, 0, "out of memory");
        goto done;
    }
    if (samples_map(r, inputs, ninputs, map, err) ||
        samples_map(r, outputs, noutputs, map + ninputs, err))
        goto done;
    for (;;) {
        int got = samples_next(r, vals, err);
        if (got == 0) break;
        if (got < 0) goto done; /* a malformed row is an error here, as in lens-fit */
        double row[POLY_MAX_INPUTS + POLY_MAX_OUTPUTS];
        int finite = 1;
        for (int i = 0; i < ninputs + noutputs; i++) {
            row[i] = vals[map[i]];
            if (i < ninputs && !isfinite(row[i])) finite = 0;
        }
        if (!finite) {
            lens_errf(err, path, samples_line(r), "an input is not a finite number");
            goto done;
        }
        if (push_row(&in, &cap_in, count, row, ninputs) ||
            push_row(&out, &cap_out, count, row + ninputs, noutputs)) {
            lens_errf(err, path, 0, "out of memory");
            goto done;
        }
        count++;
    }
    const char *lens = samples_meta(r, "lens"), *lens_path = samples_meta(r, "lens-path");
    sys = fit_system(lens ? lens : "unknown", ninputs, inputs, noutputs, outputs, count, in, out,
                     opt, err);
    if (sys && lens_path) poly_set_lens_path(sys, lens_path);
done:
    free(vals);
    free(in);
    free(out);
    samples_close(r);
    return sys;
}
