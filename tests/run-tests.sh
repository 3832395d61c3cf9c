#!/usr/bin/env bash
# Runs every test and prints one summary line "N passed, N failed".
#  - cmocka unit tests: $BUILD/tests/test_*   (their own "[  PASSED  ] N test(s)." lines are counted)
#  - command-line tests: tests/cli/*.sh and tests/hard/*.sh; each prints "ok NAME" or "FAIL NAME" lines
# Environment: BIN (binaries), BUILD (build dir), SANITIZE (non-empty under ASan/UBSan).
set -u
cd "$(dirname "$0")/.."
export BIN=${BIN:-bin} BUILD=${BUILD:-build} SANITIZE=${SANITIZE:-}
export TOP=$PWD
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/lsan.supp:print_suppressions=0}
passed=0 failed=0 failures=()
log=$(mktemp -d)
trap 'rm -rf "$log"' EXIT

for t in "$BUILD"/tests/test_*; do
  [ -x "$t" ] || continue
  name=$(basename "$t")
  start=$(date +%s)
  CMOCKA_MESSAGE_OUTPUT=stdout "$t" >"$log/$name.out" 2>&1
  rc=$?
  p=$(sed -n 's/^\[  PASSED  \] \([0-9]*\) test.*/\1/p' "$log/$name.out" | tail -1)
  f=$(sed -n 's/^\[  FAILED  \] \([0-9]*\) test.*/\1/p' "$log/$name.out" | tail -1)
  p=${p:-0} f=${f:-0}
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi
  passed=$((passed + p)) failed=$((failed + f))
  printf '%-32s %3d passed %3d failed  %3ds\n' "$name" "$p" "$f" $(( $(date +%s) - start ))
  if [ "$f" -ne 0 ]; then failures+=("$name"); grep -E 'FAILED|ERROR|error|Sanitizer|runtime error' "$log/$name.out" | head -20; fi
done

for t in tests/cli/*.sh tests/hard/*.sh; do
  [ -f "$t" ] || continue
  [ "$(basename "$t")" = lib.sh ] && continue
  name=$(basename "$t" .sh)
  start=$(date +%s)
  bash "$t" >"$log/$name.out" 2>&1
  rc=$?
  p=$(grep -c '^ok ' "$log/$name.out")
  f=$(grep -c '^FAIL ' "$log/$name.out")
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; echo "FAIL $name exited $rc" >>"$log/$name.out"; fi
  passed=$((passed + p)) failed=$((failed + f))
  printf '%-32s %3d passed %3d failed  %3ds\n' "$name" "$p" "$f" $(( $(date +%s) - start ))
  if [ "$f" -ne 0 ]; then failures+=("$name"); grep -A3 '^FAIL ' "$log/$name.out" | head -30; fi
done

[ ${#failures[@]} -eq 0 ] || echo "failing: ${failures[*]}"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
