#!/usr/bin/env bash
# Time and peak memory of each reader against input size (reports/robustness.md):
# inputs 1x, 4x, 16x, one run each, /usr/bin/time -f "%e %M". Usage: tools/robustness-figures.sh
set -u
cd "$(dirname "$0")/.."
BIN=${BIN:-bin}
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
measure() { # measure LABEL SIZE_BYTES CMD...: prints a table row
  local label=$1 size=$2; shift 2
  local r; /usr/bin/time -o "$T/time" -f "%e %M" "$@" >/dev/null 2>/dev/null; r=$(tail -1 "$T/time")
  printf '| %s | %s | %s s | %s MB |\n' "$label" "$(awk -v b="$size" 'BEGIN{printf "%.2f MB", b/1048576}')" \
    "${r% *}" "$(awk -v k="${r#* }" 'BEGIN{printf "%.1f", k/1024}')"
}
echo "### .poly (terms of one output, lens-eval of one row)"
echo "| terms | file | time | peak RSS |"; echo "|---|---|---|---|"
printf '# columns: a b c d e f\n0.1 0.2 0.3 0.1 0.2 0.1\n' >"$T/in.txt"
for n in 10000 40000 160000; do
  python3 - "$n" >"$T/p.poly" <<'PY'
import sys, itertools
n = int(sys.argv[1]); w = sys.stdout.write
w("lens-poly 1\nlens big\ninputs a b c d e f\noutputs o\n")
for v in "abcdef": w(f"scaling {v} 0 1 -1 1\n")
w(f"part 0 inf\noutput o {n}\n")
def gen():
    for deg in range(25):
        for comb in itertools.combinations_with_replacement(range(6), deg):
            e = [0] * 6
            for c in comb: e[c] += 1
            yield e
for k, e in zip(range(n), gen()): w(" ".join(map(str, e)) + f" {1e-6 * (k % 7 + 1)}\n")
w("end\n")
PY
  measure "$n" "$(stat -c %s "$T/p.poly")" "$BIN/lens-eval" "$T/p.poly" "$T/in.txt"
done
echo; echo "### .poly meta lines (hashed duplicate check)"
echo "| meta lines | file | time | peak RSS |"; echo "|---|---|---|---|"
for n in 50000 200000 800000; do
  { printf 'lens-poly 1\ninputs x\noutputs o\n'; seq -f 'meta k%.0f value' 1 "$n"; printf 'part 0 inf\noutput o 1\n0 1\nend\n'; } >"$T/m.poly"
  printf '# columns: x\n1\n' >"$T/x.txt"
  measure "$n" "$(stat -c %s "$T/m.poly")" "$BIN/lens-eval" "$T/m.poly" "$T/x.txt"
done
echo; echo "### text glass catalog (glasses, lens-info of a lens naming one)"
echo "| glasses | file | time | peak RSS |"; echo "|---|---|---|---|"
for n in 50000 200000 800000; do
  seq -f 'G%.0f sellmeier1 1.03961212 0.00600069867 0.231792344 0.0200179144 1.01046945 103.560653 0.3 2.5 1.5168 64.17' 1 "$n" >"$T/g.catalog"
  measure "$n" "$(stat -c %s "$T/g.catalog")" "$BIN/lens-info" --glass-catalog "$T/g.catalog" lenses/lensbaby.lens
done
echo; echo "### native .lens (surfaces, lens-info --format lens)"
echo "| surfaces | file | time | peak RSS |"; echo "|---|---|---|---|"
for n in 2000 8000 32000; do
  { echo "# sensor: 36x24"; for i in $(seq "$n"); do echo "inf 0.5 1.5/60 20"; echo "inf 0.5 air 20"; done; echo "inf 10 stop 10"; } >"$T/l.lens"
  measure "$((2 * n + 1))" "$(stat -c %s "$T/l.lens")" "$BIN/lens-info" --format lens "$T/l.lens"
done
echo; echo "### samples stream (rows through lens-trace -)"
echo "| rows | stream | time | peak RSS |"; echo "|---|---|---|---|"
for n in 25000 100000 400000; do
  "$BIN/lens-trace" lenses/simple.lens -n "$n" --seed 1 2>/dev/null |
    awk '/^# columns/ { print "# columns: x y u v lambda"; next } /^#/ { next } { print $1, $2, $3, $4, $5 }' >"$T/s.txt"
  measure "$n" "$(stat -c %s "$T/s.txt")" "$BIN/lens-trace" lenses/simple.lens - <"$T/s.txt"
done
echo; echo "### hostile shapes refused at once"
echo "| input | file | time | peak RSS |"; echo "|---|---|---|---|"
{ printf 'lens-poly 1\ninputs'; seq -f ' i%.0f' 1 1000000 | tr -d '\n'; echo; } >"$T/names.poly"
measure "inputs line of 10^6 names" "$(stat -c %s "$T/names.poly")" "$BIN/lens-eval" "$T/names.poly" "$T/x.txt"
head -c 200000000 /dev/zero | tr '\0' 1 >"$T/endless.txt"
measure "one 200 MB line (samples)" 200000000 "$BIN/lens-fit" "$T/endless.txt"
measure "one 200 MB line (.lens)" 200000000 "$BIN/lens-info" --lens-format lens "$T/endless.txt"
