#!/usr/bin/env bash
# Pictures through cairo: PNG, and SVG/PDF by the file name; a system drawn over its lens
# in lens-distort's grid map leaves the lens visible (both colours cover many pixels);
# the titles state f-number, object and focus.
source "$(dirname "$0")/lib.sh"
command -v python3 >/dev/null || { ok "pictures (skipped: no python3)"; exit 0; }
DG=lenses/dgauss.50mm.lens

# count_rgb PNG R G B TOL: pixels within TOL (0..255) of the colour (8-bit RGB or RGBA PNG)
count_rgb() {
  python3 - "$@" <<'PY'
import struct, sys, zlib
path, r, g, b, tol = sys.argv[1], *map(int, sys.argv[2:6])
data = open(path, 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n'
pos, idat, w = 8, b'', 0
while pos < len(data):
    n, kind = struct.unpack('>I4s', data[pos:pos + 8]); body = data[pos + 8:pos + 8 + n]; pos += 12 + n
    if kind == b'IHDR': w, h, depth, ctype = struct.unpack('>IIBB', body[:10])
    if kind == b'IDAT': idat += body
bpp = {2: 3, 6: 4}[ctype]; raw = zlib.decompress(idat); stride = w * bpp
prev, rows, i = bytearray(stride), [], 0
for y in range(h):
    f = raw[i]; line = bytearray(raw[i + 1:i + 1 + stride]); i += 1 + stride
    for x in range(stride):
        a = line[x - bpp] if x >= bpp else 0; up = prev[x]; c = prev[x - bpp] if x >= bpp else 0
        if f == 1: line[x] = (line[x] + a) & 255
        elif f == 2: line[x] = (line[x] + up) & 255
        elif f == 3: line[x] = (line[x] + (a + up) // 2) & 255
        elif f == 4:
            p = a + up - c; pa, pb, pc = abs(p - a), abs(p - up), abs(p - c)
            line[x] = (line[x] + (a if pa <= pb and pa <= pc else up if pb <= pc else c)) & 255
    rows.append(line); prev = line
print(sum(1 for line in rows for x in range(0, stride, bpp)
          if abs(line[x] - r) <= tol and abs(line[x + 1] - g) <= tol and abs(line[x + 2] - b) <= tol))
PY
}

run $BIN/lens-trace $DG -n 20000 --seed 1 --no-passage-columns -o $T/train.txt 2>/dev/null
run $BIN/lens-fit -q --terms 12 -o $T/dg.poly $T/train.txt 2>/dev/null
run $BIN/lens-distort $DG --compare $T/dg.poly --fields 0,10,20 --illum-rays 0 --png $T/g.png >$T/g.txt 2>/dev/null
# lens: (0.05, 0.3, 0.8) wide and solid; system: (0.85, 0.15, 0.1) thin and dashed, on top
blue=$(count_rgb $T/g.png 13 77 204 40) red=$(count_rgb $T/g.png 217 38 26 40)
if [ "${blue:-0}" -gt 10000 ] && [ "${red:-0}" -gt 1000 ]
then ok distort_compare_both_visible; else fail distort_compare_both_visible "lens $blue px, system $red px"; fi

# vector output by the file name
run $BIN/lens-spot $DG --fields 0,10 --rays 60 --png $T/s.svg >/dev/null
run $BIN/lens-distort $DG --fields 0,10 --illum-rays 0 --png $T/d.pdf >/dev/null
if head -c 200 $T/s.svg | grep -q '<svg' && [ "$(head -c 5 $T/d.pdf)" = "%PDF-" ] && ! ls $T | grep -q tmp
then ok pictures_svg_pdf; else fail pictures_svg_pdf "$(head -c 100 $T/s.svg)"; fi

# Text on the pictures (SPARSELENS_TEXT_BOXES: each text's ink box, canvas_cairo.c): every
# label inside its picture and whole (no title cut to an ellipsis, a one-field spot
# picture too), no two overprinting, µm never written "um"; the second title line states
# f-number, object and focus (fisheye-ii's file is focused at 77 mm, the Angenieux's
# sensor short of the infinity focus: a negative focus distance, said so).
export SPARSELENS_TEXT_BOXES=$T/boxes.txt
FE=lenses/fisheye-ii.lens
run $BIN/lens-spot $DG --compare $T/dg.poly --fields 0,10,20 --rays 60 --png $T/sc.png >/dev/null 2>&1
run $BIN/lens-distort $DG --compare $T/dg.poly --fields 0,10,20 --illum-rays 0 --png $T/dc.png >/dev/null 2>&1
run $BIN/lens-spot $FE --fnumber 4 --rays 40 --png $T/fe.png >/dev/null 2>&1
run $BIN/lens-spot lenses/double-gauss-angenieux.lens --fields 0 --rays 40 --png $T/ag.png >/dev/null 2>&1
for c in fan field layout; do run $BIN/lens-$c $DG --compare $T/dg.poly --png $T/$c.png >/dev/null 2>&1; done
unset SPARSELENS_TEXT_BOXES
out=$(python3 - $T/boxes.txt <<'PY'
import re, sys
pics, cur = [], None
for line in open(sys.argv[1], encoding='utf-8'):
    line = line.rstrip('\n')
    if line.startswith('# picture '):
        path, w, h = line[10:].rsplit(' ', 2)
        cur = (path.rsplit('/', 1)[-1], float(w), float(h), []); pics.append(cur); continue
    x0, y0, x1, y1, text = line.split(' ', 4)
    cur[3].append((float(x0), float(y0), float(x1), float(y1), text))
bad = []
for name, w, h, boxes in pics:
    for b in boxes:
        if b[0] < -0.5 or b[1] < -0.5 or b[2] > w + 0.5 or b[3] > h + 0.5:
            bad.append('%s: "%s" leaves the %gx%g picture' % (name, b[4], w, h))
        if re.search(r'\bum\b', b[4]): bad.append('%s: "um" in "%s"' % (name, b[4]))
        if '…' in b[4]: bad.append('%s: cut: "%s"' % (name, b[4]))
    for i in range(len(boxes)):
        for j in range(i):
            a, b = boxes[i], boxes[j]
            if min(a[2], b[2]) - max(a[0], b[0]) > 0.5 and min(a[3], b[3]) - max(a[1], b[1]) > 0.5:
                bad.append('%s: "%s" overprints "%s"' % (name, a[4], b[4]))
    if name != 'layout.png' and not any('µm' in b[4] for b in boxes): bad.append('%s: no µm' % name)
titles = {name: ' '.join(b[4] for b in boxes[:2]) for name, w, h, boxes in pics}
for name, want in [('sc.png', 'f/2.03, object at infinity, sensor as in the file (focused at infinity)'),
                   ('dc.png', 'f/2.03, object at infinity'),
                   ('fe.png', 'f/4, object at infinity, sensor as in the file (focused at 77.23 mm)'),
                   ('ag.png', 'f/1.14, object at infinity, sensor as in the file (0.00296 mm short of the infinity focus)'),
                   ('fan.png', 'f/2.03, object at infinity'), ('field.png', 'f/2.03'), ('layout.png', 'f/2.03')]:
    if want not in titles.get(name, ''): bad.append('%s: title "%s" lacks "%s"' % (name, titles.get(name), want))
print(len(pics), 'pictures,', sum(len(p[3]) for p in pics), 'texts')
print('\n'.join(bad))
PY
)
if [ "$(head -1 <<<"$out")" = "7 pictures, $(grep -vc '^#' $T/boxes.txt) texts" ] && [ -z "$(tail -n +2 <<<"$out")" ]
then ok "picture texts inside, not overprinting, µm, titles state f-number and focus ($(head -1 <<<"$out"))"
else fail "picture texts" "$(tr '\n' ';' <<<"$out")"; fi
