/* libFuzzer target: lens_load on a file without a known extension, so the content
 * sniffing (native, .fx or pbrt) picks the reader, as for a lens piped in or renamed.
 * needs: src/lens/lens_load.c */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "sparselens/lens.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    fuzz_use_shipped_catalog();
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_path(data, size);
    lens_t lens;
    lens_err err;
    int rc = lens_load(path, NULL, &lens, &err);
    if (rc == 0)
        fuzz_check_lens(&lens, NULL);
    else
        FUZZ_CHECK(err.msg[0] != 0 && strchr(err.msg, '\n') == NULL);
    lens_free(&lens);
    return 0;
}
