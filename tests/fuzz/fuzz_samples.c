/* libFuzzer target: the sample-file reader (samples_open, samples_map, samples_next).
 * A malformed row must come back as -1 with every value nan and a FILE:LINE message, and
 * reading goes on after it, as the filters (lens-trace -, lens-eval) rely on.
 * needs: src/sample/samples.c */
#include <math.h>

#include "fuzz_common.h"
#include "sparselens/samples.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_path(data, size);
    lens_err err;
    samples_reader *r = samples_open(path, &err);
    if (!r) {
        FUZZ_CHECK(err.msg[0] != 0 && strchr(err.msg, '\n') == NULL);
        return 0;
    }
    int nc = samples_ncols(r);
    FUZZ_CHECK(nc > 0);
    for (int i = 0; i < nc; i++)
        FUZZ_CHECK(samples_find(r, samples_colname(r, i)) >= 0);
    static const char *const names[] = {"x", "y", "u", "v", "lambda"};
    int map[5];
    (void)samples_map(r, names, 5, map, &err);
    double *vals = malloc((size_t)nc * sizeof *vals);
    FUZZ_CHECK(vals != NULL);
    long last = 0;
    int rc;
    while ((rc = samples_next(r, vals, &err)) != 0) {
        FUZZ_CHECK(samples_line(r) > last);
        last = samples_line(r);
        if (rc < 0) {
            for (int i = 0; i < nc; i++)
                FUZZ_CHECK(isnan(vals[i]));
            FUZZ_CHECK(strchr(err.msg, '\n') == NULL && strstr(err.msg, ":") != NULL);
        }
    }
    FILE *null = fopen("/dev/null", "w");
    if (null) {
        samples_write_row(null, vals, nc);
        fclose(null);
    }
    free(vals);
    samples_close(r);
    return 0;
}
