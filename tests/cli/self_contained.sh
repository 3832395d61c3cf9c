#!/usr/bin/env bash
# The repository holds every file its tests, tools and examples use: no tracked file may
# name a folder beside the checkout (where its source material came from), and the reference
# prescriptions the importers and tests read are tracked, each folder with its provenance.
. "$(dirname "$0")/lib.sh"
if ! git -C "$TOP" rev-parse --git-dir >/dev/null 2>&1; then ok "self_contained (skipped: not a git checkout)"; exit 0; fi
# The folder's name is assembled so that this file does not name it either.
outside=shared
hits=$(git -C "$TOP" grep -nIE "\\.\\./$outside|/work/$outside" -- . || true)
if [ -z "$hits" ]; then ok "no tracked file names the folder beside the checkout"; else fail "no tracked file names the folder beside the checkout" "$(echo "$hits" | head -5 | tr '\n' ' ')"; fi
for d in lenses/reference/fx lenses/reference/pbrt; do
  n=$(git -C "$TOP" ls-files "$d" | grep -cE '\.(fx|dat)$')
  if [ "$n" -gt 0 ] && git -C "$TOP" ls-files --error-unmatch "$d/PROVENANCE.md" >/dev/null 2>&1; then ok "tracked $d ($n files, provenance)"
  else fail "tracked $d" "$n files; PROVENANCE.md tracked?"; fi
done
exit 0
