/* libFuzzer target: the .poly reader must reject or accept any bytes without crashing,
 * and whatever it accepts must write, read back, and evaluate to the same bits. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "poly.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    FILE *f = fmemopen((void *)data, size, "r");
    if (!f)
        return 0;
    poly_system *s = NULL;
    lens_err err;
    int rc = poly_read_stream(f, "fuzz", &s, &err);
    fclose(f);
    if (rc != 0)
        return 0;
    char *buf = NULL;
    size_t len = 0;
    FILE *w = open_memstream(&buf, &len);
    poly_write(w, s);
    fclose(w);
    FILE *r = fmemopen(buf, len, "r");
    poly_system *t = NULL;
    if (poly_read_stream(r, "again", &t, &err) != 0)
        abort(); /* what was written must read */
    fclose(r);
    int nin = poly_ninputs(s), nout = poly_noutputs(s);
    double *in = calloc((size_t)nin, sizeof(double)), *a = calloc((size_t)nout, sizeof(double)),
           *b = calloc((size_t)nout, sizeof(double));
    for (int i = 0; i < nin; i++)
        in[i] = 0.5 + 0.25 * i;
    if (poly_eval(s, in, a) != poly_eval(t, in, b) || memcmp(a, b, (size_t)nout * sizeof(double)))
        abort();
    free(in);
    free(a);
    free(b);
    free(buf);
    poly_free(s);
    poly_free(t);
    return 0;
}
