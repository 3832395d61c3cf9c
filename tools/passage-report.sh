#!/usr/bin/env bash
# Passage of the default pipeline on every shipped lens (reports/vignetting.md): a
# system fitted as the README fits one (lens-trace LENS -n N | lens-fit), measured on a
# test set over the whole ray space (--sampling full, every direction that can pass),
# as shares of the light the lens passes (lens-eval --report).
# usage: tools/passage-report.sh [N_TRAIN [N_TEST [LENS...]]]   (from the repository root)
set -eu
B=${BIN:-bin}
ntrain=${1:-20000}; ntest=${2:-200000}; shift 2 2>/dev/null || shift $#
lenses=("$@"); [ ${#lenses[@]} -gt 0 ] || lenses=(lenses/*.lens)
D=$(mktemp -d); trap 'rm -rf "$D"' EXIT
echo "| lens | passage | clip surfaces (circles) | outputs | lens passes | false pass | false block | disagree | worst 1 mm ring |"
echo "|---|---|---|---|---|---|---|---|---|"
for L in "${lenses[@]}"; do
  n=$(basename "$L" .lens)
  "$B/lens-trace" "$L" -n "$ntrain" -o "$D/train.txt" 2>/dev/null
  "$B/lens-fit" -q -o "$D/sys.poly" "$D/train.txt" 2>"$D/fit.err" || { echo "| $n | fit failed: $(head -1 "$D/fit.err") |"; continue; }
  "$B/lens-trace" "$L" -n "$ntest" --seed 2 --sampling full 2>/dev/null |
    "$B/lens-eval" "$D/sys.poly" --report 2>/dev/null >"$D/rep.txt"
  # the system's circles on clip surfaces, and those lens-fit dropped (they decided nothing)
  clip=$(awk '$1 == "pass" && $2 ~ /^s[0-9]+_x$/ { printf "%s ", substr($2, 1, length($2) - 2) }' "$D/sys.poly")
  dropped=$(sed -n 's/^meta fit_dropped_circles //p' "$D/sys.poly" | grep -o 's[0-9]* (' | tr -d ' (' | tr '\n' ' ')
  [ -z "$dropped" ] || clip="${clip}(dropped ${dropped% }) "
  awk -v n="$n" -v clip="${clip:-none}" -v ps="$(sed -n 's/^meta passage //p' "$D/sys.poly" | cut -c1-7)" \
      -v nout="$(awk '$1 == "outputs" { print NF - 1 }' "$D/sys.poly")" '
    $1 == "both_pass" { bp = $2 } $1 == "false_block" { fb = $2 } $1 == "false_pass" { fp = $2 }
    $1 == "light_false_pass" { lp = $2 } $1 == "light_false_block" { lb = $2 }
    $1 == "light_disagree" { ld = $2 } $1 == "worst_ring_mm" { wr = $2 } $1 == "worst_ring_disagree" { wd = $2 }
    END { printf "| %s | %s | %s| %d | %d | %.3f%% (%d) | %.3f%% (%d) | **%.3f%%** | %.2f%% at %d-%d mm |\n",
          n, ps, clip, nout, bp + fb, 100 * lp, fp, 100 * lb, fb, 100 * ld, 100 * wd, wr, wr + 1 }' "$D/rep.txt"
done
