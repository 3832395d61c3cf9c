#!/usr/bin/env bash
# make realworld: the user's pipeline on every prescription of lenses/realworld (files
# nobody here wrote), one lens after another as a user would run it, and
# reports/realworld.md from the results (tools/report_realworld.py).
#
#   tools/realworld.sh [OUTDIR]       (from the repository root; default build/realworld)
#
# Per lens (OUTDIR/<folder>/<file>/):
#   lens-info FILE                     imports with no option? (else its error line)
#   efl against the file's own focal length (# focal: of a lens(5) file, lentil's
#   patent figure) and against an independent check: a ray parallel to the axis at a
#   small height h on the sensor side traced exactly (lens-trace FILE -, d line); it
#   leaves the front surface at angle theta and efl = h / sin(theta) (paraxial limit)
#   lens-trace FILE -n 20000 | lens-fit                 fit time, held-out RMS
#   lens-trace FILE -n 20000 --seed 2 --sampling full | lens-eval --report   passage
#   lens-spot FILE --compare SYSTEM    spot RMS lens vs system per field row
#   lens-distort FILE --compare SYSTEM distortion at the top field, lens vs system
# Two lenses run at a time (JOBS). Mirror systems are refused by the importers on
# purpose and are listed apart as not refracting.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
BIN=${BIN:-bin}
if [ "${1:-}" = --one ]; then OUT=${OUT:-build/realworld}; else OUT=${1:-${OUT:-build/realworld}}; fi
JOBS=${JOBS:-2}
D_LINE=0.5875618
export BIN OUT D_LINE

# sensor_for (the one place that supplies the flags imported files still need),
# efl_check and has_mirror
source tools/realworld-lib.sh

one() { # FILE: measure one lens into $OUT/<folder>/<file>/row.tsv
  local f=$1 dir info lens rc err class efl focal indep flags sys
  dir="$OUT/$(basename "$(dirname "$f")")/$(basename "$f")"
  rm -rf "$dir"; mkdir -p "$dir"
  info=$dir/info.txt lens=$dir/lens.txt
  "$BIN"/lens-info "$f" >"$info" 2>"$dir/info.err"; rc=$?
  err=$(grep -v ': warning: ' "$dir/info.err" | head -1)
  row() { printf '%s\t' "$@" | sed 's/\t$//' >"$dir/row.tsv"; echo >>"$dir/row.tsv"; }
  if [ $rc -ne 0 ]; then
    class=refused
    if echo "$err" | grep -q 'is a mirror' || has_mirror "$f"; then class=not-refracting; fi
    row "$f" "$class" "${err:-exit $rc}"
    return
  fi
  "$BIN"/lens-info "$f" --format lens >"$lens" 2>/dev/null
  efl=$(awk '$1 == "efl" { print $2 }' "$info")
  focal=$(awk '$1 == "focal_header" { print $2 }' "$info")
  indep=$(efl_check "$f" "$lens")
  sensor_for "$f" "$info" "$lens"
  flags=$SENSOR_FLAGS
  if [ -z "$TOP" ]; then
    row "$f" imported - "$NEEDS" "$efl" "${focal:--}" "${indep:-nan}" - - - - - - - - - "no sensor could be chosen"
    return
  fi
  sys=$dir/system.poly
  # shellcheck disable=SC2086
  "$BIN"/lens-trace "$f" -n 20000 --seed 1 $flags -q 2>"$dir/trace.err" |
    "$BIN"/lens-fit -o "$sys" 2>"$dir/fit.err" >/dev/null
  if [ ! -s "$sys" ]; then
    row "$f" imported - "$NEEDS" "$efl" "${focal:--}" "${indep:-nan}" - - - - - - - - "$TOP" \
      "fit failed: $(grep -hv ': warning: ' "$dir/trace.err" "$dir/fit.err" | head -1)"
    return
  fi
  local fit_s rms passage outside spot spotr dl ds
  fit_s=$(sed -n 's/.*fit time \([0-9.e+-]*\) s.*/\1/p' "$dir/fit.err" | tail -1)
  rms=$(awk '$2 == "out_x" || $2 == "out_y" { for (i = 3; i < NF; i++) if ($i == "holdout_rms") { v = $(i + 1) * 1000; if (v > m) m = v } } END { printf "%.4g", m }' "$dir/fit.err")
  # shellcheck disable=SC2086
  "$BIN"/lens-trace "$f" -n 20000 --seed 2 --sampling full $flags -q 2>>"$dir/trace.err" |
    "$BIN"/lens-eval "$sys" --report >"$dir/eval.txt" 2>"$dir/eval.err"
  passage=$(awk '$1 == "light_disagree" { printf "%.4g", $2 * 100 }' "$dir/eval.txt")
  outside=$(awk '$1 == "rays" && !r { r = $2 } $1 == "outside_domain" { o = $2 } END { if (r) printf "%.3g", 100 * o / r }' "$dir/eval.txt")
  local f0 f1
  f0=$(awk -v t="$TOP" 'BEGIN { printf "%.6g", 0.7 * t }')
  f1=$(awk -v t="$TOP" 'BEGIN { printf "%.6g", t }')
  "$BIN"/lens-spot "$f" --fields "0,$f0,$f1" --compare "$sys" >"$dir/spot.txt" 2>"$dir/spot.err"
  # worst |system / lens - 1| of the spot RMS about the chief ray, pooled rows ("all")
  # shellcheck disable=SC2016
  # (a file of one wavelength has no pooled row: its one row is the field's)
  local spot_awk='!/^#/ && ($1 == "lens" || $1 == "poly") { c[$1, $2]++; one[$1, $2] = $11; fl[$2] = 1 }
    $3 == "all" && ($1 == "lens" || $1 == "poly") { v[$1, $2] = $11 }
    END { for (k in c) if (c[k] == 1) v[k] = one[k]
          w = -1; for (x in fl) { l = v["lens", x]; p = v["poly", x]
            if (l == "" || p == "" || l == "nan" || p == "nan" || l + 0 == 0) continue
            e = p / l - 1; a = e < 0 ? -e : e; if (a > w) { w = a; we = e; wf = x } }
          if (w < 0) print "-\t-"; else printf "%+.3g\t%s\n", 100 * we, wf }'
  spot=$(awk "$spot_awk" "$dir/spot.txt")
  # the same with a random pupil: the hexapolar pattern puts its outer ring on the stop's
  # rim, where the lens passes it and the system's fitted pass circle may not
  "$BIN"/lens-spot "$f" --fields "0,$f0,$f1" --pupil random --rays 4000 --compare "$sys" >"$dir/spot-random.txt" 2>/dev/null
  spotr=$(awk "$spot_awk" "$dir/spot-random.txt")
  "$BIN"/lens-distort "$f" --fields "0,$f1" --illum-rays 0 --compare "$sys" >"$dir/distort.txt" 2>"$dir/distort.err"
  dl=$(awk -v t="$f1" '$1 == "lens" && $2 + 0 == t + 0 { print $5 }' "$dir/distort.txt" | tail -1)
  ds=$(awk -v t="$f1" '$1 == "poly" && $2 + 0 == t + 0 { print $5 }' "$dir/distort.txt" | tail -1)
  local note=""
  [ -s "$dir/spot.txt" ] || note="lens-spot: $(grep -v ': warning: ' "$dir/spot.err" | head -1)"
  [ -n "$dl" ] || note="$note lens-distort: $(grep -v ': warning: ' "$dir/distort.err" | head -1)"
  row "$f" imported - "$NEEDS" "$efl" "${focal:--}" "${indep:-nan}" "${fit_s:--}" "${rms:--}" \
    "${passage:--}" "${outside:--}" "${spot%%$'\t'*}" "${spot#*$'\t'}" "${dl:--}" "${ds:--}" "$TOP" \
    "${note:-$TOP_FROM}" "${SENSOR_FLAGS:--}" "${spotr%%$'\t'*}" "${spotr#*$'\t'}"
}

if [ "${1:-}" = --one ]; then
  one "$2"
  exit 0
fi

for c in lens-info lens-trace lens-fit lens-eval lens-spot lens-distort; do
  [ -x "$BIN/$c" ] || { echo "realworld: $BIN/$c missing: run make" >&2; exit 1; }
done
mkdir -p "$OUT"
start=$(date +%s)
find lenses/realworld -mindepth 2 -maxdepth 2 -type f \
  \( -iname '*.zmx' -o -iname '*.seq' -o -name '*.lens' -o -name '*.fx' \) | LC_ALL=C sort >"$OUT/lenses.txt"
export -f one sensor_for efl_check has_mirror
# shellcheck disable=SC2016
xargs -d '\n' -P "$JOBS" -I{} bash -c 'one "$1" && echo "realworld: $1" >&2' _ {} <"$OUT/lenses.txt"
while IFS= read -r f; do
  cat "$OUT/$(basename "$(dirname "$f")")/$(basename "$f")/row.tsv"
done <"$OUT/lenses.txt" >"$OUT/rows.tsv"
secs=$(( $(date +%s) - start ))
python3 tools/report_realworld.py "$OUT/rows.tsv" reports/realworld.md "$secs" "$JOBS"
echo "realworld: wrote reports/realworld.md ($(wc -l <"$OUT/rows.tsv") files, ${secs} s)" >&2
