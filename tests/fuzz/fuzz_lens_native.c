/* libFuzzer target: the project's .lens reader (lens_read_native).
 * needs: src/lens/lens_native.c */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "sparselens/lens.h"

FUZZ_LENS_READER_TARGET(lens_read_native, "fuzz.lens")
