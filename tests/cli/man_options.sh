#!/usr/bin/env bash
# Options are documented where they are defined: each command's option table
# is the source of its --help and of the SYNOPSIS and OPTIONS sections of its man page.
# Fails when a man page and the table drift apart (an option added without `make man`, a
# section edited by hand), when --help lists an option the man page lacks, when a page
# does not render cleanly, or when --version is not the VERSION file's; and the usual
# spellings (-n5, --seed=2, --, clustered flags) give the same result as the spaced ones.
source "$(dirname "$0")/lib.sh"

version=$(cat VERSION)
for cmd in "$BIN"/lens-*; do
  verb=$(basename "$cmd")
  page=man/$verb.1
  if [ ! -f "$page" ]; then fail "man_$verb" "no $page"; continue; fi
  # the page as `make man` would leave it: the generated sections spliced into a copy
  cp "$page" "$T/$verb.1"
  run tools/man-options.sh "$T/$verb.1" "$cmd"
  for section in SYNOPSIS OPTIONS; do
    name=man_${section,,}_$verb
    if cmp -s <(sed -n "/^\.SH $section\$/,/^\.SH /p" "$page") <(sed -n "/^\.SH $section\$/,/^\.SH /p" "$T/$verb.1")
    then ok "$name"
    else fail "$name" "$page $section differs from '$verb --help-man' (run make man): $(diff "$page" "$T/$verb.1" | head -4 | tr '\n' ' ')"; fi
  done
  awk '/^\.SH OPTIONS/ { on = 1; next } on && /^\.SH / { exit } on' "$page" >"$T/$verb.section"
  # every option --help lists is in the man page's OPTIONS (with roff's \- for -)
  missing=""
  for o in $(run "$cmd" --help | grep -oE '^ +(-[a-zA-Z], )?--[a-z][a-z0-9-]*' | grep -oE -- '--[a-z0-9-]+$'); do
    grep -qF -- "\\fB$(sed 's/-/\\-/g' <<<"$o")\\fR" "$T/$verb.section" || missing="$missing $o"
  done
  if [ -z "$missing" ]; then ok "help_in_man_$verb"; else fail "help_in_man_$verb" "not in $page:$missing"; fi
  if command -v groff >/dev/null; then
    w=$(groff -man -ww -z "$page" 2>&1)
    if [ -z "$w" ]; then ok "man_renders_$verb"; else fail "man_renders_$verb" "$w"; fi
  fi
  v=$(run "$cmd" --version)
  if [ "$v" = "$verb (sparselens) $version" ]; then ok "version_$verb"; else fail "version_$verb" "'$v'"; fi
done

# Spellings: the same rays whichever way the options are written.
L=lenses/simple.lens
if [ -x "$BIN/lens-trace" ]; then
  run "$BIN/lens-trace" "$L" -n 5 --seed 3 >"$T/a.txt"
  ok_all=1
  for args in "-n5 --seed=3" "--seed 3 -qn5" "-q -n 5 --seed=3 -- $L"; do
    # shellcheck disable=SC2086
    if [ "${args% -- *}" != "$args" ]; then run "$BIN/lens-trace" $args >"$T/b.txt"
    else run "$BIN/lens-trace" "$L" $args >"$T/b.txt"; fi
    cmp -s "$T/a.txt" "$T/b.txt" || { ok_all=0; fail spellings "'$args' differs"; }
  done
  [ $ok_all = 1 ] && ok spellings
  expect_error "unknown option" "^lens-trace: unknown option '--nope' \(see --help\)$" "$BIN/lens-trace" "$L" --nope
  expect_error "flag with a value" "^lens-trace: --all takes no value" "$BIN/lens-trace" "$L" --all=1
  expect_error "missing value" "^lens-trace: --seed needs a value" "$BIN/lens-trace" "$L" --seed
  expect_error "range" "^lens-trace: -n: 0 is out of range 1\.\.1000000000$" "$BIN/lens-trace" "$L" -n0
fi
