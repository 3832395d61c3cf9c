#!/usr/bin/env bash
# tools/bench-compare.sh (make bench-compare): the working tree against itself, one
# short process a side; the table has both systems' rows, and B / A is B's best over
# A's as the row gives them. Bad arguments are refused before anything runs.
source "$(dirname "$0")/lib.sh"
S=tools/bench-compare.sh
if BIN=$BIN BUILD=$BUILD run $S . . 1 2000 >$T/cmp.md 2>$T/cmp.err &&
   awk -F'|' '/_ns_per_ray/ { n++; a = $3 + 0; b = $5 + 0; r = $7 + 0
                if (a <= 0 || b <= 0 || (b / a - r) ^ 2 > 0.001 ^ 2) bad = bad " " $2 }
              /poly_batch_ns_per_ray/ { p = 1 } /poly5_batch_ns_per_ray/ { q = 1 }
              END { exit !(n >= 12 && p && q && bad == "") }' $T/cmp.md &&
   grep -q '^A: \. (working tree), B: \. (working tree); 1 processes each' $T/cmp.md
then ok bench_compare_self; else fail bench_compare_self "$(cat $T/cmp.md $T/cmp.err | head -20)"; fi
# BIN and BUILD given as absolute paths
if BIN=$TOP/$BIN BUILD=$TOP/$BUILD run $S . . 1 500 >$T/abs.md 2>$T/abs.err &&
   grep -q 'poly5_batch_ns_per_ray' $T/abs.md
then ok bench_compare_absolute_paths; else fail bench_compare_absolute_paths "$(cat $T/abs.err | head -5)"; fi
expect_error bench_compare_usage 'usage: tools/bench-compare.sh A B' $S .
expect_error bench_compare_runs "RUNS must be a positive integer, not 'x'" $S . . x
expect_error bench_compare_rev "'no-such-rev' is not a commit" $S no-such-rev .
