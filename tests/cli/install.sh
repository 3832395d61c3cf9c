#!/usr/bin/env bash
# make install PREFIX=... DESTDIR=...: the commands, man pages (sections 1, 5, 7),
# lenses (with the reference prescriptions) and scenes land where they should; the
# installed man pages name no source-tree path, and every installed file they name is
# there; and the installed commands, from an empty directory with nothing but the staged
# prefix, find every lens and scene the installed pages' examples name by its short name.
# (The examples themselves run once, in tests/cli/docs_examples.sh, from the installed
# pages with the installed commands.)
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

pages=("$root"/share/man/man*/*)
set -f # the paths, globs among them, are expanded only by compgen
named=$(grep -ohE "$prefix/share/sparselens/[^ )\"'\\]*" "${pages[@]}" | sed 's/[.,;:]$//' | sort -u)
absent=""
for f in $named; do compgen -G "$dest$f" >/dev/null || absent="$absent $f"; done
set +f
if [ -z "$absent" ]; then ok "installed man pages name installed files ($(wc -w <<<"$named") paths)"
else fail "installed man pages name installed files" "not installed:$absent"; fi

# The short names of the examples: the first operand of a lens command, unless an
# example writes that file itself (after '>' or -o); a lens must load, a scene render.
(cd "$root/share/man" && "$TOP/tools/doc-examples.sh" --list man*/*) | grep -v '^#@' >"$T/examples"
made=$(grep -oE '(>|-o) *[^ |;&)>]+' "$T/examples" | sed -E 's/^(>|-o) *//' | sort -u)
operands() { # COMMAND-PATTERN: the operands after it, not made by an example
  grep -oE "(^|[|;&(] *)lens-($1) +[^ -][^ ]*" "$T/examples" | awk '{ print $NF }' | sort -u |
    grep -vxF -f <(printf '%s\n' $made) || true
}
lenses=$(operands 'info|trace|spot|distort|fan|field|mtf|layout') scenes=$(operands render)
bad=""
for name in $lenses; do
  (cd "$T/elsewhere" && PATH="$root/bin:$PATH" run lens-info "$name" >/dev/null 2>&1) || bad="$bad $name"
done
for name in $scenes; do
  (cd "$T/elsewhere" && PATH="$root/bin:$PATH" run lens-render "$name" -o scene.exr --exact --spp 1 -q \
    >/dev/null 2>&1) || bad="$bad $name"
done
n=$(($(wc -w <<<"$lenses") + $(wc -w <<<"$scenes")))
if [ -z "$bad" ] && [ "$(wc -w <<<"$scenes")" -gt 0 ]; then
  ok "installed commands find the lenses and scenes the examples name ($n: $(echo $lenses $scenes))"
else fail "installed commands find the lenses and scenes the examples name" "not found:$bad (of $n)"; fi
exit 0
