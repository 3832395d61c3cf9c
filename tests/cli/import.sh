#!/usr/bin/env bash
# Zemax .zmx / CODE V .seq / AGF through lens-info: first-order data against closed forms,
# warnings for skipped parts, conversion to .lens and back, the glass flags, refusals.
source "$(dirname "$0")/lib.sh"
if [ ! -x "$BIN/lens-info" ]; then
  echo "# $BIN/lens-info not built: import skipped"
  exit 0
fi
D=tests/data/import
AGF="--glass-catalog $D/test.agf"

# Thick lens R = +-50, t = 5, n = 1.5: f = 1 / (0.5 (0.04 - 2.5/3750)), bfl = f (1 - 1/30).
f=$(awk 'BEGIN { printf "%.12f", 1 / (0.5 * (0.04 - 2.5 / 3750)) }')
b=$(awk -v f="$f" 'BEGIN { printf "%.12f", f * (1 - 1 / 30) }')
for file in singlet.zmx singlet_cm.zmx singlet.seq; do
  out=$(run "$BIN/lens-info" "$D/$file" 2>"$T/err") || { fail "singlet-$file" "$(cat "$T/err")"; continue; }
  e=$(value efl <<<"$out") bb=$(value bfl <<<"$out")
  if near "$e" "$f" 1e-6 && near "$bb" "$b" 1e-6; then ok "singlet-$file"; else fail "singlet-$file" "efl $e bfl $bb, expected $f $b"; fi
done

# Skipped parts are said on stderr, one "lens-info: warning:" line each.
run "$BIN/lens-info" "$D/singlet.zmx" >/dev/null 2>"$T/err"
if grep -q "^lens-info: warning: $D/singlet.zmx: skipped: coatings (2), tolerance operands (3)" "$T/err"; then
  ok warn-skipped; else fail warn-skipped "stderr: $(cat "$T/err")"; fi

# Converted: the header keeps source and notes; the .lens gives the same first-order data.
if run "$BIN/lens-info" "$D/cooke.zmx" $AGF --format lens >"$T/cooke.lens" 2>/dev/null &&
   grep -q '^# source: Zemax file cooke.zmx' "$T/cooke.lens" &&
   grep -q '^# note: wavelengths' "$T/cooke.lens"; then
  a=$(run "$BIN/lens-info" "$D/cooke.zmx" $AGF 2>/dev/null | value efl)
  c=$(run "$BIN/lens-info" "$T/cooke.lens" $AGF 2>/dev/null | value efl)
  if near "$a" "$c" 1e-9 && near "$a" 50 0.05; then ok convert-cooke; else fail convert-cooke "efl $a vs $c (design 50)"; fi
else
  fail convert-cooke "no source/note header in $(head -5 "$T/cooke.lens")"
fi

# Each .seq gives the .zmx twin's focal length.
for n in singlet doublet asphere cooke dgauss; do
  a=$(run "$BIN/lens-info" "$D/$n.zmx" $AGF 2>/dev/null | value efl)
  s=$(run "$BIN/lens-info" "$D/$n.seq" $AGF 2>/dev/null | value efl)
  if [ -n "$a" ] && near "$a" "$s" 1e-9; then ok "seq-$n"; else fail "seq-$n" "zmx efl '$a', seq efl '$s'"; fi
done

# Missing glass: one line naming the glass and the catalogs; the fallback reads it.
sed 's/GLAS N-BK7 0 0 1.5168 64.17/GLAS XG-NOPE 0 0 1.5168 64.17/' "$D/doublet.zmx" >"$T/nope.zmx"
expect_error missing-glass "^lens-info: $T/nope.zmx:[0-9]+: glass XG-NOPE not found in .*test.agf" \
  "$BIN/lens-info" "$T/nope.zmx" $AGF
if run "$BIN/lens-info" "$T/nope.zmx" $AGF --glass-fallback ndvd >/dev/null 2>"$T/err" &&
   grep -q "warning: .*XG-NOPE" "$T/err"; then ok glass-fallback; else fail glass-fallback "$(cat "$T/err")"; fi

# A fold mirror is refused with the surface and the reason.
sed 's/GLAS N-F2 0 0 1.62004 36.37/GLAS MIRROR/' "$D/doublet.zmx" >"$T/fold.zmx"
expect_error refuse-mirror "^lens-info: $T/fold.zmx:[0-9]+: surface 2 is a mirror" "$BIN/lens-info" "$T/fold.zmx" $AGF

# stdin ('-') is read in every format, told by content: the same first-order data as the
# file, and an imported lens's warnings name '-'.
for file in singlet.zmx singlet.seq cooke.zmx dgauss.seq; do
  a=$(run "$BIN/lens-info" "$D/$file" $AGF 2>/dev/null)
  s=$(run "$BIN/lens-info" - $AGF <"$D/$file" 2>"$T/err")
  if [ -n "$a" ] && [ "$a" = "$s" ]; then ok "stdin-$file"; else fail "stdin-$file" "$(head -3 <<<"$s") / $(cat "$T/err")"; fi
done
run "$BIN/lens-info" - <"$D/singlet.zmx" >/dev/null 2>"$T/err"
if grep -q "^lens-info: warning: -: skipped: coatings" "$T/err"; then ok stdin-warnings; else fail stdin-warnings "$(cat "$T/err")"; fi
# ... and a converted .lens piped back in keeps its notes to itself (said at conversion)
run "$BIN/lens-info" "$D/singlet.zmx" --format lens 2>/dev/null | run "$BIN/lens-info" - >/dev/null 2>"$T/err"
if ! grep -q "skipped" "$T/err"; then ok stdin-native-quiet; else fail stdin-native-quiet "$(cat "$T/err")"; fi

# --lens-format names the format whatever the file is called; a wrong one is refused.
cp "$D/singlet.seq" "$T/singlet.txt"
a=$(run "$BIN/lens-info" "$D/singlet.seq" 2>/dev/null | value efl)
s=$(run "$BIN/lens-info" --lens-format seq "$T/singlet.txt" 2>/dev/null | value efl)
if [ -n "$a" ] && [ "$a" = "$s" ]; then ok lens-format-seq; else fail lens-format-seq "'$a' vs '$s'"; fi
expect_error lens-format-wrong "^lens-info: $T/singlet.txt: not a Zemax" "$BIN/lens-info" --lens-format zmx "$T/singlet.txt"
expect_error lens-format-unknown "^lens-info: --lens-format: expected one of lens, fx, pbrt, zmx, seq" \
  "$BIN/lens-info" --lens-format codev "$T/singlet.txt"

# Model glasses out of range (n_d below 1, above 3, V_d <= 0) are refused at their line,
# from a file and from stdin alike.
gl=$(grep -n 'GLAS N-BK7 0 0 1.5168 64.17' "$D/doublet.zmx" | head -1 | cut -d: -f1)
for bad in "0.6 40" "1e17 40" "1.5 -3"; do
  sed "s/GLAS N-BK7 0 0 1.5168 64.17/GLAS ___BLANK 1 0 $bad/" "$D/doublet.zmx" >"$T/model.zmx"
  expect_error "zmx-model-glass-${bad// /_}" "^lens-info: -:$gl: model glass .*(below 1|above 3|Abbe)" \
    sh -c "'$BIN/lens-info' - <'$T/model.zmx'"
done

# No aperture value but the stop's clear aperture (Zemax FLOA): the stop's semi-diameter
# is the aperture, and the surfaces without DIAM are sized from it. The Cooke triplet's
# stop is 3.804553 mm where ENPD 10 puts it: floated by that stop, the entrance pupil
# lens-info computes is 10 mm again.
awk '/^ENPD/ { print "FLOA"; next } /^SURF 4/ { s = 1 } /^SURF 5/ { s = 0 }
     /^  DIAM/ && !s { next } { print }' lenses/cooke-triplet.zmx >$T/floa.zmx
epd=$(run "$BIN/lens-info" $T/floa.zmx 2>$T/err | value entrance_pupil_diameter)
if near "$epd" 10 1e-5 && grep -q "semi-diameters not in the file (DIAM), set from paraxial rays (EPD 10 mm" $T/err
then ok zmx_float_by_stop; else fail zmx_float_by_stop "epd '$epd' $(cat $T/err)"; fi

# CODE V files other programs write: "SO 0 inf" reads as an object at infinity (the
# singlet's closed-form efl); DIF DOE is refused as diffractive, not skipped; CIR EDG is
# a drawing edge (noted), not an obscuration.
sed 's/^SO 0 1e10/SO 0 inf/' $D/singlet.seq >$T/inf.seq
e=$(run "$BIN/lens-info" $T/inf.seq 2>/dev/null | value efl)
if near "$e" "$f" 1e-6; then ok seq_so_inf; else fail seq_so_inf "efl '$e', expected $f"; fi
sed 's/^  CCY 0; THC 0/  DIF DOE/' $D/singlet.seq >$T/doe.seq
expect_error seq_dif_doe_refused "doe.seq:[0-9]+: surface 1 is diffractive \(DIF DOE\)" run "$BIN/lens-info" $T/doe.seq
sed 's/^  CCY 0; THC 0/  CIR EDG 6/' $D/singlet.seq >$T/edg.seq
e=$(run "$BIN/lens-info" $T/edg.seq 2>$T/err | value efl)
if near "$e" "$f" 1e-6 && grep -q "skipped: edge apertures (CIR EDG, drawing only)" $T/err && ! grep -q "obscuration" $T/err
then ok seq_cir_edg; else fail seq_cir_edg "efl '$e' $(cat $T/err)"; fi

# Fused silica by its Zemax name (the MISC catalog): the singlet in SILICA has the
# thick-lens efl of Malitson's n_d (Sellmeier terms of the published fit, here in awk).
sed 's/^S 50 5 1.5:60/S 50 5 SILICA/' $D/singlet.seq >$T/silica.seq
n=$(awk 'BEGIN { l = 0.5875618 ^ 2; s = 0.6961663 * l / (l - 0.0684043 ^ 2)
  s += 0.4079426 * l / (l - 0.1162414 ^ 2); s += 0.8974794 * l / (l - 9.896161 ^ 2)
  printf "%.12f", sqrt(1 + s) }')
fs=$(awk -v n="$n" 'BEGIN { c = 1 / 50; printf "%.12f", 1 / ((n - 1) * (2 * c - (n - 1) * 5 * c * c / n)) }')
e=$(run "$BIN/lens-info" $T/silica.seq 2>/dev/null | value efl)
if near "$e" "$fs" 1e-6; then ok glass_silica; else fail glass_silica "efl '$e', expected $fs (n_d $n)"; fi

# A private glass no catalog has travels with the lens written from it (# glass: lines,
# lens(5)): the converted lens reads back with the same efl.
S=lenses/realworld/ray-optics/CODV_65988_noDOE.seq
run "$BIN/lens-info" $S --format lens >$T/e48.lens 2>/dev/null
a=$(run "$BIN/lens-info" $S 2>/dev/null | value efl) b=$(run "$BIN/lens-info" $T/e48.lens 2>/dev/null | value efl)
if grep -q "^# glass: E48 schott " $T/e48.lens && [ -n "$a" ] && [ "$a" = "$b" ]
then ok private_glass_written_back; else fail private_glass_written_back "efl $a / $b"; fi
