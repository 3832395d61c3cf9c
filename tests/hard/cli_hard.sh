#!/usr/bin/env bash
# Hard cases seen from the command line:
#  - lens-eval on rays just outside a system's training domain (x = 10 + 1e-9 where the
#    domain ends at 10): the values are still computed, and the extrapolation is
#    reported on stderr (a count, "outside"/"extrapolat..."), never silent;
#  - the same rays give byte-identical output with OMP_NUM_THREADS=1 and 2 (lens-eval),
#    and with --threads 1 and 2 (lens-trace -, lens-fit).
source "$(dirname "$0")/../cli/lib.sh"
POLY=tests/fuzz/corpus/poly/small.poly   # domain: x, y in [-10, 10], u, v in [-0.5, 0.5]
LENS=lenses/fisheye-aspherical.lens
have() { [ -x "$BIN/lens-$1" ]; }

# rays: a grid inside the domain, plus one ray just outside it in x
n=${SANITIZE:+500}; n=${n:-5000}
awk -v n="$n" 'BEGIN { print "# columns: x y u v lambda"
  for (i = 0; i < n; i++) printf "%.9g %.9g %.9g %.9g %.9g\n", -9 + 18 * (i % 97) / 96, -9 + 18 * (i % 89) / 88,
    -0.4 + 0.8 * (i % 13) / 12, -0.4 + 0.8 * (i % 7) / 6, 0.45 + 0.2 * (i % 5) / 4 }' >"$T/rays.txt"
printf '# columns: x y u v lambda\n1 1 0.1 0.1 0.55\n10.000000001 0 0 0 0.55\n' >"$T/edge.txt"

if have eval; then
  out=$("$BIN/lens-eval" "$POLY" "$T/edge.txt" 2>"$T/err"); rc=$?
  rows=$(grep -v '^#' <<<"$out" | grep -c .)
  if [ $rc -eq 0 ] && [ "$rows" -eq 2 ] && ! grep -v '^#' <<<"$out" | sed -n 2p | grep -qi nan \
     && grep -qiE 'outside|extrapolat' "$T/err" && grep -qw 1 "$T/err"; then
    ok "eval_extrapolation_reported ($(head -1 "$T/err"))"
  else
    fail eval_extrapolation_reported "status $rc, $rows rows, stderr: $(tr '\n' '|' <"$T/err")"
  fi
  OMP_NUM_THREADS=1 "$BIN/lens-eval" "$POLY" "$T/rays.txt" -o "$T/e1.txt" 2>/dev/null
  OMP_NUM_THREADS=2 "$BIN/lens-eval" "$POLY" "$T/rays.txt" -o "$T/e2.txt" 2>/dev/null
  if [ -s "$T/e1.txt" ] && cmp -s "$T/e1.txt" "$T/e2.txt"; then ok "eval_threads_bit_identical ($n rays)"
  else fail eval_threads_bit_identical "outputs with 1 and 2 threads differ (or are empty)"; fi
else
  ok "eval_extrapolation_reported (skipped: lens-eval not built)"
fi

if have trace; then
  "$BIN/lens-trace" "$LENS" - --threads 1 <"$T/rays.txt" >"$T/t1.txt" 2>/dev/null
  "$BIN/lens-trace" "$LENS" - --threads 2 <"$T/rays.txt" >"$T/t2.txt" 2>/dev/null
  if [ -s "$T/t1.txt" ] && cmp -s "$T/t1.txt" "$T/t2.txt"; then ok "trace_threads_bit_identical ($n rays)"
  else fail trace_threads_bit_identical "outputs with --threads 1 and 2 differ (or are empty)"; fi
  m=${SANITIZE:+300}; m=${m:-1500}
  "$BIN/lens-trace" "$LENS" -n "$m" --seed 5 --sampling rear -o "$T/train.txt" 2>/dev/null
  if have fit && [ -s "$T/train.txt" ]; then
    "$BIN/lens-fit" -q --terms 10 --degree 6 --threads 1 "$T/train.txt" -o "$T/f1.poly"
    "$BIN/lens-fit" -q --terms 10 --degree 6 --threads 2 "$T/train.txt" -o "$T/f2.poly"
    if [ -s "$T/f1.poly" ] && cmp -s "$T/f1.poly" "$T/f2.poly"; then ok "fit_threads_bit_identical ($m samples)"
    else fail fit_threads_bit_identical "systems fitted with --threads 1 and 2 differ"; fi
  else
    ok "fit_threads_bit_identical (skipped: lens-fit not built)"
  fi
else
  ok "trace_threads_bit_identical (skipped: lens-trace not built)"
fi
