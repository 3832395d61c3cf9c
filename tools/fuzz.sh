#!/usr/bin/env bash
# Builds and runs the libFuzzer targets tests/fuzz/fuzz_*.c (one per parser).
#
#   tools/fuzz.sh SECONDS      build, then fuzz each target for SECONDS (make fuzz FUZZ_SECONDS=...)
#   tools/fuzz.sh --build      build only
#   tools/fuzz.sh --replay     run every saved regression input once (exit 1 if one still fails)
#
# Targets are built with clang -fsanitize=fuzzer,address,undefined into build-fuzz/, with
# the library's C sources compiled by clang too (the OpenCV shim is not needed by any
# parser). A target whose "needs:" line names a file that is not on this branch yet (the
# scene parser before the renderer lands, say) is skipped with a line saying so.
# Each run starts from the committed seeds in tests/fuzz/corpus/<target>/ (and
# tests/fuzz/corpus/fuzz_<target>/, where a target's author put them) plus the
# inputs earlier runs found (build-fuzz/corpus/<target>/, not committed); crashes, leaks
# and timeouts are written to tests/fuzz/regressions/<target>/ to be committed as
# regression inputs once fixed.
# Output: one line per target, "fuzz TARGET execs N crashes K" (or "fuzz TARGET skipped
# (...)"), then "fuzz total execs N crashes K". FUZZ_TARGETS="a b" limits the targets.
set -u
cd "$(dirname "$0")/.."
mode=${1:-60}
OUT=${FUZZ_BUILD:-build-fuzz}
CLANG=${CLANG:-clang}
SAN="-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=undefined,float-cast-overflow"
# The library flags come from the Makefile (pkg-config and its fallbacks, the x86-64
# baseline only on x86-64); the outer make's job server is not passed on.
makevar() { env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL "${MAKE:-make}" -s --no-print-directory "print-$1"; }
CFLAGS="-std=c11 -O1 -g -fno-omit-frame-pointer -fopenmp $(makevar ARCH_FLAGS) -Wall -Wextra $(makevar CPPFLAGS) $(makevar CAIRO_CFLAGS) -Itests/fuzz -D_GNU_SOURCE"
LIBS="$(makevar CAIRO_LIBS) $(makevar EXR_LIBS) $(makevar PROJ_LIBS) $(makevar LAPACK_LIBS) -lm"
export SPARSELENS_GLASS_CATALOG=${SPARSELENS_GLASS_CATALOG:-lenses/glass.catalog}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

have_libfuzzer() {
  command -v "$CLANG" >/dev/null || return 1
  printf 'int LLVMFuzzerTestOneInput(const char *d, long n) { (void)d; (void)n; return 0; }\n' \
    >"$OUT/probe.c"
  "$CLANG" -fsanitize=fuzzer "$OUT/probe.c" -o "$OUT/probe" 2>/dev/null
}

targets() {
  local f t
  for f in tests/fuzz/fuzz_*.c; do
    t=$(basename "$f" .c); t=${t#fuzz_}
    if [ -n "${FUZZ_TARGETS:-}" ] && ! grep -qw -- "$t" <<<"$FUZZ_TARGETS"; then continue; fi
    echo "$t"
  done
}

# The files a target's "needs:" comment names, missing on this branch (empty: buildable).
missing_needs() {
  local need
  for need in $(sed -n 's/.*needs: //p' "tests/fuzz/fuzz_$1.c"); do
    [ -e "$need" ] || printf '%s ' "$need"
  done
}

# Library objects: every src/<stage>/*.c, rebuilt when it or any header is newer than its object.
build_lib() {
  mkdir -p "$OUT/obj"
  local newest_h src obj pids=() rc=0
  newest_h=$(ls -t include/sparselens/*.h src/*/*.h | head -1)
  for src in src/*/*.c; do
    obj=$OUT/obj/$(basename "$src" .c).o
    if [ ! -f "$obj" ] || [ "$src" -nt "$obj" ] || [ "$newest_h" -nt "$obj" ]; then
      "$CLANG" $CFLAGS $SAN -fsanitize=fuzzer-no-link -c "$src" -o "$obj" &
      pids+=($!)
      if [ ${#pids[@]} -ge 4 ]; then wait "${pids[0]}" || rc=1; pids=("${pids[@]:1}"); fi
    fi
  done
  for p in "${pids[@]}"; do wait "$p" || rc=1; done
  [ $rc -eq 0 ] || { echo "fuzz: building the library with clang failed" >&2; return 1; }
  # Objects of sources that were removed must not linger in the archive.
  for obj in "$OUT"/obj/*.o; do compgen -G "src/*/$(basename "$obj" .o).c" >/dev/null || rm -f "$obj"; done
  rm -f "$OUT/liblens.a"
  ar rcs "$OUT/liblens.a" "$OUT"/obj/*.o
}

build_targets() {
  local t miss bin rc=0
  for t in $(targets); do
    miss=$(missing_needs "$t")
    [ -z "$miss" ] || continue
    bin=$OUT/fuzz_$t
    if [ ! -x "$bin" ] || [ "tests/fuzz/fuzz_$t.c" -nt "$bin" ] || [ "$OUT/liblens.a" -nt "$bin" ] \
       || [ -n "$(find tests/fuzz -name '*.h' -newer "$bin")" ]; then
      "$CLANG" $CFLAGS $SAN -fsanitize=fuzzer "tests/fuzz/fuzz_$t.c" "$OUT/liblens.a" $LIBS \
        -o "$bin" || { echo "fuzz: building fuzz_$t failed" >&2; rc=1; }
    fi
  done
  return $rc
}

mkdir -p "$OUT"
if ! have_libfuzzer; then
  echo "fuzz: clang with libFuzzer not found; nothing built" >&2
  exit 77
fi
build_lib && build_targets || exit 1
[ "$mode" = --build ] && exit 0

if [ "$mode" = --replay ]; then
  status=0
  for t in $(targets); do
    miss=$(missing_needs "$t")
    if [ -n "$miss" ]; then echo "replay $t skipped (not on this branch: $miss)"; continue; fi
    n=0 bad=0
    for f in tests/fuzz/regressions/"$t"/*; do
      [ -f "$f" ] || continue
      n=$((n + 1))
      if ! "$OUT/fuzz_$t" -runs=1 "$f" >"$OUT/replay-$t.log" 2>&1; then
        bad=$((bad + 1)); echo "replay $t: $f still fails:"; grep -m3 -E 'ERROR|runtime error|invariant' "$OUT/replay-$t.log"
      fi
    done
    echo "replay $t inputs $n failing $bad"
    [ $bad -eq 0 ] || status=1
  done
  exit $status
fi

seconds=$mode
case $seconds in ''|*[!0-9]*) echo "usage: tools/fuzz.sh SECONDS | --build | --replay" >&2; exit 2;; esac
total=0 crashes=0
for t in $(targets); do
  miss=$(missing_needs "$t")
  if [ -n "$miss" ]; then echo "fuzz $t skipped (not on this branch: $miss)"; continue; fi
  mkdir -p "$OUT/corpus/$t" "tests/fuzz/regressions/$t" "tests/fuzz/corpus/$t"
  log=$OUT/fuzz-$t.log
  before=$(ls "tests/fuzz/regressions/$t" | wc -l)
  seeds=("tests/fuzz/corpus/$t")
  [ -d "tests/fuzz/corpus/fuzz_$t" ] && seeds+=("tests/fuzz/corpus/fuzz_$t")
  "$OUT/fuzz_$t" -max_total_time="$seconds" -print_final_stats=1 -timeout=60 -rss_limit_mb=2048 \
    -max_len=16384 -artifact_prefix="tests/fuzz/regressions/$t/" \
    "$OUT/corpus/$t" "${seeds[@]}" >"$log" 2>&1
  rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  after=$(ls "tests/fuzz/regressions/$t" | wc -l)
  found=$((after - before))
  [ $rc -eq 0 ] || [ $found -gt 0 ] || found=1 # a failure that left no artifact still counts
  total=$((total + ${execs:-0})) crashes=$((crashes + found))
  echo "fuzz $t execs ${execs:-0} crashes $found"
  if [ $found -gt 0 ]; then grep -m5 -E 'ERROR|runtime error|invariant|Test unit written' "$log" | sed 's/^/  /'; fi
done
echo "fuzz total execs $total crashes $crashes"
[ $crashes -eq 0 ]
