#!/usr/bin/env bash
# What a ray costs through the pipes a user times: lens-trace writing a sample file and
# lens-eval reading one and writing its outputs, on fisheye-ii with its default columns,
# in wall time per ray, with 1 and 2 threads for lens-trace. The kernels inside them
# (the exact tracer, the system's batch evaluation) are make bench's. Best of ROUNDS,
# the commands interleaved.
#
#   tools/bench-pipes.sh [RAYS] [ROUNDS]     prints "bench NAME VALUE UNIT" lines
#   tools/bench-pipes.sh --report [RAYS] [ROUNDS]   also writes reports/pipes.md
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-bin}
report=""
[ "${1:-}" = --report ] && { report=reports/pipes.md; shift; }
N=${1:-200000}
ROUNDS=${2:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
L=lenses/fisheye-ii.lens

"$BIN"/lens-trace $L -n 4000 --seed 1 -q -o "$work/train.txt"
"$BIN"/lens-fit -q -o "$work/sys.poly" "$work/train.txt"
"$BIN"/lens-trace $L -n "$N" --seed 2 -q -o "$work/rays.txt" --threads 1
bytes=$(wc -c <"$work/rays.txt")

wall() { # seconds of wall time of a command (stdout to /dev/null)
  local s e
  s=$(date +%s.%N)
  "$@" >/dev/null 2>&1 || return 1
  e=$(date +%s.%N)
  awk -v s="$s" -v e="$e" 'BEGIN { printf "%.4f", e - s }'
}
best() { awk -v a="$1" -v b="$2" 'BEGIN { print (a == "" || b + 0 < a + 0) ? b : a }'; }
t1="" t2="" te="" tn="" tc=""
for _ in $(seq "$ROUNDS"); do
  t1=$(best "$t1" "$(wall "$BIN"/lens-trace $L -n "$N" --seed 2 -q --threads 1 -o "$work/o1.txt")")
  t2=$(best "$t2" "$(wall "$BIN"/lens-trace $L -n "$N" --seed 2 -q --threads 2 -o "$work/o2.txt")")
  te=$(best "$te" "$(wall "$BIN"/lens-eval "$work/sys.poly" "$work/rays.txt")")
  # the reading alone: lens-eval writing nothing but its summary
  tn=$(best "$tn" "$(wall "$BIN"/lens-eval "$work/sys.poly" --report "$work/rays.txt")")
  # the fixed cost of lens-trace (pilot, pupil table): 1 ray
  tc=$(best "$tc" "$(wall "$BIN"/lens-trace $L -n 1 --seed 2 -q --threads 1 -o "$work/o0.txt")")
done
cmp -s "$work/o1.txt" "$work/o2.txt" || echo "bench-pipes: 1 and 2 threads wrote different files" >&2
awk -v n="$N" -v t1="$t1" -v t2="$t2" -v te="$te" -v tn="$tn" -v tc="$tc" -v bytes="$bytes" 'BEGIN {
  printf "bench pipe_trace_fisheye-ii_1thread_us_per_ray %.3f us\n", 1e6 * (t1 - tc) / n
  printf "bench pipe_trace_fisheye-ii_2threads_us_per_ray %.3f us\n", 1e6 * (t2 - tc) / n
  printf "bench pipe_trace_fixed_s %.3f s\n", tc
  printf "bench pipe_eval_fisheye-ii_us_per_ray %.3f us\n", 1e6 * te / n
  printf "bench pipe_eval_report_only_us_per_ray %.3f us\n", 1e6 * tn / n
  printf "bench pipe_sample_bytes_per_ray %.1f B\n", bytes / n
  printf "bench ratio_pipe_trace_1thread_over_2threads %.2f x\n", (t1 - tc) / (t2 - tc)
}' | tee "$work/out"

if [ -n "$report" ]; then
  {
    echo "# What a ray costs through the pipes"
    echo
    echo "Produced by \`tools/bench-pipes.sh --report $N $ROUNDS\` on $(date -u +'%Y-%m-%d %H:%M UTC'),"
    echo "commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown), $(nproc) cores,"
    echo "load at the end $(cut -d' ' -f1-3 /proc/loadavg). Wall time, best of $ROUNDS rounds interleaved;"
    echo "fisheye-ii, $N rays, the default columns (the passage columns included)."
    echo
    echo '```'
    cat "$work/out"
    echo '```'
    echo
    echo "- pipe_trace: lens-trace -n $N -o FILE, less its fixed cost (pipe_trace_fixed_s:"
    echo "  the pilot and the pupil table, measured with one ray), per ray. Set it beside"
    echo "  trace_fisheye-ii_1thread_ns_per_ray of reports/bench.md (the exact tracer alone) for"
    echo "  what the text costs."
    echo "- pipe_eval: lens-eval SYSTEM FILE > /dev/null, per ray: reading the rows, evaluating"
    echo "  the system, writing its outputs; report_only is lens-eval --report, which writes no"
    echo "  rows but gathers the error and passage tables. Beside poly_batch_ns_per_ray of"
    echo "  reports/bench.md (the evaluation alone)."
    echo "- numbers are written as the shortest text that reads back (%.15g, else %.17g, byte"
    echo "  for byte) by double-conversion, and read by fast_float (src/base/numtext.cpp)"
    echo "- the 1- and 2-thread files are compared byte for byte (a message says when they differ)."
  } >"$report"
  echo "bench-pipes: wrote $report" >&2
fi
