#!/usr/bin/env bash
# lens-render --focus, --fstop, --blades: overrides of the scene's camera. Each gives the
# picture of the scene that says the same (bit for bit); --fstop N against the scene's f/N0
# takes (N0 / N)^2 of the light of a uniform emitter near the axis, within its noise;
# --focus D puts the sensor where Newton's equation on lens-info's first-order data says,
# bfl + efl^2 / (D + ffl); a .poly camera refuses them.
source "$(dirname "$0")/lib.sh"
R=$BIN/lens-render
lens=$TOP/lenses/dgauss.50mm.lens
scene() { # the uniform emitter near the axis (2 x 2 mm of sensor), and extra lines
  printf 'camera %s\nsensor 2 2\nresolution 8 8\nmode grey\nspp %s\nplane 0 0 1000 0 0 -1 emit 1\n' "$lens" "$1"
  shift; printf '%s\n' "$@"
}
scene 4000 "fstop 8" >"$T/f8.scene"
scene 4000 "fstop 16" >"$T/f16.scene"
scene 1 >"$T/black.scene"; sed -i 's/emit 1$/albedo 0/' "$T/black.scene"
export XDG_CACHE_HOME=$T/cache
run "$R" "$T/black.scene" --exact -q -o "$T/black.exr"

# the same picture as the scene's own statement
run "$R" "$T/f16.scene" --exact -q -o "$T/a.exr"
run "$R" "$T/f8.scene" --exact -q --fstop 16 -o "$T/b.exr"
cmp -s "$T/a.exr" "$T/b.exr" && ok "--fstop 16 is the scene's fstop 16" || fail "--fstop 16" "pictures differ"
scene 4 "focus 2000" >"$T/focus.scene"
scene 4 >"$T/plain.scene"
run "$R" "$T/focus.scene" --exact -q -o "$T/a.exr"
run "$R" "$T/plain.scene" --exact -q --focus 2000 -o "$T/b.exr"
cmp -s "$T/a.exr" "$T/b.exr" && ok "--focus 2000 is the scene's focus 2000" || fail "--focus 2000" "pictures differ"
scene 4 "blades 6 10" >"$T/blades.scene"
scene 4 "blades 5 10" >"$T/blades5.scene"
run "$R" "$T/blades.scene" --exact -q -o "$T/a.exr"
run "$R" "$T/blades5.scene" --exact -q --blades 6 -o "$T/b.exr"
run "$R" "$T/blades.scene" --exact -q --blades 0 -o "$T/c.exr"
run "$R" "$T/plain.scene" --exact -q -o "$T/d.exr"
cmp -s "$T/a.exr" "$T/b.exr" && ok "--blades 6 is the scene's blades 6" || fail "--blades 6" "pictures differ"
cmp -s "$T/c.exr" "$T/d.exr" && ok "--blades 0 is the round stop" || fail "--blades 0" "pictures differ"
cmp -s "$T/a.exr" "$T/d.exr" && fail "blades change the picture" "six blades gave the round stop's picture" ||
  ok "blades change the picture"

# The exposure ratio. A picture's mean m is its RMS against the black one (the pixels
# differ by little more than noise), its per-pixel noise the RMS against another seed
# over sqrt 2; m's standard error that over sqrt(64).
figures() { # SCENE ARGS...: "mean se"
  local s=$1; shift
  run "$R" "$s" --exact -q "$@" --seed 2 -o "$T/s2.exr"
  local m d
  m=$(run "$R" "$s" --exact -q "$@" --seed 1 -o "$T/s1.exr" --reference "$T/black.exr" 2>&1 | sed -n 's/.*rms \([0-9.e+-]*\) .*/\1/p')
  d=$(run "$R" "$s" --exact -q "$@" --seed 1 -o "$T/s1.exr" --reference "$T/s2.exr" 2>&1 | sed -n 's/.*rms \([0-9.e+-]*\) .*/\1/p')
  awk -v m="$m" -v d="$d" 'BEGIN { print m, d / sqrt(2) / 8 }'
}
read -r m8 se8 <<<"$(figures "$T/f8.scene")"
read -r m16 se16 <<<"$(figures "$T/f8.scene" --fstop 16)"
# 4 digits: at most half a unit of the 4th in each figure, 5e-4 of it
if awk -v a="$m8" -v sa="$se8" -v b="$m16" -v sb="$se16" 'BEGIN {
     r = b / a; se = r * sqrt((sa / a)^2 + (sb / b)^2)
     d = r - 0.25; if (d < 0) d = -d; exit !(a > 0 && d <= 3 * se + r * 1e-3) }'; then
  ok "--fstop 16 against f/8: $m16 / $m8 = (8/16)^2 within noise"
else fail "--fstop 16 against f/8" "$m16 / $m8, se $se16 $se8, not 0.25"; fi

# --focus: Newton's equation on the first-order data
info=$(run "$BIN/lens-info" "$lens")
efl=$(value efl <<<"$info") bfl=$(value bfl <<<"$info") ffl=$(value ffl <<<"$info")
for d in 500 2000; do
  t=$(run "$R" "$T/plain.scene" --exact --spp 1 --focus $d -o "$T/x.exr" 2>&1 |
      sed -n 's/^camera: focus .*, the sensor \([0-9.]*\) mm behind the last surface.*/\1/p')
  want=$(awk -v f="$efl" -v b="$bfl" -v ff="$ffl" -v d=$d 'BEGIN { printf "%.6f", b + f * f / (d + ff) }')
  near "${t:-0}" "$want" 1e-5 && ok "--focus $d: the sensor $t mm behind the last surface" ||
    fail "--focus $d" "sensor '$t', Newton's equation $want"
done
t=$(run "$R" "$T/focus.scene" --exact --spp 1 --focus inf -o "$T/x.exr" 2>&1 |
    sed -n 's/^camera: focus inf, the sensor \([0-9.]*\) mm.*/\1/p')
near "${t:-0}" "$bfl" 1e-5 && ok "--focus inf: the sensor at the back focal length" || fail "--focus inf" "sensor '$t', bfl $bfl"

# bad values, and a fitted camera
expect_error focus-zero "--focus: '0': give a distance > 0 mm, or inf" "$R" "$T/plain.scene" --focus 0 -o "$T/x.exr"
expect_error blades-two "--blades: '2': give 0" "$R" "$T/plain.scene" --blades 2 -o "$T/x.exr"
run "$R" "$T/plain.scene" --spp 1 -q -o "$T/p.exr" --cache "$T/pc"
poly=$(ls "$T"/pc/*.poly 2>/dev/null | head -1)
sed "s|^camera .*|camera $poly|" "$T/plain.scene" >"$T/poly.scene"
expect_error poly-fstop "^lens-render: --fstop cannot change a fitted .poly camera" "$R" "$T/poly.scene" --fstop 4 -o "$T/x.exr"
