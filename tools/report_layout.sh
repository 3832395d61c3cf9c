#!/usr/bin/env bash
# The layout section of reports/<lens>.md (the first picture of every lens report):
# draws OUT_DIR/lenses/<lens>-layout.png with lens-layout and prints the Markdown that
# shows it with the command that made it. Called by tools/report_lens.sh; also alone, to
# splice the section into a report without sweeping again.
#   tools/report_layout.sh LENS OUT_DIR
set -euo pipefail
lens=$1 out=$2
BIN=${BIN:-bin}
name=$(basename "$lens" .lens)
mkdir -p "$out/lenses"
# fields: the axis, 0.7 and 1 of the half field of view of the sensor diagonal (as the
# other commands' defaults), drawn with 7 rays each
cmd=("$BIN"/lens-layout "$lens" --rays 7 --width 1000 --png "$out/lenses/$name-layout.png")
# exit 2: a field the lens cannot image (its rays drawn as far as they go, a warning
# naming it); the picture is made and the warning goes into the report
rc=0
txt=$("${cmd[@]}" 2>&1) || rc=$?
[ "$rc" = 0 ] || [ "$rc" = 2 ] || { echo "report_layout: $name: $txt" >&2; exit 1; }
echo "## Layout (\`lens-layout $lens --rays 7 --width 1000 --png $out/lenses/$name-layout.png\`)"
echo
echo "![meridional section with ray bundles](lenses/$name-layout.png)"
echo
echo "$txt" | grep '^# rays' | sed 's/^# rays/Rays/'
echo "$txt" | grep '^lens-layout: warning: ' | sed 's/^lens-layout: warning: /Warning: /' || true
echo
