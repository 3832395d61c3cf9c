/* libFuzzer target: pbrt's .dat lens reader (lens_read_pbrt).
 * needs: src/lens/import_pbrt.c */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "sparselens/lens.h"
#include "sparselens/import_table.h"

FUZZ_LENS_READER_TARGET(lens_read_pbrt, "fuzz.dat")
