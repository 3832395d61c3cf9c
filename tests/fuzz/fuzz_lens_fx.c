/* libFuzzer target: the .fx prescription reader (lens_read_fx).
 * needs: src/import_fx.c */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "lens.h"
#include "lens_import.h"

FUZZ_LENS_READER_TARGET(lens_read_fx, "fuzz.fx")
