#!/usr/bin/env bash
# make bench: runs every benchmark program (build/bench/bench_*) and the command-level
# benchmarks, prints their "bench NAME VALUE UNIT" lines, adds ratios against the
# baselines measured in the same run, and writes reports/bench.md with the machine and
# the commit. Each program reports medians of several runs itself.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-bin}
BUILD=${BUILD:-build}
out=$(mktemp)
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
trap 'rm -f "$out"' EXIT

for b in "$BUILD"/bench/bench_*; do
  [ -x "$b" ] || continue
  echo "# $(basename "$b")" >&2
  { "$b" || echo "bench $(basename "$b")_failed 1 flag"; } | { grep "^bench " || true; } | tee -a "$out"
done

val() { awk -v k="$1" '$1 == "bench" && $2 == k { print $3; exit }' "$out"; }
ratio() { # NAME NUMERATOR DENOMINATOR: how many times DENOMINATOR's time NUMERATOR's is
  local a b; a=$(val "$2"); b=$(val "$3")
  [ -n "$a" ] && [ -n "$b" ] || return 0
  awk -v n="$1" -v a="$a" -v b="$b" 'BEGIN { printf "bench %s %.2f x\n", n, a / b }' | tee -a "$out"
}
# Speed-ups: baseline time / candidate time (> 1 means faster than the baseline).
ratio ratio_exact_over_poly_batch_fisheye-ii trace_fisheye_ii_ns_per_ray poly_eval_batch_ns_per_ray
ratio ratio_naive_over_batch poly_eval_naive_ns_per_ray poly_eval_batch_ns_per_ray
ratio ratio_scalar_over_batch poly_eval_scalar_ns_per_ray poly_eval_batch_ns_per_ray
ratio ratio_exact_over_poly_batch trace_fisheye-ii_1thread_ns_per_ray poly_eval_batch_ns_per_ray
ratio ratio_trace_1thread_over_all trace_fisheye-ii_1thread_ns_per_ray trace_fisheye-ii_allthreads_ns_per_ray
ratio ratio_render_exact_over_poly_dgauss render_map_exact_dgauss_ns_per_ray render_map_poly_dgauss_ns_per_ray

{
  echo "# Benchmarks"
  echo
  echo "Produced by \`make bench\` (tools/bench.sh) on $(date -u +%Y-%m-%d)."
  echo
  echo "- machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores, $(awk '/MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo)"
  echo "- commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (with local changes)')"
  echo "- compiler: $(${CC:-cc} --version | head -1)"
  echo "- load average (1, 5, 15 min) at the start: $load_start; at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "  (on 2 cores a load above 1 means another job shared the machine: times grow, ratios less so)"
  echo
  echo "Every figure is the median of several runs inside one program; ratios divide two"
  echo "figures of this same run (a ratio above 1 means the second is faster)."
  echo
  echo '```'
  cat "$out"
  echo '```'
} > reports/bench.md
echo "wrote reports/bench.md" >&2
