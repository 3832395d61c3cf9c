#!/usr/bin/env bash
# Regenerates lenses/*.lens from the reference prescriptions in
# lenses/reference (fx/*.fx and pbrt/*.dat) through `lens-info FILE --format lens`,
# adding a header: name, source (file and patent or book), nominal focal length and
# f-number as the source states them, and a sensor that fits the lens.
#
# Sensors: the lens's format where the source names one (36x24 for 35 mm lenses, APS-C
# 23.6x15.7 for the DX fisheye-ii); otherwise, and for circular fisheyes, a sensor whose
# half-diagonal lies inside the image circle as lens-info computes it (the largest image
# radius a real chief ray reaches; see image_circle_radius in lens-info(1)).
# Skipped: canon-anamorphic.fx (cylindrical surfaces: not rotationally symmetric).
# nikon-zoom.fx is taken at its first (short) zoom position.
#
# Usage: tools/import-reference-lenses.sh [REFERENCE_DIR]   (run from the repository root)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-bin}
REF=${1:-lenses/reference}
[ -x "$BIN/lens-info" ] || { echo "import-reference-lenses: $BIN/lens-info missing: run make" >&2; exit 1; }
[ -d "$REF" ] || { echo "import-reference-lenses: $REF: no such directory" >&2; exit 1; }

# base|file|name|source|focal|fnumber|sensor|note ("-" = none)
table() {
cat <<'TABLE'
brendel-tessar|fx/brendel-tessar.fx|Brendel Tessar 100mm f/2.8|brendel-tessar.fx (EGSR 2016 lens set); US 2,854,889|100|2.8|36x24|-
double-gauss-angenieux|fx/double-gauss-angenieux.fx|Angenieux double Gauss f/1.1, scaled to 50 mm|double-gauss-angenieux.fx (EGSR 2016 lens set); US 2,701,982|50|1.1|23.6x15.7|the image circle (radius 18.6 mm) is too small for 36x24
double-gauss|fx/double-gauss.fx|Modified 4-member Gauss projection objective|double-gauss.fx (EGSR 2016 lens set); US 3,376,090, table F|100|-|36x24|focal: the patent table is normalised to f = 100 (paraxial EFL 99.95 mm)
fisheye-aspherical|fx/fisheye-aspherical.fx|181-degree aspherical fisheye|fisheye-aspherical.fx (EGSR 2016 lens set); Japanese patent application (J-PlatPat)|9.7|-|23.6x15.7|focal: not stated by the source; 9.7 is the paraxial EFL. Circular fisheye: the sensor lies inside the image circle (radius 14.9 mm)
fisheye-ii|fx/fisheye-ii.fx|AF DX Fisheye-Nikkor 10.5mm f/2.8G ED|fisheye-ii.fx (EGSR 2016 lens set, after pierretoscani.com); US 7,161,746 B2|10.5|2.8|23.6x15.7|sensor: the DX format the lens is made for; chief rays reach 13.9 mm, so the corners (14.2 mm) are lit only by rays off the chief ray
fisheye-iii|fx/fisheye-iii.fx|270-degree fisheye|fisheye-iii.fx (EGSR 2016 lens set, after pierretoscani.com); US 3,524,697|10|-|27.9x18.6|focal: not stated by the source; the prescription is normalised to f = 10 (paraxial EFL 10.0 mm). Circular fisheye: the sensor lies inside the image circle (radius 20.6 mm)
fisheye|fx/fisheye.fx|220-degree fisheye (Shimizu)|fisheye.fx (EGSR 2016 lens set), the uncommented prescription|6.3|-|17.3x13|focal: not stated by the source; 6.3 is the paraxial EFL. Circular fisheye: the sensor lies inside the image circle (radius 12.2 mm)
kreitzer-tele|fx/kreitzer-tele.fx|Kreitzer telephoto, scaled by 4 for 35 mm film|kreitzer-tele.fx (EGSR 2016 lens set); US 4,359,272|400|5.6|36x24|-
lensbaby|fx/lensbaby.fx|Achromatic doublet (Edmund Optics #NT32-921) with a stop behind it|lensbaby.fx (EGSR 2016 lens set); Edmund Optics #NT32-921|120|-|36x24|focal: Edmund's EFL for this doublet; the file's comment says f ~= 129 mm
nikon-zoom|fx/nikon-zoom.fx|Nikon 80-200mm f/2.8 zoom, short position|nikon-zoom.fx (EGSR 2016 lens set); Japanese patent S.53-131852; Modern Lens Design 2nd ed., p. 527, fig. 20.3|80|2.8|23.6x15.7|focal: the source's nominal 80 mm; this prescription's paraxial EFL is 57.2 mm at the first position (about 0.715 of the nominal scale), so APS-C, inside its image circle (radius 19.9 mm), rather than 36x24
petzval|fx/petzval.fx|Petzval portrait lens, scaled by 0.75|petzval.fx (EGSR 2016 lens set), after J. Sasian, OPTI 517 lecture 16|112.5|-|23.6x15.7|focal: the source's f = 150 mm scaled by 0.75; this prescription's paraxial EFL is 64.6 mm. The image circle (radius 16.5 mm) is too small for 36x24
simple|fx/simple.fx|Simple singlet with a rear stop|simple.fx (EGSR 2016 lens set)|38.7|-|36x24|focal: not stated by the source; 38.7 is the paraxial EFL
wideangle-ii|fx/wideangle-ii.fx|Wide-angle lens (second variant)|wideangle-ii.fx (EGSR 2016 lens set); cf. US 4,310,222|14.3|-|17.3x13|focal: not stated by the source; 14.3 is the paraxial EFL. The sensor lies inside the image circle (radius 11.0 mm)
wideangle|fx/wideangle.fx|Wide-angle lens|wideangle.fx (EGSR 2016 lens set); US 4,310,222|14.3|-|16x12|focal: not stated by the source; 14.3 is the paraxial EFL. The sensor lies inside the image circle (radius 10.3 mm)
dgauss.50mm|pbrt/dgauss.50mm.dat|Double Gauss 50mm f/2 (Tronnier)|pbrt dgauss.50mm.dat; US 2,673,491; Modern Lens Design p. 312, scaled to 50 mm|50|2|36x24|-
fisheye.10mm|pbrt/fisheye.10mm.dat|Muller 16mm f/4 fisheye, scaled to 10 mm|pbrt fisheye.10mm.dat; Modern Lens Design p. 164|10|4|21x14|the sensor lies inside the image circle (radius 13.1 mm)
telephoto.250mm|pbrt/telephoto.250mm.dat|Sigler super achromat telephoto 250mm f/5.6|pbrt telephoto.250mm.dat; Modern Lens Design p. 175, scaled to 250 mm|250|5.6|36x24|-
wide|pbrt/wide.dat|Nakamura wide-angle lens (38 degrees)|pbrt wide.dat; Modern Lens Design p. 360|100|-|130x86.7|focal: Modern Lens Design's normalisation to f = 100 (paraxial EFL 100.1 mm); sensor: 38 degrees taken as the half field, half-diagonal 100 tan 38° = 78 mm, inside the image circle (radius 108 mm)
TABLE
}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
n=0
while IFS='|' read -r base file name source focal fnumber sensor note; do
  out=lenses/$base.lens
  "$BIN/lens-info" "$REF/$file" --format lens --sensor "$sensor" >"$tmp/body"
  {
    echo "# name: $name"
    echo "# source: $source"
    echo "# focal: $focal"
    [ "$fnumber" = - ] || echo "# fnumber: $fnumber"
    [ "$note" = - ] || echo "# note: $note"
    grep -vE '^# (name|source|focal|fnumber):' "$tmp/body"
  } >"$tmp/$base.lens"
  # What we ship must read back.
  "$BIN/lens-info" "$tmp/$base.lens" --format lens >/dev/null
  mv "$tmp/$base.lens" "$out"
  n=$((n + 1))
done < <(table)
echo "import-reference-lenses: wrote $n lenses to lenses/"
