/* libFuzzer target: pbrt's .dat lens reader (lens_read_pbrt).
 * needs: src/import_pbrt.c */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "lens.h"
#include "lens_import.h"

FUZZ_LENS_READER_TARGET(lens_read_pbrt, "fuzz.dat")
