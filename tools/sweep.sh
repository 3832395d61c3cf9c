#!/usr/bin/env bash
# One lens's accuracy-against-time sweep (make reports, tools/reports.mk).
#   tools/sweep.sh LENS OUTDIR [full|reduced]
# Writes OUTDIR/sweep.tsv, one row per fitted system, with the held-out error on the
# outer pupil (position RMS in mm, direction RMS in arcminutes; the 99th percentile of
# the x and y errors, combined as sqrt(p99_x^2 + p99_y^2), and the largest x or y error,
# which show when a few rays carry the RMS), the training error,
# the evaluation time per ray (batch, one thread), the fit time, and the exact
# tracer's time per ray on the same rays in the same run: the best of interleaved
# rounds, with the spread of the rounds (median / best - 1, in %; see
# bench/bench_system.c). Every row names its .poly,
# its report files and the command that made it, so each figure can be traced back.
set -euo pipefail
lens=$1 out=$2 mode=${3:-full}
BIN=${BIN:-bin} BUILD=${BUILD:-build}
name=$(basename "$lens" .lens)
mkdir -p "$out/points"
if [ "$mode" = reduced ]; then ntrain=4000 ntest=4000; else ntrain=30000 ntest=20000; fi
d=0.5875618

# Rays: the first N passing rays of a seed are a prefix of the first M > N, so the
# sample-size sweep reuses one training file.
[ -s "$out/train.txt" ] ||
  "$BIN"/lens-trace "$lens" -n $ntrain --seed 1 -o "$out/train.txt"
[ -s "$out/test.txt" ] || "$BIN"/lens-trace "$lens" -n $ntest --seed 2 -o "$out/test.txt"
[ -s "$out/train-d.txt" ] || "$BIN"/lens-trace "$lens" -n $((ntrain / 2)) --seed 3 --lambda $d -o "$out/train-d.txt"
[ -s "$out/test-d.txt" ] || "$BIN"/lens-trace "$lens" -n $((ntest / 2)) --seed 4 --lambda $d -o "$out/test-d.txt"
subset() { # N FILE -> first N rows with the header
  awk -v n="$1" '/^#/ { print; next } k < n { print; k++ }' "$2"
}

# sweep points: kind terms degree samples parts lambda
points() {
  if [ "$mode" = reduced ]; then
    for t in 5 10 20 40; do echo "terms $t 7 4000 1 1"; done
    for g in 3 5 7; do echo "degree 20 $g 4000 1 1"; done
    echo "parts 20 7 4000 3 1"
    echo "mono 20 7 2000 1 0"
    return
  fi
  for t in 5 10 20 40 80; do echo "terms $t 11 15000 1 1"; done
  for g in 3 5 7 9 13; do echo "degree 40 $g 15000 1 1"; done
  for n in 1000 4000 30000; do echo "samples 40 11 $n 1 1"; done
  echo "parts 40 11 15000 4 1"
  echo "mono 40 11 15000 1 0"
}

row() { # error report -> pos_rms_mm dir_rms_arcmin pos_p99_mm pos_max_mm
  awk '$1 == "out_x_mm" && !x { x = $3; px = $5; mx = $6 } $1 == "out_y_mm" && !y { y = $3; py = $5; my = $6 }
       $1 == "out_u_arcmin" && !u { u = $3 } $1 == "out_v_arcmin" && !v { v = $3 }
       /^$/ { exit }
       END { printf "%.6g %.6g %.6g %.6g\n", sqrt(x * x + y * y), sqrt(u * u + v * v), sqrt(px * px + py * py),
             (mx > my ? mx : my) }' "$1"
}

# Fits and error reports first; the times afterwards, all systems of the lens in one run
# of bench_system (interleaved rounds with the exact tracer: see its header).
printf '' > "$out/times.args"
{
  points | while read -r kind t g n p l; do
    id="$kind-t$t-d$g-n$n-p$p-l$l"
    poly="$out/points/$id.poly"
    if [ "$l" = 1 ]; then train="$out/train.txt" test="$out/test.txt" inputs=x,y,u,v,lambda
    else train="$out/train-d.txt" test="$out/test-d.txt" inputs=x,y,u,v; fi
    # Partitioned points ask for a tolerance one polynomial cannot meet, so the fitter
    # splits the ray space (it only partitions where a tolerance is missed).
    tol=""
    [ "$p" -gt 1 ] && tol="--tolerance out_x=0.0004,out_y=0.0004"
    cmd="lens-fit --terms $t --degree $g --parts $p $tol --inputs $inputs --lens $name -o $id.poly (first $n rays of $(basename "$train"))"
    subset "$n" "$train" > "$out/points/$id.train"
    "$BIN"/lens-fit --terms $t --degree $g --parts $p $tol --inputs $inputs --lens "$name" \
        -o "$poly" "$out/points/$id.train" 2> "$out/points/$id.fitlog"
    fit_s=$(sed -n 's/.*fit time \([0-9.e+-]*\) s.*/\1/p' "$out/points/$id.fitlog" | tail -1)
    "$BIN"/lens-eval "$poly" --report "$test" > "$out/points/$id.test.report" 2>/dev/null || true
    "$BIN"/lens-eval "$poly" --report "$out/points/$id.train" > "$out/points/$id.train.report" 2>/dev/null || true
    rm -f "$out/points/$id.train"
    read -r tpos tdir tp99 tmax < <(row "$out/points/$id.test.report")
    read -r rpos _ _ _ < <(row "$out/points/$id.train.report")
    printf -- '--samples %s --poly %s\n' "$test" "$poly" >> "$out/times.args"
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$kind" "$t" "$g" "$n" "$p" "$l" \
      "$tpos" "$tdir" "$rpos" "${fit_s:-nan}" "points/$id.poly" "$cmd" "$tp99" "$tmax"
  done
} > "$out/rows.tmp"
# shellcheck disable=SC2046
"$BUILD"/bench/bench_system --samples "$out/test.txt" --lens "$lens" $(cat "$out/times.args") > "$out/times.txt"
{
  printf 'lens\tkind\tterms\tdegree\tsamples\tparts\tlambda\ttest_pos_rms_mm\ttest_dir_rms_arcmin\ttest_pos_p99_mm\ttest_pos_max_mm\ttrain_pos_rms_mm\teval_ns_per_ray\texact_ns_per_ray\teval_spread_pct\texact_spread_pct\tfit_s\tsystem\tcommand\n'
  awk -F'\t' -v OFS='\t' -v dir="$out/" '
    FNR == NR && $0 ~ /^exact / { split($0, e, " "); exact = e[2]; espread = e[4]; next }
    FNR == NR && $0 ~ /^system / { split($0, q, " "); p = q[2]; sub("^" dir, "", p); best[p] = q[3]; spread[p] = q[5]; next }
    FNR == NR { next }
    { b = ($12 in best) ? best[$12] : "nan"; sp = ($12 in spread) ? spread[$12] : "nan"
      print $1, $2, $3, $4, $5, $6, $7, $8, $9, $14, $15, $10, b, exact, sp, espread, $11, $12, $13 }' \
    "$out/times.txt" "$out/rows.tmp"
} > "$out/sweep.tsv.tmp"
rm -f "$out/rows.tmp" "$out/times.args"
mv "$out/sweep.tsv.tmp" "$out/sweep.tsv"
echo "sweep: $name: $(($(wc -l < "$out/sweep.tsv") - 1)) points in $out/sweep.tsv" >&2
