/* libFuzzer target: the .poly reader (poly_read_stream). An accepted system must write
 * and read back, and evaluate without faults at points inside and outside its domain.
 * needs: src/poly/poly_io.c */
#include <math.h>

#include "fuzz_common.h"
#include "sparselens/poly.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_stream s;
    if (fuzz_stream_open(&s, data, size))
        return 0;
    poly_system *sys = NULL;
    lens_err err;
    int rc = poly_read_stream(s.f, "fuzz.poly", &sys, &err);
    fuzz_stream_close(&s);
    if (rc != 0) {
        FUZZ_CHECK(err.msg[0] != 0 && strchr(err.msg, '\n') == NULL);
        return 0;
    }
    char *text = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&text, &len);
    FUZZ_CHECK(m != NULL);
    FUZZ_CHECK(poly_write(m, sys) == 0);
    fclose(m);
    poly_system *back = NULL;
    FUZZ_CHECK(fuzz_stream_open(&s, (const uint8_t *)text, len) == 0);
    rc = poly_read_stream(s.f, "roundtrip.poly", &back, &err);
    fuzz_stream_close(&s);
    if (rc != 0)
        fprintf(stderr, "written system does not read back: %s\n", err.msg);
    FUZZ_CHECK(rc == 0);
    FUZZ_CHECK(poly_ninputs(back) == poly_ninputs(sys) && poly_noutputs(back) == poly_noutputs(sys));
    poly_free(back);
    free(text);

    int ni = poly_ninputs(sys), no = poly_noutputs(sys);
    double *in = calloc((size_t)ni, sizeof *in), *out = calloc((size_t)no, sizeof *out);
    double *jac = calloc((size_t)ni * (size_t)no, sizeof *jac);
    FUZZ_CHECK(in && out && jac);
    const double pts[] = {0, 0.5, -3, 1e6};
    for (int k = 0; k < 4; k++) {
        for (int i = 0; i < ni; i++)
            in[i] = pts[k] * (i + 1);
        (void)poly_eval(sys, in, out);
        (void)poly_eval_jacobian(sys, in, out, jac);
        (void)poly_in_domain(sys, in);
    }
    free(in);
    free(out);
    free(jac);
    poly_free(sys);
    return 0;
}
