/* libFuzzer target: the Zemax .zmx importer (lens_read_zmx).
 * needs: src/import.h */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "lens.h"
#include "lens_import.h"
#include "import.h"

FUZZ_LENS_READER_TARGET(lens_read_zmx, "fuzz.zmx")
