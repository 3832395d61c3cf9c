/* libFuzzer target: lens_parse_seq on arbitrary bytes must return a lens or an error,
 * never crash, hang or leak. Glass names go through the shipped catalog only. */
#include <stddef.h>
#include <stdint.h>

#include "import.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lens_t lens;
    lens_err err;
    if (lens_parse_seq((const char *)data, size, "fuzz.seq", NULL, &lens, &err) == 0)
        lens_free(&lens);
    return 0;
}
