#!/usr/bin/env bash
# Output for scripts: --json parses and holds the numbers of the text; --precision; units
# on lens-info's keys; round-off about zero printed as 0; lens-info's warnings about the
# data (f-number and focal length against the header, the focus distance); --fnumber.
source "$(dirname "$0")/lib.sh"
command -v python3 >/dev/null || { ok "script_output (skipped: no python3)"; exit 0; }
FE=lenses/fisheye-ii.lens KT=lenses/kreitzer-tele.lens DG=lenses/dgauss.50mm.lens

# same_numbers TEXT JSON TABLE: every row of the text's first table equals the JSON table's
# row by row and column by column (numbers compared as numbers, nan as null)
same_numbers() {
  python3 - "$1" "$2" "$3" <<'PY'
import json, math, sys
text, js, table = sys.argv[1:4]
data = json.load(open(js))
cols, rows = None, []
for line in open(text):
    if line.startswith('# columns:'):
        if cols is not None: break
        cols = line.split()[2:]; continue
    if line.startswith('#') or not line.strip():
        if cols is not None and rows: break
        continue
    rows.append(line.split())
jr = data[table]
assert len(jr) == len(rows), (len(jr), len(rows))
for r, o in zip(rows, jr):
    for c, v in zip(cols, r):
        w = o[c]
        if v == 'nan': assert w is None, (c, v, w); continue
        try: f = float(v)
        except ValueError: assert w == v, (c, v, w); continue
        if isinstance(w, str): assert w == v, (c, v, w); continue
        assert f == w, (c, v, w)
PY
}

# lens-info: key value unit; the JSON has the same values, the units and the warnings
run $BIN/lens-info $DG >$T/i.txt 2>$T/i.err
run $BIN/lens-info $DG --json >$T/i.json 2>/dev/null
if python3 -m json.tool $T/i.json >/dev/null && grep -qx 'efl 50.35816696 mm' $T/i.txt &&
   grep -qx 'field_of_view_deg 47.19519566 deg' $T/i.txt && grep -qx 'stop_surface 6 -' $T/i.txt &&
   python3 - $T/i.txt $T/i.json <<'PY'
import json, sys
d = json.load(open(sys.argv[2]))
for line in open(sys.argv[1]):
    k, *rest = line.split()
    if k == 'name': continue
    v, unit = rest
    if v in ('inf', '-inf', 'nan'): assert d[k] is None, (k, v, d[k])
    else: assert str(d[k]) == v or float(d[k]) == float(v), (k, v, d[k])
    assert d['units'][k] == unit, (k, unit)
assert d['warnings'] == []
PY
then ok info_json_units; else fail info_json_units "$(cat $T/i.txt)"; fi
if [ ! -s $T/i.err ] && [ "$(run $BIN/lens-info $DG --precision 3 | value efl)" = 50.4 ]
then ok info_precision_no_warning; else fail info_precision_no_warning "$(cat $T/i.err)"; fi

# a designer's questions: fisheye-ii computes f/1.75 for a lens labelled f/2.8 and is
# focused at 77 mm; kreitzer-tele f/3.11 against f/5.6, focused "past infinity"
run $BIN/lens-info $FE >/dev/null 2>$T/fe.err
run $BIN/lens-info $KT --json >$T/kt.json 2>$T/kt.err
run $BIN/lens-info fisheye >/dev/null 2>$T/fo.err
if grep -q "^lens-info: warning: $FE: the computed f-number (1.749) differs from the header's (2.8) by 38 %" $T/fe.err &&
   grep -q "^lens-info: warning: $FE: focus_distance 77.226 mm: the sensor is focused on a near object, 1.07 mm behind the infinity focus" $T/fe.err &&
   grep -q "^lens-info: warning: $KT: the computed f-number (3.112) differs from the header's (5.6)" $T/kt.err &&
   grep -q "^lens-info: warning: $KT: focus_distance -519887 mm is negative: the sensor is 0.309 mm nearer the lens than the infinity focus" $T/kt.err &&
   grep -q "^lens-info: warning: fisheye: focus_distance -32.5445 mm is negative: the sensor is 2.14 mm beyond the infinity focus" $T/fo.err &&
   [ "$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["warnings"]))' $T/kt.json)" = "$(grep -c warning $T/kt.err)" ]
then ok info_questions_the_data; else fail info_questions_the_data "$(cat $T/fe.err $T/kt.err)"; fi

# the focal length against the header's: 50.358 mm against 60 is 16 % off (a warning),
# against 52 it is 3.2 %, within the 5 % a header's round figure may be off (none)
sed 's/^# focal: .*/# focal: 60/' $DG >$T/f60.lens; sed 's/^# focal: .*/# focal: 52/' $DG >$T/f52.lens
run $BIN/lens-info $T/f60.lens >/dev/null 2>$T/f60.err; run $BIN/lens-info $T/f52.lens >/dev/null 2>$T/f52.err
if grep -qx "lens-info: warning: $T/f60.lens: the computed focal length (50.36 mm) differs from the header's (60 mm) by 16 %: check the prescription or the header" $T/f60.err &&
   [ "$(grep -c . $T/f60.err)" = 1 ] && [ ! -s $T/f52.err ]
then ok info_questions_focal_length; else fail info_questions_focal_length "$(cat $T/f60.err $T/f52.err)"; fi

# lens-spot: round-off about zero is 0 (the on-axis centroid cancels to ~1e-13 mm), and
# the JSON rows equal the text rows
run $BIN/lens-spot $FE --fields 0,60 --rays 60 >$T/s.txt
run $BIN/lens-spot $FE --fields 0,60 --rays 60 --json >$T/s.json
if [ "$(awk '$2 == 0 { print $9, $10 }' $T/s.txt | sort -u)" = "0 0" ] && python3 -m json.tool $T/s.json >/dev/null &&
   same_numbers $T/s.txt $T/s.json spots &&
   grep -q '^# AF DX Fisheye-Nikkor 10.5mm f/2.8G ED: f/1.75, object at infinity, sensor as in the file (focused at 77.23 mm)$' $T/s.txt
then ok spot_json_roundoff_setup; else fail spot_json_roundoff_setup "$(cat $T/s.txt)"; fi
# --precision sets the digits of every number
if [ "$(run $BIN/lens-spot $FE --fields 60 --wavelengths d --rays 60 --precision 3 | awk '!/^#/ { print $8, $11 }')" = "9.92 99.3" ]
then ok spot_precision; else fail spot_precision; fi

# lens-distort: the JSON rows equal the text rows; fits and best mapping are there too
run $BIN/lens-distort $FE --fields 0,30,60,90 --illum-rays 4 --opencv 2000x1330 >$T/d.txt
run $BIN/lens-distort $FE --fields 0,30,60,90 --illum-rays 4 --opencv 2000x1330 --json >$T/d.json
if python3 -m json.tool $T/d.json >/dev/null && same_numbers $T/d.txt $T/d.json distortion &&
   python3 - $T/d.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d['best_mapping'][0]['mapping'] == 'equisolid'
fe = [r for r in d['opencv'] if r['camera'] == 'fisheye'][0]
assert fe['rms_px'] < 0.01 and d['setup']['fnumber'] > 1.7
PY
then ok distort_json; else fail distort_json "$(head -3 $T/d.json)"; fi

# --fnumber: the stop scaled so that efl / entrance pupil = N; every traced ray's stop
# hit lies within the new stop radius, and the sampling reaches its rim
sd=$(awk '$3 == "stop" { print $4 }' $KT)
run $BIN/lens-trace $KT --fnumber 5.6 -n 4000 --stop-columns >$T/kt.txt 2>/dev/null
if grep -q '^# fnumber: 5.6 ' $T/kt.txt &&
   awk -v r="$(awk -v s=$sd 'BEGIN { printf "%.12g", s * 3.111667095 / 5.6 }')" '!/^#/ && $10 > 0 { h = sqrt($11 * $11 + $12 * $12); if (h > m) m = h }
        END { exit !(m <= r * (1 + 1e-6) && m > 0.97 * r) }' $T/kt.txt
then ok trace_fnumber; else fail trace_fnumber "sd=$sd $(head -5 $T/kt.txt)"; fi
expect_error spot_fnumber_not_faster "f/1.2 is faster than the lens' widest aperture f/1.75" \
  $BIN/lens-spot $FE --fnumber 1.2 --fields 0
if run $BIN/lens-spot $FE --fnumber 2.8 --fields 0 --wavelengths d --rays 60 | grep -q ': f/2.8, object at infinity'
then ok spot_fnumber_stated; else fail spot_fnumber_stated; fi
if run $BIN/lens-distort $FE --fnumber 2.8 --fields 0,30 --illum-rays 0 | grep -q ': f/2.8, object at infinity'
then ok distort_fnumber_stated; else fail distort_fnumber_stated; fi

# lens-eval --report: unique keys with units, named tables, the same numbers in JSON
run $BIN/lens-trace $DG -n 1500 --seed 1 >$T/train.txt 2>/dev/null
run $BIN/lens-fit -q --terms 15 -o $T/dg.poly $T/train.txt 2>/dev/null
run $BIN/lens-trace $DG -n 1500 --seed 2 --sampling full >$T/test.txt 2>/dev/null
run $BIN/lens-eval $T/dg.poly $T/test.txt --report >$T/r.txt 2>/dev/null
run $BIN/lens-eval $T/dg.poly $T/test.txt --report --json >$T/r.json 2>/dev/null
keys=$(awk '/^# columns: key rays/ { on = 1; next } on && /^$/ { exit } on { print $1 }' $T/r.txt)
if python3 -m json.tool $T/r.json >/dev/null && same_numbers $T/r.txt $T/r.json error &&
   [ "$(echo "$keys" | sort | uniq -d)" = "" ] && echo "$keys" | grep -qx out_u_arcmin && echo "$keys" | grep -qx out_x_mm &&
   grep -q '^# table: error_by_radius$' $T/r.txt && grep -q '^# table: passage$' $T/r.txt &&
   python3 - $T/r.txt $T/r.json <<'PY'
import json, sys
d = json.load(open(sys.argv[2]))
kv = dict(l.split()[:2] for l in open(sys.argv[1]) if l.split() and l.split()[0] in d['passage'])
assert kv and all(float(v) == d['passage'][k] for k, v in kv.items()), kv
assert len(d['error_by_radius']) == 8 * len(d['error'])
PY
then ok eval_report_json_keys; else fail eval_report_json_keys "$(head -12 $T/r.txt)"; fi
expect_error eval_json_needs_report "only the report" $BIN/lens-eval $T/dg.poly $T/test.txt --json
