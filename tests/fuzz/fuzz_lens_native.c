/* libFuzzer target: the project's .lens reader (lens_read_native).
 * needs: src/lens_native.c */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "lens.h"
#include "lens_import.h"

FUZZ_LENS_READER_TARGET(lens_read_native, "fuzz.lens")
