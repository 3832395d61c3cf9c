/* libFuzzer target: the Zemax AGF glass catalog reader (agf_parse), 8-bit and UTF-16.
 * A glass handed to the callback must be finite where it matters (its range).
 * needs: include/sparselens/agf.h */
#include <math.h>

#include "sparselens/agf.h"
#include "fuzz_common.h"
#include "sparselens/glass.h"

static int add(void *ctx, const glass_t *g, lens_err *err)
{
    (void)err;
    size_t *count = ctx;
    (*count)++;
    double n;
    lens_err e;
    if (glass_index(g, 0.5 * (g->lambda_min + g->lambda_max), &n, &e) == 0)
        FUZZ_CHECK(isfinite(n));
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    size_t count = 0;
    lens_err err;
    if (agf_parse((const char *)data, size, "fuzz.agf", add, &count, &err) != 0)
        FUZZ_CHECK(err.msg[0] != 0 && strchr(err.msg, '\n') == NULL);
    return 0;
}
