/* libFuzzer target: the CODE V .seq importer (lens_read_seq).
 * needs: include/sparselens/import_design.h */
#include "fuzz_common.h"
#include "fuzz_lens_check.h"
#include "sparselens/lens.h"
#include "sparselens/import_design.h"

FUZZ_LENS_READER_TARGET(lens_read_seq, "fuzz.seq")
