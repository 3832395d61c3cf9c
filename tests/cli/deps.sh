#!/usr/bin/env bash
# Portability of `make deps` and the build: on a system where the libraries are present
# but there is no apt-get, dpkg or sudo (and, second, no pkg-config either), deps says
# what it skipped and succeeds, and the library's sources that include an outside
# library's headers and a command still compile, link and run with the flags the
# Makefile finds. A missing required part is named, with exit status 1.
. "$(dirname "$0")/lib.sh"
# A PATH with every command of this one except those hidden (first wins, as in a PATH).
restricted_path() { # DIR HIDDEN...
  local dir=$1 d f; shift
  local hidden=" $* "
  mkdir -p "$dir"
  local IFS=:
  for d in $PATH; do
    [ -d "$d" ] || continue
    for f in "$d"/*; do
      local b=${f##*/}
      [ -x "$f" ] && [ ! -e "$dir/$b" ] || continue
      case $hidden in *" $b "*) continue ;; esac
      ln -s "$f" "$dir/$b"
    done
  done
}
hide="apt apt-get apt-cache dpkg dpkg-query sudo parallel"
restricted_path "$T/p1" $hide
restricted_path "$T/p2" $hide pkg-config
for c in apt-get dpkg sudo; do
  [ ! -e "$T/p1/$c" ] || { fail "deps restricted PATH" "$c still on it"; exit 0; }
done

out=$(PATH=$T/p1 tools/install-deps.sh 2>&1); rc=$?
if [ $rc -eq 0 ] && grep -q 'installing nothing (apt-get is not on PATH)' <<<"$out" &&
   grep -q 'skipped (optional, not found): parallel' <<<"$out"; then ok "deps without apt-get/dpkg/sudo: says what it skipped"
else fail "deps without apt-get/dpkg/sudo" "rc $rc: $(tr '\n' ' ' <<<"$out")"; fi

out=$(PATH=$T/p1 DEPS_INSTALL=no CXX=/nonexistent/c++ tools/install-deps.sh 2>&1); rc=$?
if [ $rc -eq 1 ] && grep -q 'MISSING (required): c++' <<<"$out"; then ok "deps names a missing required part"
else fail "deps names a missing required part" "rc $rc: $(tr '\n' ' ' <<<"$out")"; fi

# Compile the library's sources that include an outside library's headers (cairo,
# OpenEXR, OpenCV, PROJ, LAPACKE), and compile and link commands against the built
# library, once with pkg-config and once with the Makefile's fallbacks (the OpenCV shim
# is in the library; lens-spot links it).
lib=$BUILD/liblens.a
[ -f "$lib" ] || { ok "deps build (skipped: $lib not built)"; exit 0; }
srcs=$(grep -lE '#include <(openexr|cairo|opencv2|geodesic|lapacke)' src/*/*.c src/*/*.cpp)
for p in p1 p2; do
  objs=$(sed -E "s#^src/(.*)\.(c|cpp)\$#$T/build-$p/src/\1.o#" <<<"$srcs")
  # shellcheck disable=SC2086
  if env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL PATH="$T/$p" make -s --no-print-directory \
       SANITIZE="$SANITIZE" BUILD="$T/build-$p" $objs >"$T/objs-$p.log" 2>&1; then
    what="without apt-get/dpkg/sudo"; [ $p = p2 ] && what="$what/pkg-config"
    ok "compile $what: $(echo $srcs | wc -w) sources that use outside headers"
  else fail "compile ${p}" "$(tail -3 "$T/objs-$p.log" | tr '\n' ' ')"; fi
done
for p in p1 p2; do
  env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL PATH="$T/$p" make -s --no-print-directory -o "$lib" \
    SANITIZE="$SANITIZE" BIN="$T/bin-$p" "$T/bin-$p/lens-info" "$T/bin-$p/lens-spot" >"$T/make-$p.log" 2>&1
  efl=$(PATH="$T/$p" run "$T/bin-$p/lens-info" lenses/dgauss.50mm.lens 2>/dev/null | value efl)
  rows=$(PATH="$T/$p" run "$T/bin-$p/lens-spot" lenses/dgauss.50mm.lens --fields 0 2>/dev/null | grep -vc '^#')
  what="without apt-get/dpkg/sudo"; [ $p = p2 ] && what="$what/pkg-config"
  if near "${efl:-0}" 50 1 && [ "${rows:-0}" -gt 0 ]; then ok "build $what (efl $efl)"
  else fail "build $what" "$(tail -3 "$T/make-$p.log" | tr '\n' ' ') efl '$efl'"; fi
done
exit 0
