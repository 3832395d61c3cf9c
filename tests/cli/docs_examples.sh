#!/usr/bin/env bash
# Every example of the documentation runs as printed (tools/doc-examples.sh says what an
# example is): the README's "$ " lines in a plain copy of the repository (the files git
# tracks, plus new files not yet ignored, with nothing beside them), with
# bin/ the built commands; every man page's EXAMPLES in an empty directory, with the
# built commands on PATH and lenses named as a user names them. New examples and new
# man pages are picked up by themselves. A failing example is one FAIL line with its
# file and line.
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
# The README sets up PATH itself (its first lines say how); man pages expect the
# commands on PATH, as after `make install` (tests/cli/install.sh checks that the
# installed pages name only installed files). One file after the other: the heavy
# examples (lens-trace, lens-fit, lens-render) already use every core, and pages side by
# side measured no faster (reports/suite-time.md).
tools/doc-examples.sh --run "$T/docs" README.md
PATH="$TOP/$BIN:$PATH" tools/doc-examples.sh --run "$T/docs" man/*.[1-8]
exit 0
