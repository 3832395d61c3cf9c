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

# quietly CMD...: CMD with its stderr kept aside, shown (and the script stopped) if it fails
quietly() {
  "$@" 2>"$work/err" || { echo "bench-compare: failed: $*" >&2; cat "$work/err" >&2; exit 1; }
}

# tree REV NAME: a built tree of REV; prints its bin directory and its bench_poly, one a line
tree() {
  if [ "$1" = . ]; then
    local bin bench
    bin=$(realpath -m "${BIN:-bin}") bench=$(realpath -m "${BUILD:-build}/bench/bench_poly")
    for f in "$bench" "$bin/lens-trace" "$bin/lens-fit"; do
      [ -x "$f" ] || { echo "bench-compare: $f missing: build the working tree first (make)" >&2; return 1; }
    done
    printf '%s\n%s\n' "$bin" "$bench"
    return
  fi
  local c dir=$work/$2
  c=$(git rev-parse --verify --quiet "$1^{commit}") || { echo "bench-compare: '$1' is not a commit" >&2; return 1; }
  mkdir -p "$dir" || return 1
  git archive "$c" | tar -x -C "$dir" || { echo "bench-compare: cannot unpack $1" >&2; return 1; }
  echo "bench-compare: building $1 ($(git rev-parse --short "$c")) in $dir" >&2
  env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make -s --no-print-directory -C "$dir" -j2 \
    build/bench/bench_poly bin/lens-trace bin/lens-fit >&2 || { echo "bench-compare: building $1 failed" >&2; return 1; }
  printf '%s\n%s\n' "$dir/bin" "$dir/build/bench/bench_poly"
}
treeA=$(tree "$revA" A)
treeB=$(tree "$revB" B)
binof() { if [ "$1" = A ]; then sed -n 1p <<<"$treeA"; else sed -n 1p <<<"$treeB"; fi; }
benchof() { if [ "$1" = A ]; then sed -n 2p <<<"$treeA"; else sed -n 2p <<<"$treeB"; fi; }
label() { if [ "$1" = . ]; then echo "working tree"; else git rev-parse --short "$1"; fi; }

# make bench's two systems of fisheye-ii, fitted by each side from the same samples
quietly "$(binof B)/lens-trace" lenses/fisheye-ii.lens -n 4000 --seed 1 -o "$work/train.txt"
optics=out_x,out_y,out_u,out_v,out_eta
for s in A B; do
  bin=$(binof $s)
  quietly "$bin/lens-fit" -q --terms 40 --degree 11 -o "$work/$s.poly" "$work/train.txt"
  quietly "$bin/lens-fit" -q --terms 40 --degree 11 --frame none --lambda-transform identity -o "$work/$s-nf.poly" "$work/train.txt"
  # (the optical outputs alone: lens-fit warns that the passage is partial, as meant)
  quietly "$bin/lens-fit" -q --terms 40 --degree 11 --outputs $optics -o "$work/$s-5.poly" "$work/train.txt"
  quietly "$bin/lens-fit" -q --terms 40 --degree 11 --outputs $optics --frame none --lambda-transform identity \
    -o "$work/$s-5nf.poly" "$work/train.txt"
done
# (their terms and coefficients; the meta lines may differ between versions)
grep -v '^meta ' "$work/A.poly" >"$work/A.terms"
grep -v '^meta ' "$work/B.poly" >"$work/B.terms"
cmp -s "$work/A.terms" "$work/B.terms" || echo "bench-compare: note: the two revisions fit different systems" >&2

for k in $(seq "$runs"); do
  echo "bench-compare: round $k of $runs" >&2
  for s in A B; do
    b=$(benchof $s)
    quietly "$b" "$rays" "$work/$s.poly" "$work/$s-nf.poly" poly >"$work/run"
    quietly "$b" "$rays" "$work/$s-5.poly" "$work/$s-5nf.poly" poly5 >>"$work/run"
    grep '^bench ' "$work/run" | sed "s/^/$s /" >>"$work/all"
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
