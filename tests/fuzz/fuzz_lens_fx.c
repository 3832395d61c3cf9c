/* libFuzzer target: the .fx prescription reader (lens_read_fx).
 * needs: src/lens/import_fx.c */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "sparselens/lens.h"
#include "sparselens/import_table.h"

FUZZ_LENS_READER_TARGET(lens_read_fx, "fuzz.fx")
