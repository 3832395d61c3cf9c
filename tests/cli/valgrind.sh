#!/usr/bin/env bash
# The command-line tests' key commands under valgrind (memcheck), on small inputs.
# Expectation: no invalid read or write, no use of uninitialised values, no leak of
# definitely lost memory (valgrind --error-exitcode=99 -q --leak-check=full
# --errors-for-leak-kinds=definite, also on error exits), and the
# command's own status is what it would be without valgrind (0 good input, 1 bad input).
# Runs when VALGRIND_TESTS=1, or by default when not under SANITIZE (sanitizer builds do
# not run under valgrind). Commands not built on this branch are skipped.
source "$(dirname "$0")/lib.sh"

if [ -n "${SANITIZE:-}" ] && [ "${VALGRIND_TESTS:-}" != 1 ]; then
  ok "valgrind (skipped: SANITIZE build; VALGRIND_TESTS=1 forces it)"; exit 0; fi
if ! command -v valgrind >/dev/null; then ok "valgrind (skipped: valgrind not installed)"; exit 0; fi

LENS=lenses/simple.lens
POLY=tests/fuzz/corpus/poly/small.poly
# libgomp keeps its thread pool to exit; one thread keeps the report about our code.
export OMP_NUM_THREADS=1
vg() { valgrind -q --error-exitcode=99 --leak-check="$leak" --errors-for-leak-kinds=definite \
         --show-leak-kinds=definite "$@"; }
have() { [ -x "$BIN/lens-$1" ]; }

# vcheck NAME EXPECTED_STATUS CMD...: stdin comes from the caller.
vcheck() {
  local n=$1 want=$2; shift 2
  local leak=full
  # error exits free their memory too (bad_input.sh checks the same under ASan)
  vg "$@" >"$T/out" 2>"$T/err"
  local rc=$?
  if [ $rc -eq 99 ]; then fail "$n" "valgrind errors: $(grep -m4 '==' "$T/err" | tr '\n' '|')"
  elif [ $rc -ne "$want" ]; then fail "$n" "status $rc, expected $want: $(head -2 "$T/err" | tr '\n' '|')"
  else ok "$n"; fi
}

printf '# columns: x y u v lambda\n0 0 0 0 0.5875618\n0.5 -0.3 0.01 0.02 0.5\nnan 1 0 0 0.55\n1 1 -0.02 0.01 0.6\n' >"$T/rays.txt"
printf '85 2 1.5\n' >"$T/bad.lens"

if have info; then
  vcheck valgrind_info 0 "$BIN/lens-info" "$LENS"
  vcheck valgrind_info_bad 1 "$BIN/lens-info" "$T/bad.lens"
else ok "valgrind_info (skipped: lens-info not built)"; fi

if have trace; then
  vcheck valgrind_trace_generate 0 "$BIN/lens-trace" "$LENS" -n 200 --seed 1 --sampling rear -o "$T/train.txt"
  vcheck valgrind_trace_pupil 0 "$BIN/lens-trace" "$LENS" -n 5 --seed 1
  vcheck valgrind_trace_stream 1 "$BIN/lens-trace" "$LENS" - <"$T/rays.txt"
  vcheck valgrind_trace_bad 1 "$BIN/lens-trace" "$T/bad.lens" -n 10
else ok "valgrind_trace (skipped: lens-trace not built)"; fi

if have fit; then
  if [ -s "$T/train.txt" ]; then
    vcheck valgrind_fit 0 "$BIN/lens-fit" -q --terms 6 --degree 3 --threads 1 "$T/train.txt" -o "$T/fit.poly"
  fi
  vcheck valgrind_fit_bad 1 "$BIN/lens-fit" -q "$T/bad.lens"
else ok "valgrind_fit (skipped: lens-fit not built)"; fi

if have eval; then
  vcheck valgrind_eval_stream 1 "$BIN/lens-eval" "$POLY" - <"$T/rays.txt"
  sed 's/^  1 0 0 0 0 1.5/  30 0 0 0 0 1.5/' "$POLY" >"$T/bad.poly"
  vcheck valgrind_eval_bad 1 "$BIN/lens-eval" "$T/bad.poly" "$T/rays.txt"
else ok "valgrind_eval (skipped: lens-eval not built)"; fi

if have spot; then
  vcheck valgrind_spot 0 "$BIN/lens-spot" "$LENS" --rays 20 --wavelengths d
else ok "valgrind_spot (skipped: lens-spot not built)"; fi

if have distort; then
  vcheck valgrind_distort 0 "$BIN/lens-distort" "$LENS" --illum-rays 0 --grid 5 --fields 0,5,10
else ok "valgrind_distort (skipped: lens-distort not built)"; fi
