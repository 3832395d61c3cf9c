#!/usr/bin/env bash
# The repository holds every file its tests, tools and examples use: no tracked file may
# name a folder beside the checkout (../shared, /work/shared), and the reference
# prescriptions the importers and tests read are tracked, each folder with its provenance.
. "$(dirname "$0")/lib.sh"
if ! git -C "$TOP" rev-parse --git-dir >/dev/null 2>&1; then ok "self_contained (skipped: not a git checkout)"; exit 0; fi
# This file names the pattern itself; every other tracked file must not.
hits=$(git -C "$TOP" grep -nIE '\.\./shared|/work/shared' -- . ':!tests/cli/self_contained.sh' || true)
if [ -z "$hits" ]; then ok "no tracked file names ../shared"; else fail "no tracked file names ../shared" "$(echo "$hits" | head -5 | tr '\n' ' ')"; fi
for d in lenses/reference/fx lenses/reference/pbrt; do
  n=$(git -C "$TOP" ls-files "$d" | grep -cE '\.(fx|dat)$')
  if [ "$n" -gt 0 ] && git -C "$TOP" ls-files --error-unmatch "$d/PROVENANCE.md" >/dev/null 2>&1; then ok "tracked $d ($n files, provenance)"
  else fail "tracked $d" "$n files; PROVENANCE.md tracked?"; fi
done
exit 0
