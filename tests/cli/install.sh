#!/usr/bin/env bash
# make install PREFIX=... DESTDIR=...: the commands, man pages (sections 1, 5, 7),
# lenses (with the reference prescriptions) and scenes land where they should; the
# installed man pages name no source-tree path; and the installed commands, from an
# empty directory with nothing but the staged prefix, run every installed man page's
# examples, lenses and scenes named by their short names.
. "$(dirname "$0")/lib.sh"
[ -f "$BUILD/liblens.a" ] || { ok "install (skipped: not built)"; exit 0; }
dest=$T/dest prefix=/opt/sparselens
env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make -s --no-print-directory -C "$TOP" install \
  SANITIZE="$SANITIZE" PREFIX=$prefix DESTDIR="$dest" >"$T/install.log" 2>&1 ||
  { fail "make install" "$(tail -3 "$T/install.log" | tr '\n' ' ')"; exit 0; }
root=$dest$prefix
missing=""
for c in cmd/lens-*.c; do c=$(basename "$c" .c); [ -x "$root/bin/$c" ] || missing="$missing bin/$c"; done
for m in man/*.[1-8]; do
  s=${m##*.}; [ -f "$root/share/man/man$s/$(basename "$m")" ] || missing="$missing $m"
done
for f in lenses/*.lens lenses/glass.catalog lenses/reference/fx/fisheye-ii.fx \
         lenses/reference/pbrt/PROVENANCE.md scenes/dgauss.scene; do
  [ -f "$root/share/sparselens/$f" ] || missing="$missing share/sparselens/$f"
done
if [ -z "$missing" ]; then ok "make install: commands, man pages, lenses, scenes"
else fail "make install" "missing:$missing"; fi

# Installed pages point at installed files: no bin/, tests/data, or bare lenses/ and
# scenes/ of the source tree.
bad=$(grep -nE '(^|[ (])(bin/lens-|tests/data|lenses/|scenes/)' "$root"/share/man/man*/* | head -3)
if [ -z "$bad" ]; then ok "installed man pages name installed paths"
else fail "installed man pages name installed paths" "$bad"; fi

# From an empty directory, with only the staged prefix (no source tree, no lens path).
export XDG_CACHE_HOME=$T/cache
unset SPARSELENS_LENS_PATH SPARSELENS_SCENE_PATH SPARSELENS_GLASS_CATALOG
mkdir -p "$T/elsewhere"
efl=$(cd "$T/elsewhere" && PATH="$root/bin:$PATH" run lens-info dgauss.50mm 2>/dev/null | value efl)
if near "${efl:-0}" 50.358 0.01; then ok "installed lens-info dgauss.50mm by short name"
else fail "installed lens-info dgauss.50mm by short name" "efl '$efl'"; fi
(cd "$root/share/man" && PATH="$root/bin:$PATH" "$TOP/tools/doc-examples.sh" --run "$T/elsewhere" man*/*)
exit 0
