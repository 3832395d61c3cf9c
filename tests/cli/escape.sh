#!/usr/bin/env bash
# Text from input files never becomes code or markup, and no picture loses it: hostile
# names (a comment closed, a statement added, a lone backslash, a trigraph, quotes,
# markup, control bytes, Latin-1 and ill-formed UTF-8) through every emitter and writer.
# The C each emitter writes compiles as C11 with -pedantic -Werror and as C++17, shows no
# added statement to the preprocessor, and two cameras of two lenses link into one C++
# program; the SVG parses as XML, the JSON as JSON and gives the names back; the PNGs
# are as full of ink as with a plain name.
source "$(dirname "$0")/lib.sh"
CFLAGS_C="-std=c11 -Wall -Wextra -Werror -pedantic"
CFLAGS_CXX="-std=c++17 -Wall -Wextra -Werror"
CXX=${CXX:-g++}
# compiles_clean NAME FILE.c: as C11 and as C++; no INJECTED left after the preprocessor
compiles_clean() {
  local n=$1 c=$2 e
  if ! e=$(cc $CFLAGS_C -x c -c "$c" -o "$T/$n.o" 2>&1); then fail "$n" "C: $(head -3 <<<"$e")"; return; fi
  if ! e=$($CXX $CFLAGS_CXX -x c++ -c "$c" -o "$T/$n.pp.o" 2>&1); then fail "$n" "C++: $(head -3 <<<"$e")"; return; fi
  if cc -E -P "$c" | grep -q INJECTED; then fail "$n" "an injected statement survives the preprocessor"; return; fi
  if nm "$T/$n.o" | grep -q INJECTED; then fail "$n" "an injected symbol"; return; fi
  ok "$n"
}
hostile='*/(void)"INJECTED";/*'

# a system with hostile input, output and lens names (a .poly's names are words; the
# lens line takes the rest of its line)
cat >"$T/h.poly" <<P
lens-poly 2
lens */ (void)"INJECTED"; /* a*/ /* "q" <b> & ]]> ??/ \\
lens-path /an/absolute/build/dir/hostile.lens
inputs $hostile y
outputs a*/ /*u out_eta\\
scaling $hostile 0 1 -10 10
scaling y 0 1 -10 10
pass a*/ /*u 10
part 0 inf
output a*/ 1
  1 0 1
output /*u 0
output out_eta\\ 1
  0 0 1
end
P
run $BIN/lens-eval "$T/h.poly" --emit c -o "$T/h.c" || fail eval_emit_hostile "lens-eval --emit c failed"
compiles_clean eval_emit_hostile_compiles "$T/h.c"
[ -s "$T/h.h" ] && compiles_clean eval_emit_header_compiles "$T/h.h" || fail eval_emit_header_compiles "no h.h"
if grep -q '/an/absolute' "$T/h.c" "$T/h.h"; then fail emit_no_absolute_path "$(grep -m1 /an/ "$T/h.c")"
else ok emit_no_absolute_path; fi
if grep -q 'fisheye-ii' "$T/h.c"; then fail emit_no_other_lens "$(grep -m1 fisheye "$T/h.c")"; else ok emit_no_other_lens; fi

# the shipped systems, an input no term uses among them (eval_tiny: y)
for p in tests/data/*.poly; do
  b=$(basename "$p" .poly)
  run $BIN/lens-eval "$p" --emit c -o "$T/$b.c" && compiles_clean "eval_emit_${b}_compiles" "$T/$b.c"
done

# names that would clash or are reserved, refused before anything is written
for n in sqrt NAN INFINITY _lens __x fabs float_t int class main n 9x a-b; do
  expect_error "eval_name_refused_$n" "^lens-eval: --name:" $BIN/lens-eval tests/data/eval_tiny.poly --emit c --name "$n" -o "$T/refused.c"
done
[ ! -e "$T/refused.c" ] && [ ! -e "$T/refused.h" ] && ok name_refused_no_file || fail name_refused_no_file
expect_error fit_name_refused_sqrt "^lens-fit: --name: 'sqrt' cannot name the generated C: declared by <math.h>" \
  $BIN/lens-fit -q --emit c --name sqrt /dev/null

# a sample file whose columns carry the hostile names, fitted and emitted; the header
# from the same default name as lens-eval's
run $BIN/lens-trace lenses/dgauss.50mm.lens -n 1500 --seed 3 >"$T/train.txt"
sed -e 's|^# lens: .*|# lens: */ (void)"INJECTED"; /* ü \\|' "$T/train.txt" >"$T/htrain.txt"
if run $BIN/lens-fit -q --terms 12 --degree 4 "$T/htrain.txt" --emit c -o "$T/fit.c"; then
  compiles_clean fit_emit_hostile_compiles "$T/fit.c"
  grep -q '^int lens_poly(' "$T/fit.h" && grep -q '^int lens_poly(' "$T/fit.c" &&
    ok emit_one_default_name || fail emit_one_default_name "$(grep -m1 '^int ' "$T/fit.h")"
else fail fit_emit_hostile_compiles "lens-fit --emit c failed"; fi

# lens-render --emit-camera: a lens named to inject, two cameras of two lenses with
# --name, linked into one C++ program that runs both
sed '1s|.*|# name: */ (void)"INJECTED"; /* a*/ \\|' lenses/dgauss.50mm.lens >"$T/dg.lens"
cp lenses/simple.lens "$T/simple.lens"
for l in dg simple; do
  printf 'camera %s.lens\nsensor 36 24\nresolution 8 6\nspp 2\nplane 0 0 1000 0 0 -1 emit 1\n' "$l" >"$T/$l.scene"
done
run $BIN/lens-render "$T/dg.scene" --emit-camera "$T/cam_dg.c" --name cam_dg --cache "$T/cache" -q 2>"$T/r1.err"
run $BIN/lens-render "$T/simple.scene" --emit-camera "$T/cam_simple.c" --name cam_simple --cache "$T/cache" -q 2>"$T/r2.err"
if [ -s "$T/cam_dg.c" ] && [ -s "$T/cam_dg.h" ] && [ -s "$T/cam_simple.c" ]; then
  compiles_clean camera_hostile_compiles "$T/cam_dg.c"
  cat >"$T/two.cpp" <<'CPP'
#include <cstdio>
#include "cam_dg.h"
#include "cam_simple.h"
int main()
{
    double org[3], dir[3];
    int passed[2] = {0, 0};
    for (int k = 0; k < 400; k++) {
        double r1 = (k % 20 + 0.5) / 20, r2 = (k / 20 + 0.5) / 20;
        passed[0] += cam_dg_ray(0.5, 0.5, 0.55, r1, r2, org, dir) > 0;
        passed[1] += cam_simple_ray(0.5, 0.5, 0.55, r1, r2, org, dir) > 0;
    }
    std::printf("%d %d\n", passed[0], passed[1]);
    return passed[0] > 0 && passed[1] > 0 ? 0 : 1;
}
CPP
  if cc -std=c11 -O1 -c "$T/cam_dg.c" -o "$T/cam_dg.o" && cc -std=c11 -O1 -c "$T/cam_simple.c" -o "$T/cam_simple.o" &&
     $CXX $CFLAGS_CXX -I"$T" "$T/two.cpp" "$T/cam_dg.o" "$T/cam_simple.o" -lm -o "$T/two" 2>"$T/link.err" &&
     out=$("$T/two"); then ok two_cameras_one_cxx_program; else fail two_cameras_one_cxx_program "$(head -3 "$T/link.err") ${out:-}"; fi
else fail camera_hostile_compiles "$(cat "$T/r1.err" "$T/r2.err" | head -3)"; fi
expect_error render_name_refused "^lens-render: --name: " $BIN/lens-render "$T/dg.scene" --emit-camera "$T/x.c" --name NAN
expect_error render_emit_write_error "write error|No space" $BIN/lens-render "$T/simple.scene" --emit-camera /dev/full --cache "$T/cache" -q

# SVG: a .zmx NAME in Latin-1 with markup in it
LC_ALL=C sed "s/^NAME .*/NAME Objektiv f$(printf '\\xfc')r <Cooke> \\& \"Taylor\" ]]> $(printf '\\x01')/" lenses/cooke-triplet.zmx >"$T/latin.zmx"
if run $BIN/lens-layout "$T/latin.zmx" --svg "$T/l.svg" --png "$T/l.png" >/dev/null 2>"$T/layout.err" &&
   python3 -c '
import sys, xml.etree.ElementTree as E
r = E.parse(sys.argv[1]).getroot()
t = r.find("{http://www.w3.org/2000/svg}title").text
assert "Objektiv für <Cooke> & \"Taylor\" ]]>" in t, t
' "$T/l.svg" 2>"$T/xml.err"; then ok layout_svg_escaped; else fail layout_svg_escaped "$(cat "$T/layout.err" "$T/xml.err" | tail -2)"; fi

# pictures: as much ink with a Latin-1 or ill-formed name as with an ASCII one
ink() { python3 - "$1" <<'PY'
import sys, zlib, struct
d = open(sys.argv[1], 'rb').read()
assert d[:8] == b'\x89PNG\r\n\x1a\n'
i, idat, w, h, ct = 8, b'', 0, 0, 0
while i < len(d):
    n, t = struct.unpack('>I4s', d[i:i+8]); c = d[i+8:i+8+n]; i += 12 + n
    if t == b'IHDR': w, h, bd, ct = struct.unpack('>IIBB', c[:10])
    if t == b'IDAT': idat += c
raw = zlib.decompress(idat); bpp = {2: 3, 6: 4}[ct]; stride = w * bpp
prev, ink, p = bytearray(stride), 0, 0
for y in range(h):
    f = raw[p]; line = bytearray(raw[p+1:p+1+stride]); p += 1 + stride
    for x in range(stride):
        a = line[x-bpp] if x >= bpp else 0; b = prev[x]; c = prev[x-bpp] if x >= bpp else 0
        if f == 1: line[x] = (line[x] + a) & 255
        elif f == 2: line[x] = (line[x] + b) & 255
        elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
        elif f == 4:
            pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
            line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    ink += sum(1 for x in range(0, stride, bpp) if min(line[x:x+3]) < 250)
    prev = line
print(ink)
PY
}
ascii_name='Objektiv fur'
for l in plain latin bad; do
  case $l in plain) nm1="$ascii_name";; latin) nm1=$'Objektiv f\xfcr';; bad) nm1=$'Objektiv f\xc3\x28\xff\x01';; esac
  { printf '# name: %s\n' "$nm1"; sed 1d lenses/dgauss.50mm.lens; } >"$T/$l.lens"
done
for cmd in spot mtf fan; do
  case $cmd in spot) args="--png";; mtf) args="--png";; fan) args="--png";; esac
  for l in plain latin bad; do
    run $BIN/lens-$cmd "$T/$l.lens" $args "$T/$cmd-$l.png" >/dev/null 2>"$T/$cmd.err" || echo "rc $?" >>"$T/$cmd.err"
  done
  a=$(ink "$T/$cmd-plain.png" 2>/dev/null); b=$(ink "$T/$cmd-latin.png" 2>/dev/null); c=$(ink "$T/$cmd-bad.png" 2>/dev/null)
  # the pictures differ only in a few letters of the title
  if [ -n "$a" ] && [ -n "$b" ] && [ -n "$c" ] && [ "$a" -gt 1000 ] && near "$b" "$a" $((a / 20)) && near "$c" "$a" $((a / 20))
  then ok "${cmd}_picture_with_latin1_name"; else fail "${cmd}_picture_with_latin1_name" "ink $a $b $c $(head -2 "$T/$cmd.err")"; fi
done

# JSON: the names given back (valid UTF-8 as it is, Latin-1 as its characters)
for l in plain latin; do
  run $BIN/lens-info "$T/$l.lens" --json >"$T/info-$l.json" 2>/dev/null
done
if python3 -c '
import json, sys
for f, want in ((sys.argv[1], "Objektiv fur"), (sys.argv[2], "Objektiv für")):
    d = json.load(open(f, encoding="utf-8"))
    assert want in json.dumps(d, ensure_ascii=False), (f, want)
' "$T/info-plain.json" "$T/info-latin.json" 2>"$T/json.err"; then ok info_json_names; else fail info_json_names "$(tail -1 "$T/json.err")"; fi
printf '# columns: x y u v lambda a"b\\c\x01\n0 0 0 0 0.55 1\n' >"$T/cols.txt"
if run $BIN/lens-eval tests/data/perfect-50mm.poly "$T/cols.txt" --json >"$T/cols.json" 2>/dev/null; then
  python3 -c 'import json,sys; json.load(open(sys.argv[1]))' "$T/cols.json" && ok eval_json_parses || fail eval_json_parses "$(head -c 300 "$T/cols.json")"
else ok eval_json_parses; fi

# A name in a power's comment ("m3 = m1 * m1; /* NAME^2 */") is escaped too: the
# fuzzer's input whose input name closes a comment emits C in which, comments removed,
# nothing of the name is left.
R=tests/fuzz/regressions/poly_emit/name-in-power-comment.poly
if run $BIN/lens-eval $R --emit c -o $T/power.c 2>/dev/null && cc -std=c11 -Wall -Wextra -Werror -pedantic -c $T/power.c -o $T/power.o 2>$T/cc.err &&
   ! cc -E -P $T/power.c 2>/dev/null | grep -q INJECTED
then ok c_power_comment_escaped; else fail c_power_comment_escaped "$(head -3 $T/cc.err; grep -n INJECTED $T/power.c | head -3)"; fi
