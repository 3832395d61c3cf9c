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
