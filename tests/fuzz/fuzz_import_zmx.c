/* libFuzzer target: lens_parse_zmx on arbitrary bytes must return a lens or an error,
 * never crash, hang or leak. Glass names resolve in no catalog, so that each run is
 * independent of the disk (and fast). */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "import.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const none[] = {NULL};
    lens_load_options opt = {.catalogs = none};
    setenv("SPARSELENS_GLASS_CATALOG", "/nonexistent", 1);
    lens_t lens;
    lens_err err;
    if (lens_parse_zmx((const char *)data, size, "fuzz.zmx", &opt, &lens, &err) == 0)
        lens_free(&lens);
    return 0;
}
