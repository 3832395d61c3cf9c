/* libFuzzer target: agf_parse on arbitrary bytes must read glasses or give an error,
 * never crash, hang or leak; every glass handed over must be usable. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "agf.h"
#include "glass.h"

static int use(void *ctx, const glass_t *g, lens_err *err)
{
    (void)ctx;
    (void)err;
    volatile double n = glass_index_unchecked(g, 0.55);
    (void)n;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lens_err err;
    agf_parse((const char *)data, size, "fuzz.agf", use, NULL, &err);
    return 0;
}
