#!/usr/bin/env bash
# What the passage costs in time and what it buys (reports/vignetting.md): one
# lens fitted as the README fits it, with each lens-fit --passage-tolerance in turn; per
# setting the passage's terms, the batch evaluation (bench_poly's batch_optics: the
# optical outputs written, every pass circle tested) beside the exact tracer per passing
# ray, and the passage's disagreement with the lens as shares of the light the lens
# passes (lens-eval --report on a --sampling full test set, as tools/passage-report.sh).
# The optical outputs are the same fit in every row. The settings are timed in turn,
# one bench_poly process each, ROUNDS rounds (default 3), and each keeps its fastest:
# one process runs at one of the machine's two speeds all through it (reports/bench.md),
# and a setting timed only in a slow spell had looked slower than one with more terms.
# usage: tools/passage-cost.sh [LENS [N_TRAIN [N_TEST [TOLERANCE...]]]]   (from the repository root)
set -euo pipefail
B=${BIN:-bin}
BUILD=${BUILD:-build}
lens=${1:-lenses/fisheye-ii.lens}; ntrain=${2:-20000}; ntest=${3:-200000}
shift 3 2>/dev/null || shift $#
tols=("$@"); [ ${#tols[@]} -gt 0 ] || tols=(0.0003 0.001 0.003 0.01 0.03)
[ -x "$BUILD/bench/bench_poly" ] || { echo "passage-cost: $BUILD/bench/bench_poly missing (make bench builds it)" >&2; exit 1; }
D=$(mktemp -d); trap 'rm -rf "$D"' EXIT
# quietly CMD...: CMD with its stderr kept aside, shown (and the script stopped) if it fails
quietly() { "$@" 2>"$D/err" || { echo "passage-cost: failed: $*" >&2; cat "$D/err" >&2; exit 1; }; }
quietly "$B/lens-trace" "$lens" -n "$ntrain" -o "$D/train.txt"
quietly "$B/lens-trace" "$lens" -n "$ntest" --seed 2 --sampling full -o "$D/test.txt"
echo "Lens $(basename "$lens" .lens); training: lens-trace -n $ntrain (seed 1), test: -n $ntest --sampling full --seed 2."
echo
echo "| --passage-tolerance | passage terms | batch ns a ray | exact tracer over batch, per passing ray | false pass | false block | disagree | worst 1 mm ring |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
ROUNDS=${ROUNDS:-3}
# the systems and their light first; then the timings in rounds, every setting once a
# round (one process each), so that the machine's slow and fast spells fall on all alike
for k in "${!tols[@]}"; do
  t=${tols[$k]}
  echo "passage-cost: --passage-tolerance $t" >&2
  quietly "$B/lens-fit" -q --passage-tolerance "$t" -o "$D/sys$k.poly" "$D/train.txt"
  quietly "$B/lens-eval" "$D/sys$k.poly" "$D/test.txt" --report >"$D/rep$k.txt"
  best_t[$k]=inf ratio[$k]=""
done
for round in $(seq "$ROUNDS"); do
  echo "passage-cost: timing round $round of $ROUNDS" >&2
  for k in "${!tols[@]}"; do
    quietly "$BUILD/bench/bench_poly" 20000 "$D/sys$k.poly" "$D/sys$k.poly" p >"$D/bench.txt"
    tt=$(awk '$2 == "p_batch_optics_ns_per_ray" { print $3 }' "$D/bench.txt")
    if awk -v a="$tt" -v b="${best_t[$k]}" 'BEGIN { exit !(b == "inf" || a + 0 < b + 0) }'; then
      best_t[$k]=$tt
      ratio[$k]=$(awk '$2 == "ratio_p_trace_over_batch_optics_per_passing_ray" { print $3 }' "$D/bench.txt")
    fi
  done
done
for k in "${!tols[@]}"; do
  terms=$(awk '$1 == "meta" && $2 ~ /^fit_(ap|s[0-9]+)_[xy]$/ { s += $4 } END { print s + 0 }' "$D/sys$k.poly")
  awk -v t="${tols[$k]}" -v terms="$terms" -v ns="${best_t[$k]}" -v ratio="${ratio[$k]}" '
    $1 == "false_block" { fb = $2 } $1 == "false_pass" { fp = $2 }
    $1 == "light_false_pass" { lp = $2 } $1 == "light_false_block" { lb = $2 }
    $1 == "light_disagree" { ld = $2 } $1 == "worst_ring_mm" { wr = $2 } $1 == "worst_ring_disagree" { wd = $2 }
    END { printf "| %s | %d | %.1f | %.2fx | %.3f%% (%d) | %.3f%% (%d) | **%.3f%%** | %.2f%% at %d-%d mm |\n",
          t, terms, ns, ratio, 100 * lp, fp, 100 * lb, fb, 100 * ld, 100 * wd, wr, wr + 1 }' "$D/rep$k.txt"
done
