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
# Targets run side by side, FUZZ_JOBS at once (default: the number of cores). Only the
# library sources the targets use are compiled (found by linking them against the
# archive `make` built), each again only when it or a header it includes changed.
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
# One make run prints them all, a line each.
{ read -r ARCH_FLAGS; read -r CPPFLAGS; read -r CAIRO_CFLAGS; read -r CAIRO_LIBS; read -r EXR_LIBS
  read -r PROJ_LIBS; read -r LAPACK_LIBS; read -r BUILD_DIR; read -r DCONV_LIBS; } < <(env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL \
  "${MAKE:-make}" -s --no-print-directory print-ARCH_FLAGS print-CPPFLAGS print-CAIRO_CFLAGS \
  print-CAIRO_LIBS print-EXR_LIBS print-PROJ_LIBS print-LAPACK_LIBS print-BUILD print-DCONV_LIBS)
CFLAGS="-std=c11 -O1 -g -fno-omit-frame-pointer -fopenmp $ARCH_FLAGS -Wall -Wextra $CPPFLAGS $CAIRO_CFLAGS -Itests/fuzz -D_GNU_SOURCE"
# The number-text shim is C++ (double-conversion, fast_float): the object `make` built
# serves, as the OpenCV shim is not needed at all.
LIBS="$CAIRO_LIBS $EXR_LIBS $PROJ_LIBS $LAPACK_LIBS -lm"
[ -f "$BUILD_DIR/src/base/numtext.o" ] && LIBS="$BUILD_DIR/src/base/numtext.o $DCONV_LIBS -lstdc++ $LIBS"
export SPARSELENS_GLASS_CATALOG=${SPARSELENS_GLASS_CATALOG:-lenses/glass.catalog}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

# The probe is kept: a later run skips it.
have_libfuzzer() {
  [ -x "$OUT/probe" ] && return 0
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

# Whether OBJ must be built again: missing, or older than a file its .d (clang -MMD)
# names, its source among them.
stale() { # OBJ
  [ -f "$1" ] && [ -f "$1.d" ] || return 0
  local dep
  for dep in $(sed -e 's/^[^:]*://' -e 's/\\$//' "$1.d"); do [ "$dep" -nt "$1" ] && return 0; done
  return 1
}

# The library sources the targets use: the linker says which members of the archive that
# `make` built ($BUILD/liblens.a, gcc's, same sources) a program made of all the targets
# pulls in (about a third of the library: the parsers and what they call). Without that
# archive, or when that link fails: every source.
lib_sources() {
  local lib=$BUILD_DIR/liblens.a t objs=() members
  if [ -f "$lib" ]; then
    mkdir -p "$OUT/closure"
    for t in $(targets); do
      [ -z "$(missing_needs "$t")" ] || continue
      ${CC:-cc} $CPPFLAGS -Itests/fuzz -D_GNU_SOURCE -std=c11 -fopenmp -c "tests/fuzz/fuzz_$t.c" \
        -o "$OUT/closure/$t.o" 2>/dev/null && objs+=("$OUT/closure/$t.o")
    done
    printf 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n);\n%s\n' \
      'int main(void) { return LLVMFuzzerTestOneInput(0, 0); }' >"$OUT/closure/main.c"
    if ${CC:-cc} -fopenmp "$OUT/closure/main.c" "${objs[@]}" -Wl,--allow-multiple-definition "$lib" \
         $LIBS -lstdc++ -Wl,-Map="$OUT/closure/map" -o "$OUT/closure/all" 2>/dev/null; then
      # the map's lines "ARCHIVE(MEMBER.o)  FILE (SYMBOL)", the member first
      grep -oE '^[^ ]*liblens\.a\([^)]*\.o\)' "$OUT/closure/map" | sed -E 's/.*\((.*)\.o\)$/\1/' |
        sort -u | while read -r m; do ls src/*/"$m".c 2>/dev/null; done
      return
    fi
  fi
  ls src/*/*.c
}

# Library objects, each rebuilt when its source or a header it includes changed.
build_lib() { # SOURCES...
  mkdir -p "$OUT/obj"
  local src obj pids=() rc=0 built=0
  for src in "$@"; do
    obj=$OUT/obj/$(basename "$src" .c).o
    if stale "$obj"; then
      "$CLANG" $CFLAGS $SAN -fsanitize=fuzzer-no-link -MMD -MF "$obj.d" -c "$src" -o "$obj" &
      pids+=($!) built=1
      if [ ${#pids[@]} -ge 4 ]; then wait "${pids[0]}" || rc=1; pids=("${pids[@]:1}"); fi
    fi
  done
  for p in "${pids[@]}"; do wait "$p" || rc=1; done
  [ $rc -eq 0 ] || { echo "fuzz: building the library with clang failed" >&2; return 1; }
  # Objects of sources that were removed must not linger in the archive.
  for obj in "$OUT"/obj/*.o; do
    [ -e "$obj" ] || continue
    compgen -G "src/*/$(basename "$obj" .o).c" >/dev/null || { rm -f "$obj" "$obj.d"; built=1; }
  done
  [ $built = 0 ] && [ -f "$OUT/liblens.a" ] && return 0
  rm -f "$OUT/liblens.a"
  ar rcs "$OUT/liblens.a" "$OUT"/obj/*.o
}

build_targets() {
  local t miss bin rc=0
  for t in $(targets); do
    miss=$(missing_needs "$t")
    [ -z "$miss" ] || continue
    bin=$OUT/fuzz_$t
    if stale "$bin" || [ "$OUT/liblens.a" -nt "$bin" ]; then
      "$CLANG" $CFLAGS $SAN -fsanitize=fuzzer -MMD -MF "$bin.d" "tests/fuzz/fuzz_$t.c" \
        "$OUT/liblens.a" $LIBS -o "$bin" 2>"$OUT/link-$t.log" || { rc=1; cat "$OUT/link-$t.log" >&2; }
    fi
  done
  return $rc
}

# The sources the targets need; when a target does not link with them (the archive
# `make` built was older than the sources), with every source.
build() {
  build_lib $(lib_sources) && build_targets 2>/dev/null && return 0
  echo "fuzz: building with every library source" >&2
  build_lib src/*/*.c && build_targets
}

mkdir -p "$OUT"
if ! have_libfuzzer; then
  echo "fuzz: clang with libFuzzer not found; nothing built" >&2
  exit 77
fi
build || exit 1
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
# One target's run: its report line (and what a crash said) in $OUT/result-TARGET.
fuzz_one() { # TARGET
  local t=$1 log=$OUT/fuzz-$1.log before after found execs rc seeds
  mkdir -p "$OUT/corpus/$t" "tests/fuzz/regressions/$t" "tests/fuzz/corpus/$t"
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
  echo "fuzz $t execs ${execs:-0} crashes $found"
  if [ $found -gt 0 ]; then grep -m5 -E 'ERROR|runtime error|invariant|Test unit written' "$log" | sed 's/^/  /'; fi
}

# The targets run side by side, FUZZ_JOBS at once (default: the cores); each gets its
# SECONDS, and the reports come out in the order of the targets.
jobs=${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 2)}
running=0 ran=()
for t in $(targets); do
  miss=$(missing_needs "$t")
  if [ -n "$miss" ]; then echo "fuzz $t skipped (not on this branch: $miss)"; continue; fi
  fuzz_one "$t" >"$OUT/result-$t" &
  ran+=("$t") running=$((running + 1))
  if [ $running -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
done
wait
total=0 crashes=0
for t in "${ran[@]}"; do
  cat "$OUT/result-$t"
  read -r _ _ _ execs _ found <"$OUT/result-$t"
  total=$((total + execs)) crashes=$((crashes + found))
done
echo "fuzz total execs $total crashes $crashes"
[ $crashes -eq 0 ]
