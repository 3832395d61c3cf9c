/* libFuzzer target: the project's .lens reader (lens_read_native).
 * needs: src/lens_native.c */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "lens.h"
#include "lens_import.h"


int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    fuzz_use_shipped_catalog();
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_stream s;
    if (fuzz_stream_open(&s, data, size))
        return 0;
    lens_t lens;
    lens_err err;
    lens_init(&lens);
    int rc = lens_read_native(s.f, "fuzz.lens", NULL, &lens, &err);
    fuzz_stream_close(&s);
    if (rc == 0)
        fuzz_check_lens(&lens, NULL);
    else
        FUZZ_CHECK(err.msg[0] != 0 && strchr(err.msg, '\n') == NULL);
    lens_free(&lens);
    return 0;
}
