/* libFuzzer target: the Zemax .zmx importer (lens_read_zmx).
 * needs: include/sparselens/import.h */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "sparselens/lens.h"
#include "sparselens/lens_import.h"
#include "sparselens/import.h"

FUZZ_LENS_READER_TARGET(lens_read_zmx, "fuzz.zmx")
