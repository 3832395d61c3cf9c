#!/usr/bin/env bash
# Conventions every command keeps: a misspelt long option is answered with the nearest
# real one (a name far from every option gets no guess); a picture's kind follows its name.
. "$(dirname "$0")/lib.sh"
L=lenses/dgauss.50mm.lens
expect_error hint_prefix "^lens-spot: unknown option '--field': did you mean --fields\? \(see --help\)$" \
  "$BIN/lens-spot" "$L" --field 3
expect_error hint_typo "^lens-trace: unknown option '--sede': did you mean --seed\? \(see --help\)$" \
  "$BIN/lens-trace" "$L" --sede 3
expect_error hint_swap "did you mean --terms\?" "$BIN/lens-fit" --tersm 3
expect_error hint_builtin "did you mean --version\?" "$BIN/lens-info" --verison
expect_error hint_none "^lens-trace: unknown option '--zzzzz' \(see --help\)$" "$BIN/lens-trace" "$L" --zzzzz
expect_error hint_value_form "did you mean --seed\?" "$BIN/lens-trace" "$L" --sed=3
# A picture's kind follows its name: a .jpg is refused before anything is written.
rm -f "$T/fan.jpg"
expect_error picture_kind "fan.jpg: a picture is written as PNG, SVG or PDF.*'\.jpg' is none of them" \
  "$BIN/lens-fan" "$L" --png "$T/fan.jpg"
if [ -e "$T/fan.jpg" ]; then fail picture_kind_no_file "a .jpg was left behind"; else ok picture_kind_no_file; fi
# Every z is measured from the first surface: the exit pupil's z and its distance from
# the last surface differ by that surface's z, the total track less the sensor distance.
info=$("$BIN/lens-info" "$L")
v() { awk -v k="$1" '$1 == k { print $2 }' <<<"$info"; }
last=$(awk -v t="$(v total_track)" -v s="$(v sensor_distance)" 'BEGIN { print t - s }')
d=$(awk -v a="$(v exit_pupil_z)" -v b="$(v exit_pupil_from_last_surface)" 'BEGIN { print a - b }')
if near "$d" "$last" 1e-6 && ! near "$(v exit_pupil_z)" "$(v exit_pupil_from_last_surface)" 1; then
  ok exit_pupil_from_first_surface
else
  fail exit_pupil_from_first_surface "exit_pupil_z - exit_pupil_from_last_surface = $d, last surface at $last"
fi
# lens-info --seidel: the Lagrange invariant of a ray entering parallel at the pupil's
# rim and a chief ray at slope tan(field) through its centre is -(D/2) tan(field), D the
# entrance pupil diameter lens-info prints; the sums row is the last of the table, in JSON too.
D=$(v entrance_pupil_diameter)
H=$("$BIN/lens-info" "$L" --seidel --field 10 | awk '$1 == "lagrange_invariant_mm" { print $2 }')
Hw=$(awk -v d="$D" 'BEGIN { print -d / 2 * sin(10 * atan2(0, -1) / 180) / cos(10 * atan2(0, -1) / 180) }')
if near "$H" "$Hw" 1e-5; then ok seidel_lagrange; else fail seidel_lagrange "H $H, expected $Hw"; fi
if "$BIN/lens-info" "$L" --seidel --json | python3 -c '
import json, sys
d = json.load(sys.stdin)
rows = d["seidel"]
assert rows[-1]["surface"] == "sum"
for k in ("S_I", "S_II", "S_III", "S_IV", "S_V"):
    assert abs(sum(r[k] for r in rows[:-1]) - rows[-1][k]) < 1e-7, k
'; then ok seidel_json; else fail seidel_json "the JSON does not parse or its sums do not add up"; fi
expect_error seidel_field_alone "^lens-info: --field: the chief ray's angle of --seidel" "$BIN/lens-info" "$L" --field 3
