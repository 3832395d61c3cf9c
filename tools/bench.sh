#!/usr/bin/env bash
# make bench: runs every benchmark program (build/bench/bench_*) and the command-level
# benchmarks, prints their "bench NAME VALUE UNIT" lines, adds ratios against the
# baselines measured in the same run, and writes reports/bench.md with the machine and
# the commit. Each program reports its own best / median figures; notes written by
# hand below the marker line of reports/bench.md survive a new run.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-bin}
BUILD=${BUILD:-build}
out=$(mktemp)
load_start=$(cut -d' ' -f1-3 /proc/loadavg)

work=$(mktemp -d)
trap 'rm -f "$out"; rm -rf "$work"' EXIT
# The default fit of fisheye-ii (README: lens-fit --terms 40 --degree 11, the meridional
# frame except out_u, out_v, and 1/lambda^2), and the same without frame or transform:
# bench_poly measures these, not a stand-in.
"$BIN"/lens-trace lenses/fisheye-ii.lens -n 4000 --seed 1 -o "$work/train.txt"
"$BIN"/lens-fit -q --terms 40 --degree 11 -o "$work/fisheye-ii.poly" "$work/train.txt"
"$BIN"/lens-fit -q --terms 40 --degree 11 --frame none --lambda-transform identity \
  -o "$work/fisheye-ii-noframe.poly" "$work/train.txt"
# The same with the five optical outputs alone (no passage hit points: figures poly5_*).
optics=out_x,out_y,out_u,out_v,out_eta
"$BIN"/lens-fit -q --terms 40 --degree 11 --outputs $optics -o "$work/fisheye-ii-5.poly" "$work/train.txt"
"$BIN"/lens-fit -q --terms 40 --degree 11 --outputs $optics --frame none --lambda-transform identity \
  -o "$work/fisheye-ii-5-noframe.poly" "$work/train.txt"

for b in "$BUILD"/bench/bench_*; do
  [ -x "$b" ] || continue
  echo "# $(basename "$b")" >&2
  runs=("")
  [ "$(basename "$b")" = bench_poly ] &&
    runs=("20000 $work/fisheye-ii.poly $work/fisheye-ii-noframe.poly poly"
          "20000 $work/fisheye-ii-5.poly $work/fisheye-ii-5-noframe.poly poly5")
  for a in "${runs[@]}"; do
    if [ "$(basename "$b")" != bench_poly ]; then
      # shellcheck disable=SC2086
      { "$b" $a || echo "bench $(basename "$b")_failed 1 flag"; } | { grep "^bench " || true; } | tee -a "$out"
      continue
    fi
    # bench_poly in three processes: on this machine one process's kernels run up to
    # 10% slower than the next one's all through it (the same binary and rays; where
    # its memory and code land), which interleaving within a run cannot even out. The
    # report keeps the run of the fastest batch evaluation whole (its ratios are
    # within that run) and gives the range of the main ratios over the three.
    tag=${a##* } best_run="" best_t=inf
    for k in 1 2 3; do
      # shellcheck disable=SC2086
      { "$b" $a || echo "bench $(basename "$b")_failed 1 flag"; } | { grep "^bench " || true; } > "$work/run$k"
      t=$(awk -v k="${tag}_batch_ns_per_ray" '$2 == k { print $3 }' "$work/run$k")
      if [ -n "$t" ] && awk -v a="$t" -v b="$best_t" 'BEGIN { exit !(b == "inf" || a + 0 < b + 0) }'; then
        best_t=$t best_run=$k
      fi
    done
    tee -a "$out" < "$work/run${best_run:-1}"
    for r in trace_over_batch_optics_per_passing_ray scalar_over_batch jacobian_batch_optics_over_batch \
             jacobian_chunks_over_batch_chunks emitted_c_batch_over_batch; do
      cat "$work/run1" "$work/run2" "$work/run3" |
        awk -v k="ratio_${tag}_$r" '$2 == k { v = $3 + 0; if (n++ == 0 || v < lo) lo = v; if (n == 1 || v > hi) hi = v }
          END { if (n) printf "bench %s_over_3_processes %.2f-%.2f x\n", k, lo, hi }'
    done | tee -a "$out"
  done
done

# lens-spot, lens-distort and lens-mtf through the fitted system (Newton on its Jacobian
# from each object-space ray back to the sensor) beside the same command on the lens: CPU
# time (user + system) of the whole command, best of 3 rounds that alternate the two.
cputime() { /usr/bin/time -f '%U %S' -o "$work/t" "$@" > /dev/null 2>&1 || return 1; awk '{ print $1 + $2 }' "$work/t"; }
for cmd in lens-spot lens-distort lens-mtf; do
  best_l=inf best_p=inf
  for _ in 1 2 3; do
    tl=$(cputime "$BIN/$cmd" lenses/fisheye-ii.lens) || tl=inf
    tp=$(cputime "$BIN/$cmd" "$work/fisheye-ii.poly" --lens lenses/fisheye-ii.lens) || tp=inf
    best_l=$(awk -v a="$best_l" -v b="$tl" 'BEGIN { print (b + 0 < a + 0 || a == "inf") ? b : a }')
    best_p=$(awk -v a="$best_p" -v b="$tp" 'BEGIN { print (b + 0 < a + 0 || a == "inf") ? b : a }')
  done
  name=${cmd#lens-}
  printf 'bench %s_fisheye-ii_lens_cpu_s %s s\nbench %s_fisheye-ii_poly_cpu_s %s s\n' "$name" "$best_l" "$name" "$best_p" | tee -a "$out"
done

# A ray through the pipes a user times (lens-trace writing, lens-eval reading and
# writing text), against the kernels above: tools/bench-pipes.sh.
BIN=$BIN tools/bench-pipes.sh 200000 3 2>/dev/null | tee -a "$out"

val() { awk -v k="$1" '$1 == "bench" && $2 == k { print $3; exit }' "$out"; }
ratio() { # NAME NUMERATOR DENOMINATOR: how many times DENOMINATOR's time NUMERATOR's is
  local a b; a=$(val "$2"); b=$(val "$3")
  [ -n "$a" ] && [ -n "$b" ] || return 0
  awk -v n="$1" -v a="$a" -v b="$b" 'BEGIN { printf "bench %s %.2f x\n", n, a / b }' | tee -a "$out"
}
# Speed-ups: baseline time / candidate time (> 1 means faster than the baseline);
# bench_poly prints its own (ratio_*), all between best rounds of one interleaved run.
ratio ratio_trace_1thread_over_all trace_fisheye-ii_1thread_ns_per_ray trace_fisheye-ii_allthreads_ns_per_ray
ratio ratio_render_exact_over_poly_dgauss render_map_exact_dgauss_ns_per_ray render_map_poly_dgauss_ns_per_ray
ratio ratio_spot_poly_over_lens spot_fisheye-ii_poly_cpu_s spot_fisheye-ii_lens_cpu_s
ratio ratio_distort_poly_over_lens distort_fisheye-ii_poly_cpu_s distort_fisheye-ii_lens_cpu_s
ratio ratio_mtf_poly_over_lens mtf_fisheye-ii_poly_cpu_s mtf_fisheye-ii_lens_cpu_s
# Notes written by hand below the marker line of the old report are kept.
marker='<!-- notes: kept by tools/bench.sh -->'
notes=$(awk -v m="$marker" 'f { print } $0 == m { f = 1 }' reports/bench.md 2>/dev/null || true)
{
  echo "# Benchmarks"
  echo
  echo "Produced by \`make bench\` (tools/bench.sh) on $(date -u +'%Y-%m-%d %H:%M UTC')."
  echo
  echo "- machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores, $(awk '/MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo)"
  echo "- commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (with local changes)')"
  echo "- compiler: $(${CC:-cc} --version | head -1)"
  echo "- load average (1, 5, 15 min) at the start: $load_start; at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "  (on 2 cores a load above 1 means another job shared the machine: times grow, ratios less so)"
  echo
  echo "bench_poly times its methods in interleaved rounds and gives each one's best round,"
  echo "median and spread (median / best - 1); it runs in three processes per system, and the"
  echo "figures are those of the process whose batch evaluation was fastest (*_over_3_processes:"
  echo "the range of the main ratios over the three). The other programs give medians of"
  echo "several runs. Ratios divide two figures of one run: ratio_A_over_B is A's time over"
  echo "B's (above 1: B is faster)."
  echo
  echo '```'
  cat "$out"
  echo '```'
  echo
  echo "$marker"
  [ -n "$notes" ] && echo "$notes"
} > reports/bench.md.tmp
mv reports/bench.md.tmp reports/bench.md
echo "wrote reports/bench.md" >&2
