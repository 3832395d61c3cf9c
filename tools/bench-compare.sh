#!/usr/bin/env bash
# make bench-compare A=REV B=REV: the polynomial kernels of two revisions side by side,
# on this machine, now. One process of bench_poly runs at one of two speeds all through
# it (up to 10% apart, reports/bench.md), and a rebuild that moves code shifts one-ray
# loops by as much, so two `make bench` runs an hour apart cannot tell a 5% change from
# noise. Here both revisions are built, fit the same samples with their own lens-fit,
# and their bench_poly processes alternate (A B A B ...), RUNS of each per system; each
# figure is given as the best and the range over its side's processes, and B's best over
# A's.
#   tools/bench-compare.sh A B [RUNS [RAYS]]    (from the repository root)
# A, B: commits (anything git rev-parse takes), or "." for the working tree as it is
# (as built: BIN and BUILD). RUNS: processes per side and system (default 5);
# RAYS: rays per process (default 20000, as make bench).
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: tools/bench-compare.sh A B [RUNS [RAYS]]" >&2; exit 2; }
revA=$1 revB=$2 runs=${3:-5} rays=${4:-20000}
case $runs in '' | *[!0-9]* | 0) echo "bench-compare: RUNS must be a positive integer, not '$runs'" >&2; exit 2 ;; esac
case $rays in '' | *[!0-9]* | 0) echo "bench-compare: RAYS must be a positive integer, not '$rays'" >&2; exit 2 ;; esac
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# tree REV NAME: a built tree of REV; prints its root
tree() {
  if [ "$1" = . ]; then
    local f
    for f in "${BUILD:-build}/bench/bench_poly" "${BIN:-bin}/lens-trace" "${BIN:-bin}/lens-fit"; do
      [ -x "$f" ] || { echo "bench-compare: $f missing: build the working tree first (make)" >&2; return 1; }
    done
    echo "$PWD"
    return
  fi
  local c dir=$work/$2
  c=$(git rev-parse --verify --quiet "$1^{commit}") || { echo "bench-compare: '$1' is not a commit" >&2; return 1; }
  mkdir -p "$dir"
  git archive "$c" | tar -x -C "$dir"
  echo "bench-compare: building $1 ($(git rev-parse --short "$c")) in $dir" >&2
  env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make -s --no-print-directory -C "$dir" -j2 \
    build/bench/bench_poly bin/lens-trace bin/lens-fit >&2
  echo "$dir"
}
rootA=$(tree "$revA" A) rootB=$(tree "$revB" B)
rootof() { if [ "$1" = A ]; then echo "$rootA"; else echo "$rootB"; fi; }
label() { if [ "$1" = . ]; then echo "working tree"; else git rev-parse --short "$1"; fi; }
binof() { if [ "$1" = "$PWD" ]; then echo "$PWD/${BIN:-bin}"; else echo "$1/bin"; fi; }
benchof() { if [ "$1" = "$PWD" ]; then echo "$PWD/${BUILD:-build}/bench/bench_poly"; else echo "$1/build/bench/bench_poly"; fi; }

# make bench's two systems of fisheye-ii, fitted by each side from the same samples
"$(binof "$rootB")/lens-trace" lenses/fisheye-ii.lens -n 4000 --seed 1 -o "$work/train.txt" 2>/dev/null
optics=out_x,out_y,out_u,out_v,out_eta
for s in A B; do
  bin=$(binof "$(rootof $s)")
  "$bin/lens-fit" -q --terms 40 --degree 11 -o "$work/$s.poly" "$work/train.txt"
  "$bin/lens-fit" -q --terms 40 --degree 11 --frame none --lambda-transform identity -o "$work/$s-nf.poly" "$work/train.txt"
  # (the optical outputs alone: lens-fit warns that the passage is partial, as meant)
  "$bin/lens-fit" -q --terms 40 --degree 11 --outputs $optics -o "$work/$s-5.poly" "$work/train.txt" 2>/dev/null
  "$bin/lens-fit" -q --terms 40 --degree 11 --outputs $optics --frame none --lambda-transform identity \
    -o "$work/$s-5nf.poly" "$work/train.txt" 2>/dev/null
done
# (their terms and coefficients; the meta lines may differ between versions)
grep -v '^meta ' "$work/A.poly" >"$work/A.terms"
grep -v '^meta ' "$work/B.poly" >"$work/B.terms"
cmp -s "$work/A.terms" "$work/B.terms" || echo "bench-compare: note: the two revisions fit different systems" >&2

for k in $(seq "$runs"); do
  echo "bench-compare: round $k of $runs" >&2
  for s in A B; do
    b=$(benchof "$(rootof $s)")
    "$b" "$rays" "$work/$s.poly" "$work/$s-nf.poly" poly 2>/dev/null | grep '^bench ' | sed "s/^/$s /" >> "$work/all"
    "$b" "$rays" "$work/$s-5.poly" "$work/$s-5nf.poly" poly5 2>/dev/null | grep '^bench ' | sed "s/^/$s /" >> "$work/all"
  done
done

echo "A: $revA ($(label "$revA")), B: $revB ($(label "$revB")); $runs processes each, alternating, $rays rays; $(date -u +'%Y-%m-%d %H:%M UTC'), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| figure (ns a ray) | A best | A range | B best | B range | B / A |"
echo "|---|---:|---:|---:|---:|---:|"
for tag in poly poly5; do
  for m in trace batch batch_optics batch_chunks scalar jacobian_batch_optics jacobian_chunks emitted_c emitted_c_batch emitted_c_native emitted_c_batch_native; do
    awk -v k="${tag}_${m}_ns_per_ray" '
      $3 == k { v = $4 + 0; s = $1
                if (!(s in lo) || v < lo[s]) lo[s] = v
                if (!(s in hi) || v > hi[s]) hi[s] = v }
      END { if (("A" in lo) && ("B" in lo))
              printf "| %s | %.2f | %.2f-%.2f | %.2f | %.2f-%.2f | %.3f |\n", k, lo["A"], lo["A"], hi["A"],
                     lo["B"], lo["B"], hi["B"], lo["B"] / lo["A"] }' "$work/all"
  done
done
