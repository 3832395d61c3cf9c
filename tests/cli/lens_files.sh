#!/usr/bin/env bash
# Lens files through lens-info: every shipped lens loads and writes back unchanged, and
# each bad input gives one line "lens-info: FILE:LINE: what" and exit status 1.
source "$(dirname "$0")/lib.sh"
if [ ! -x "$BIN/lens-info" ]; then
  echo "# $BIN/lens-info not built: lens_files skipped"
  exit 0
fi

for f in lenses/*.lens; do
  n=$(basename "$f" .lens)
  if ! run "$BIN/lens-info" "$f" --format lens >"$T/a.lens" 2>"$T/err"; then
    fail "load-$n" "$(cat "$T/err")"; continue
  fi
  # Written lenses read back to the same text (numbers are written exactly).
  run "$BIN/lens-info" "$T/a.lens" --format lens >"$T/b.lens" 2>"$T/err"
  if cmp -s "$T/a.lens" "$T/b.lens"; then ok "load-$n"; else fail "load-$n" "round trip differs"; fi
  for key in name source focal sensor; do
    grep -q "^# $key: " "$f" || fail "header-$n" "no '# $key:' line"
  done
done

# bad_input NAME FILE LINE PATTERN: exit 1, a single stderr line "lens-info: FILE:LINE: ...PATTERN".
bad_input() {
  local n=$1 file=$2 line=$3 pat=$4 err rc
  err=$(run "$BIN/lens-info" "$file" 2>&1 >/dev/null); rc=$?
  if [ "$rc" -ne 1 ]; then fail "$n" "exit $rc, expected 1"; return; fi
  if [ "$(printf '%s\n' "$err" | wc -l)" -ne 1 ]; then fail "$n" "more than one line: $err"; return; fi
  if ! grep -qF -- "lens-info: $file:$line: " <<<"$err"; then fail "$n" "no 'lens-info: $file:$line: ' in '$err'"; return; fi
  if ! grep -qE -- "$pat" <<<"$err"; then fail "$n" "'$err' does not match '$pat'"; return; fi
  ok "$n"
}
B=tests/data/bad
bad_input bad-number       $B/bad-number.lens       3 "radius 'x' is not a number"
bad_input nan-thickness    $B/nan-thickness.lens    1 "thickness 'nan'"
bad_input unknown-material $B/unknown-material.lens 2 "unknown material 'N-UNOBTAINIUM'.*glass.catalog"
bad_input unknown-key      $B/unknown-key.lens      1 "unknown header key 'colour'"
bad_input missing-fields   $B/missing-fields.lens   2 "3 fields found"
bad_input empty            $B/empty.lens            1 "empty file"
bad_input no-stop          $B/no-stop.lens          2 "no aperture stop"
bad_input two-stops        $B/two-stops.lens        2 "second aperture stop"
bad_input bad-sensor       $B/bad-sensor.lens       1 "sensor"
bad_input bad-asphere      $B/bad-asphere.lens      1 "unknown surface coefficient 'a5'"
bad_input zero-radius      $B/zero-radius.lens      1 "radius 0"
bad_input bad-columns      $B/bad-columns.dat       3 "expected 4 columns"
bad_input cylinder         $B/cylinder.fx           4 "not rotationally symmetric"
