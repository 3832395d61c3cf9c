#!/usr/bin/env bash
# lens-render: help, errors with FILE:LINE, outputs written whole, the cache, the
# effects it reports. Values are checked by the unit tests (test_render*.c).
source "$(dirname "$0")/lib.sh"
R=$BIN/lens-render

$R --help | grep -q "usage: lens-render" && ok help || fail help "no usage"
[ -f man/lens-render.1 ] && [ -f man/lens-scene.5 ] && ok man-pages || fail man-pages "missing"

# a tiny scene next to a copy of the lens: relative camera paths resolve against it
cp lenses/dgauss.50mm.lens "$T/"
cat >"$T/s.scene" <<'S'
camera dgauss.50mm.lens
sensor 36 24
resolution 12 8
mode grey
spp 4
plane 0 0 1000 0 0 -1 checker 0.2 0.8 100
disk 0 500 500 0 -1 0 300 emit 5
S
printf 'camera dgauss.50mm.lens\nresolution 12 8\nsphere 0 0 100 5 glow 3\n' >"$T/bad.scene"

expect_error no-output 'give -o' $R "$T/s.scene"
expect_error bad-scene "bad.scene:3: unknown modifier 'glow'" $R "$T/bad.scene" -o "$T/x.exr"
# a value that is not a number is named (it had said "takes one value or three, got 0");
# a second camera is an error (the last one had won)
printf 'camera dgauss.50mm.lens\nplane 0 0 1000 0 0 -1 emit 1abc\n' >"$T/badnum.scene"
expect_error bad-scene-number "badnum.scene:2: 'emit': '1abc' is not a finite number" $R "$T/badnum.scene" -o "$T/x.exr"
printf 'camera dgauss.50mm.lens\nplane 0 0 1000 0 0 -1 albedo nan\n' >"$T/badnan.scene"
expect_error bad-scene-nan "badnan.scene:2: 'albedo': 'nan' is not a finite number" $R "$T/badnan.scene" -o "$T/x.exr"
printf 'camera dgauss.50mm.lens\ncamera dgauss.50mm.lens\n' >"$T/twocams.scene"
expect_error bad-scene-two-cameras "twocams.scene:2: a second 'camera' statement" $R "$T/twocams.scene" -o "$T/x.exr"
expect_error no-scene 'cannot open' $R "$T/none.scene" -o "$T/x.exr"
[ ! -e "$T/x.exr" ] && ok no-partial-output || fail no-partial-output "x.exr left behind"
expect_error bad-spp 'spp' $R "$T/s.scene" -o "$T/x.exr" --spp 0

err=$($R "$T/s.scene" -o "$T/e.exr" --png "$T/e.png" --exact 2>&1)
if [ -s "$T/e.exr" ] && [ -s "$T/e.png" ] && grep -q 'camera rays/s' <<<"$err"; then
  ok exact-render; else fail exact-render "$err"; fi

err=$($R "$T/s.scene" -o "$T/p.exr" --cache "$T/cache" 2>&1)
if [ -s "$T/p.exr" ] && grep -q '^effects on:' <<<"$err" && grep -q '^effects off:.*dispersion' <<<"$err" \
   && ls "$T"/cache/*.poly >/dev/null 2>&1; then ok poly-render-fits-and-caches; else fail poly-render-fits-and-caches "$err"; fi
err=$($R "$T/s.scene" -o "$T/p2.exr" --cache "$T/cache" 2>&1)
grep -q 'system: cached' <<<"$err" && ok cache-reused || fail cache-reused "$err"
grep -q 'line pupil: cached' <<<"$err" && ok pupil-cache-reused || fail pupil-cache-reused "$err"
cmp -s "$T/p.exr" "$T/p2.exr" && ok reproducible || fail reproducible "same seed, different image"

# the camera module compiles on its own, warning-free, and defines lens_camera_ray
err=$($R "$T/s.scene" --emit-camera "$T/cam.c" --cache "$T/cache" 2>&1)
if [ -s "$T/cam.c" ] && cc -std=c99 -O2 -Wall -Wextra -Werror -c "$T/cam.c" -o "$T/cam.o" 2>&1 \
   && nm "$T/cam.o" | grep -q ' T lens_camera_ray$' && nm "$T/cam.o" | grep -q ' T lens_camera_rays$'; then
  ok camera-module; else fail camera-module "$err"; fi
# with the scene's blades (their values: test_render_camera)
sed 's/^spp 4$/spp 4\nblades 6 10/' "$T/s.scene" >"$T/blades.scene"
err=$($R "$T/blades.scene" --emit-camera "$T/camb.c" --cache "$T/cache" 2>&1)
if grep -q '_blade\[6\]\[2\]' "$T/camb.c" && cc -std=c99 -O2 -Wall -Wextra -Werror -c "$T/camb.c" -o "$T/camb.o" 2>&1; then
  ok camera-module-blades; else fail camera-module-blades "$err"; fi
expect_error camera-module-exact 'needs a polynomial' $R "$T/s.scene" --emit-camera "$T/c2.c" --exact
[ ! -e "$T/c2.c" ] && ok camera-module-no-partial || fail camera-module-no-partial "c2.c left behind"

# a .poly camera: the cached system, named in a scene
poly=$(ls "$T"/cache/*.poly | head -1)
sed "s|^camera .*|camera $poly|" "$T/s.scene" >"$T/poly.scene"
cp "$T/dgauss.50mm.lens" "$T/cache/"
err=$($R "$T/poly.scene" -o "$T/q.exr" --threads 1 2>&1)
[ -s "$T/q.exr" ] && ok poly-camera || fail poly-camera "$err"

# exposure where the transmittance is not traced ray by ray (transmittance off, a .poly
# without out_eta such as the cached one above): the lens's mean transmittance on the
# axis weighs the rays, so a white plane comes out as bright as through the lens (a
# weight of 1 had made both 74% too bright). Against the exact render, within 1%.
printf 'camera %s\nsensor 36 24\nresolution 12 8\nmode grey\nspp 256\nplane 0 0 1000 0 0 -1 emit 1\n' \
  "$T/dgauss.50mm.lens" >"$T/white.scene"
{ cat "$T/white.scene"; echo 'transmittance off'; } >"$T/white-off.scene"
sed "s|^camera .*|camera $poly|" "$T/white.scene" >"$T/white-poly.scene"
$R "$T/white.scene" --exact -q -o "$T/white.exr"
for v in "exact-transmittance-off:$T/white-off.scene --exact" "poly-without-eta:$T/white-poly.scene"; do
  n=${v%%:*} args=${v#*:}
  # shellcheck disable=SC2086
  err=$($R $args -o "$T/w.exr" --reference "$T/white.exr" 2>&1)
  rel=$(sed -n 's/^error vs .*(\([0-9.]*\)% of its mean)$/\1/p' <<<"$err")
  if [ -n "$rel" ] && awk -v r="$rel" 'BEGIN { exit !(r < 1) }'; then ok "exposure-$n ($rel%)"
  else fail "exposure-$n" "$err"; fi
done
grep -q 'no out_eta' <<<"$err" && ok poly-without-eta-noted || fail poly-without-eta-noted "$err"

# what the outputs need is checked before the render: the image never written over its
# reference (that had printed rms 0 and lost the reference), nor the PNG over the EXR;
# a reference that is missing or of another size, a PNG path that cannot be written:
# refused at once, no EXR written
cp "$T/white.exr" "$T/same.exr"
expect_error render-output-is-reference "is also the input" $R "$T/white.scene" --exact -o "$T/same.exr" --reference "$T/same.exr"
cmp -s "$T/white.exr" "$T/same.exr" && ok render-reference-kept || fail render-reference-kept "the reference changed"
expect_error render-png-is-exr "--png: .* is also the EXR" $R "$T/white.scene" --exact -o "$T/a.exr" --png "$T/a.exr"
expect_error render-reference-missing "nope.exr" $R "$T/white.scene" --exact -o "$T/n.exr" --reference "$T/nope.exr"
sed 's/^resolution 12 8$/resolution 6 4/' "$T/white.scene" >"$T/small.scene"
expect_error render-reference-size "the image is 12x8, the render 6x4" $R "$T/small.scene" --exact -o "$T/n.exr" --reference "$T/white.exr"
expect_error render-png-unwritable "no/such/dir/x.png" $R "$T/white.scene" --exact -o "$T/n.exr" --png "$T/no/such/dir/x.png"
# -q silences progress, not the figures asked for by name
err=$($R "$T/white.scene" --exact -q -o "$T/q2.exr" --reference "$T/white.exr" 2>&1)
grep -q '^error vs .*white.exr: rms 0 ' <<<"$err" && ok render-quiet-keeps-figures || fail render-quiet-keeps-figures "$err"
[ ! -e "$T/n.exr" ] && [ ! -e "$T/a.exr" ] && ok render-checks-before-writing || fail render-checks-before-writing "$(ls "$T"/*.exr)"
# a .poly camera whose lens is not found: the advice fits lens-render (it has no --lens)
sed 's#^lens-path .*#lens-path /nonexistent/d.lens#' "$poly" >"$T/lost.poly"
sed "s|^camera .*|camera $T/lost.poly|" "$T/white.scene" >"$T/lost.scene"
expect_error render-lens-not-found "is not found; put the lens beside the .poly or correct its lens-path line" \
  $R "$T/lost.scene" -o "$T/n.exr"

# the glass flags every command has: an imported lens whose glasses are in a catalog of
# the user's, and a glass missing from every catalog read by its n_d/V_d
D=$PWD/tests/data/import
printf 'camera %s\nsensor 24 16\nresolution 6 4\nmode grey\nspp 2\nplane 0 0 1000 0 0 -1 emit 1\n' \
  "$T/nope.zmx" >"$T/zmx.scene"
sed 's/GLAS N-BK7 0 0 1.5168 64.17/GLAS XG-NOPE 0 0 1.5168 64.17/' "$D/doublet.zmx" >"$T/nope.zmx"
expect_error render-missing-glass "glass XG-NOPE not found in .*test.agf" \
  $R "$T/zmx.scene" -o "$T/z.exr" --exact --glass-catalog "$D/test.agf"
err=$($R "$T/zmx.scene" -o "$T/z.exr" --exact --cache "$T/cache" --glass-catalog "$D/test.agf" \
      --glass-fallback ndvd 2>&1)
if [ -s "$T/z.exr" ] && grep -q "warning: .*XG-NOPE" <<<"$err"; then ok render-glass-flags
else fail render-glass-flags "$err"; fi
