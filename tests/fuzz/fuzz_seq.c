/* libFuzzer target: the CODE V .seq importer (lens_read_seq).
 * needs: src/import.h */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "lens.h"
#include "lens_import.h"
#include "import.h"

FUZZ_LENS_READER_TARGET(lens_read_seq, "fuzz.seq")
