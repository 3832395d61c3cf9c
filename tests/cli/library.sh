#!/usr/bin/env bash
# The installed library (man 3 sparselens): a fresh `make install PREFIX=/usr
# DESTDIR=...` puts libsparselens.so (soname, version, dev link), libsparselens.a, the
# public headers alone and sparselens.pc in place; the shared library exports exactly what
# the public headers declare; and a C program and a C++ program (tests/lib/), built only
# through `pkg-config --cflags --libs sparselens` (shared, and --static against the
# archive), load a shipped lens, trace, fit, evaluate, make the camera and render a
# uniform emitter whose exposure (the mean weight of camera rays over the sensor) agrees
# with lens-render's of the same scene within 3 standard errors; a system fitted to one
# lens is refused by the camera of another.
. "$(dirname "$0")/lib.sh"
[ -f "$BUILD/liblens.a" ] || { ok "library (skipped: not built)"; exit 0; }
[ -z "$SANITIZE" ] || { ok "library (skipped under sanitizers: the installed library is the plain build's)"; exit 0; }
dest=$T/dest
env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make -s --no-print-directory -C "$TOP" install \
  PREFIX=/usr DESTDIR="$dest" >"$T/install.log" 2>&1 ||
  { fail "library: make install" "$(tail -3 "$T/install.log" | tr '\n' ' ')"; exit 0; }
lib=$dest/usr/lib
version=$(cat VERSION) major=$(cut -d. -f1 VERSION)
if [ -f "$lib/libsparselens.so.$version" ] && [ "$(readlink "$lib/libsparselens.so.$major")" = "libsparselens.so.$version" ] &&
   [ "$(readlink "$lib/libsparselens.so")" = "libsparselens.so.$major" ] && [ -f "$lib/libsparselens.a" ] &&
   [ -f "$lib/pkgconfig/sparselens.pc" ] && [ -f "$dest/usr/include/sparselens.h" ]; then
  ok "library installed: libsparselens.so.$version, its links, the archive, sparselens.pc"
else fail "library installed" "$(cd "$dest" && find . -path '*lib*' -o -path '*include*' | head -20 | tr '\n' ' ')"; fi
soname=$(readelf -d "$lib/libsparselens.so.$version" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
[ "$soname" = "libsparselens.so.$major" ] && ok "library soname $soname" || fail "library soname" "'$soname'"

# The headers installed are the umbrella's and nothing else; every one has extern "C".
want=$(sed -n 's,^#include "sparselens/\(.*\)",\1,p' include/sparselens.h | sort | tr '\n' ' ')
got=$(ls "$dest/usr/include/sparselens" | sort | tr '\n' ' ')
[ "$want" = "$got" ] && ok "library: only the public headers installed ($(wc -w <<<"$got"))" ||
  fail "library: only the public headers installed" "want '$want' got '$got'"
noguard=$(grep -L 'extern "C"' "$dest"/usr/include/sparselens/*.h)
[ -z "$noguard" ] && ok "library: every public header has extern \"C\"" || fail "library: extern C" "$noguard"
# A public header includes public headers alone (they compile by themselves installed).
for h in "$dest"/usr/include/sparselens/*.h "$dest/usr/include/sparselens.h"; do
  printf '#include "%s"\n' "$h" | c++ -x c++ -fsyntax-only -I"$dest/usr/include" - 2>>"$T/hdr.log" || echo "$h" >>"$T/hdr.bad"
done
[ ! -s "$T/hdr.bad" ] && ok "library: each public header compiles alone, as C++ too" ||
  fail "library: public headers alone" "$(cat "$T/hdr.bad") $(head -3 "$T/hdr.log")"

# Exported: exactly the functions and variables the public headers declare.
tools/public-symbols.sh cc include/sparselens.h >"$T/declared"
nm -D --defined-only "$lib/libsparselens.so.$version" | awk '$2 ~ /^[TDBR]$/ { sub(/@.*/, "", $3); print $3 }' |
  grep -v '^_' | sort -u >"$T/exported"
if cmp -s "$T/declared" "$T/exported"; then ok "library exports the public API alone ($(wc -l <"$T/declared") symbols)"
else fail "library exports" "$(diff "$T/declared" "$T/exported" | head -6 | tr '\n' ' ')"; fi

# Built through pkg-config alone (the staged tree: the sysroot prefixes its paths).
pc() { PKG_CONFIG_PATH=$lib/pkgconfig PKG_CONFIG_SYSROOT_DIR=$dest pkg-config "$@"; }
ver=$(pc --modversion sparselens)
[ "$ver" = "$version" ] && ok "pkg-config sparselens $ver" || fail "pkg-config --modversion" "'$ver'"
cflags=$(pc --cflags sparselens) libs=$(pc --libs sparselens) static=$(pc --static --libs sparselens)
# shellcheck disable=SC2086
cc -std=c11 -Wall -Wextra -Werror tests/lib/example.c $cflags $libs -lm -o "$T/ex_shared" 2>"$T/cc.log" &&
  c++ -std=c++17 -Wall -Wextra -Werror tests/lib/example.cpp $cflags $libs -o "$T/excpp_shared" 2>>"$T/cc.log" &&
  ok "C and C++ programs built with pkg-config --cflags --libs" || fail "build with pkg-config" "$(head -5 "$T/cc.log")"
# the archive: pkg-config --static's flags, the library named as the archive
# shellcheck disable=SC2086
cc -std=c11 tests/lib/example.c $cflags ${static/-lsparselens/-l:libsparselens.a} -o "$T/ex_static" 2>"$T/ccs.log" &&
  c++ -std=c++17 tests/lib/example.cpp $cflags ${static/-lsparselens/-l:libsparselens.a} -o "$T/excpp_static" 2>>"$T/ccs.log" &&
  ! readelf -d "$T/ex_static" | grep -q libsparselens &&
  ok "C and C++ programs built with pkg-config --static against libsparselens.a" || fail "static build" "$(head -5 "$T/ccs.log")"
readelf -d "$T/ex_shared" | grep -q "NEEDED.*libsparselens.so.$major" && ok "shared program needs libsparselens.so.$major" ||
  fail "shared program" "$(readelf -d "$T/ex_shared" | grep NEEDED | tr '\n' ' ')"

# Run them: the installed data directory is /usr/share/sparselens, not there yet, so the
# lenses are named by their files here.
export LD_LIBRARY_PATH=$lib XDG_CACHE_HOME=$T/cache
run "$BIN/lens-trace" lenses/dgauss.50mm.lens -n 4000 --seed 3 -o "$T/samples.txt"
N=100000
for kind in shared static; do
  out=$(cd "$T" && "./ex_$kind" "$TOP/lenses/dgauss.50mm.lens" samples.txt "$TOP/lenses/fisheye-ii.lens" $N 2>&1)
  echo "$out" >"$T/ex_$kind.out"
  efl=$(value efl <<<"$out")
  near "${efl:-0}" 50.358 0.01 && grep -q '^axis_ray passed 0 0$' <<<"$out" &&
    ok "C program ($kind): lens loaded (efl $efl), axis ray traced" || fail "C program ($kind)" "$out"
done
out=$(cat "$T/ex_shared.out")
# the fits: within a few micrometres of the exact trace on rays they did not see
for k in fit_memory_rms_out_x fit_file_rms_out_x; do
  e=$(value $k <<<"$out")
  awk -v e="${e:-1}" 'BEGIN { exit !(e < 0.01) }' && ok "C program: $k $e mm" || fail "C program: $k" "$out"
done
[ "$(sed -n 's/^fit_file_lens //p' <<<"$out")" = "$(sed -n 's/^# lens: //p' "$T/samples.txt")" ] &&
  ok "C program: the file's fit records its lens" || fail "C program: fit_file_lens" "$out"
# the same bits but where the AVX-512 batch kernel fuses a multiply-add (poly_eval.c,
# KERNEL_FMA): a rounding, far below a nanometre
near "$(value batch_vs_one <<<"$out")" 0 1e-12 && ok "C program: batch and one-ray evaluation agree" ||
  fail "C program: batch_vs_one" "$out"
grep -q "^mismatch .*fisheye-ii.lens: the system was fitted to 'Double Gauss 50mm f/2 (Tronnier)', not to this lens 'AF DX Fisheye" <<<"$out" &&
  ok "camera refuses a system fitted to another lens" || fail "camera mismatch" "$(grep mismatch <<<"$out")"
cmp -s "$T/ex_shared.out" "$T/ex_static.out" && ok "C program: shared and static give the same output" ||
  fail "C program: shared vs static" "$(diff "$T/ex_shared.out" "$T/ex_static.out" | head -4)"

# lens-render's exposure of the same scene: one pixel over the whole sensor, read back as
# the RMS difference against a black render (grey: R = G = B, so the RMS is the pixel).
spp=200000
printf 'camera %s\nsensor 36 24\nresolution 1 1\nmode grey\nspp %d\nplane 0 0 1000 0 0 -1 emit %s\n' \
  "$TOP/lenses/dgauss.50mm.lens" $spp 1 >"$T/white.scene"
sed 's/emit 1$/albedo 0/' "$T/white.scene" >"$T/black.scene"
run "$BIN/lens-render" "$T/black.scene" --exact -q --spp 1 -o "$T/black.exr"
ref=$(run "$BIN/lens-render" "$T/white.scene" --exact -q -o "$T/white.exr" --reference "$T/black.exr" 2>&1 |
      sed -n 's/^error vs .*: rms \([0-9.e+-]*\) .*/\1/p')
out_cpp=$(cd "$T" && ./excpp_shared "$TOP/lenses/dgauss.50mm.lens" example.poly $N 2>&1)
out_cpps=$(cd "$T" && ./excpp_static "$TOP/lenses/dgauss.50mm.lens" example.poly $N 2>&1)
e=$(value system_rms_out_x <<<"$out_cpp")
awk -v e="${e:-1}" 'BEGIN { exit !(e < 0.01) }' && ok "C++ program: the system read back, $e mm from the trace" ||
  fail "C++ program" "$out_cpp"
[ "$out_cpp" = "$out_cpps" ] && ok "C++ program: shared and static agree" || fail "C++ program: shared vs static" "$out_cpps"
# lens-render's own standard error is at most a program's scaled to its spp (its samples
# are stratified): the bound is 3 sqrt(se^2 + se^2 N / spp)
for v in "C:$out" "C++:$out_cpp"; do
  name=${v%%:*} o=${v#*:}
  m=$(value exposure <<<"$o") se=$(value exposure_se <<<"$o")
  if [ -n "$ref" ] && [ -n "$m" ] && awk -v a="$m" -v b="$ref" -v s="$se" -v n=$N -v k=$spp \
       'BEGIN { d = a - b; if (d < 0) d = -d; t = 3 * sqrt(s * s * (1 + n / k)); exit !(d <= t && s > 0 && s < 0.01 * a) }'; then
    ok "$name program's uniform emitter $m (se $se) matches lens-render's $ref"
  else fail "$name program's uniform emitter" "program '$m' se '$se', lens-render '$ref'"; fi
done
