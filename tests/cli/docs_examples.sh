#!/usr/bin/env bash
# Every example of the documentation runs as printed (tools/doc-examples.sh says what an
# example is): the README's "$ " lines in a plain copy of the repository (the files git
# tracks, plus new files not yet ignored, with nothing beside them), with
# bin/ the built commands; every man page's EXAMPLES as installed: `make install
# PREFIX=P DESTDIR=D` (then D/P moved to P, as a package is unpacked), and each
# installed page's examples run in an empty directory of their own with only P/bin's
# commands on PATH, lenses and scenes named by their short names. The installed pages'
# examples are those of man/ word for word (checked), so this runs man/'s too. New
# examples and new man pages are picked up by themselves. A failing example is one FAIL
# line with its file and line.
. "$(dirname "$0")/lib.sh"
for c in lens-info lens-trace lens-fit lens-eval; do
  [ -x "$BIN/$c" ] || { ok "docs_examples (skipped: $BIN/$c not built)"; exit 0; }
done
if ! git -C "$TOP" rev-parse --git-dir >/dev/null 2>&1; then ok "docs_examples (skipped: not a git checkout)"; exit 0; fi

# The plain copy: what git holds (and would hold after `git add -A`), nothing else.
clone=$T/docs/README.md
mkdir -p "$clone"
git -C "$TOP" ls-files -z --cached --others --exclude-standard |
  while IFS= read -r -d '' f; do [ -f "$TOP/$f" ] && printf '%s\0' "$f"; done |
  (cd "$TOP" && tar --null -T - -cf -) | tar -xf - -C "$clone"
ln -s "$TOP/$BIN" "$clone/bin"
[ -e "$clone/bin/lens-info" ] || { fail "docs_examples" "could not link bin/ into the copy"; exit 0; }

export XDG_CACHE_HOME=$T/cache
unset SPARSELENS_LENS_PATH SPARSELENS_SCENE_PATH SPARSELENS_GLASS_CATALOG
# The installed tree first: the README's and the section-3 pages' programs build with its
# sparselens.pc and run with its library (tests/cli/install.sh checks what lands where).
prefix=$T/prefix
env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make -s --no-print-directory -C "$TOP" install \
  SANITIZE="$SANITIZE" PREFIX="$prefix" DESTDIR="$T/stage" >"$T/install.log" 2>&1 &&
  mv "$T/stage$prefix" "$prefix" ||
  { fail "docs: make install" "$(tail -3 "$T/install.log" | tr '\n' ' ')"; exit 0; }
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig LD_LIBRARY_PATH=$prefix/lib
# The README sets up PATH itself (its first lines say how). One file after the other: the
# heavy examples (lens-trace, lens-fit, lens-render) already use every core, and pages
# side by side measured no faster (reports/suite-time.md).
tools/doc-examples.sh --run "$T/docs" README.md

# The man pages, installed.
pages=() differ=""
for m in man/*.[1-8]; do
  i=$prefix/share/man/man${m##*.}/${m##*/}
  pages+=("$i")
  cmp -s <(tools/doc-examples.sh --list "$m" | grep -v '^#@') <(tools/doc-examples.sh --list "$i" | grep -v '^#@') ||
    differ="$differ $m"
done
if [ -z "$differ" ]; then ok "installed man pages' examples are man/'s (${#pages[@]} pages)"
else fail "installed man pages' examples are man/'s" "differ:$differ"; fi
for c in "$prefix"/bin/lens-*; do
  [ "$(PATH="$prefix/bin:$PATH" command -v "${c##*/}")" = "$c" ] || { fail "docs man pages" "${c##*/} is not the installed one"; exit 0; }
done
# (reported by their names in man/: the installed pages' lines are man/'s)
PATH="$prefix/bin:$PATH" tools/doc-examples.sh --run "$T/docs" "${pages[@]}" |
  sed "s#$prefix/share/man/man[1-8]/#man/#"
exit 0
