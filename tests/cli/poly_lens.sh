#!/usr/bin/env bash
# A .poly remembers its lens: lens-trace writes "# lens:" and "# lens-path:" into its
# samples, lens-fit records them (through a pipe too, where there is no file name), and
# lens-spot SYSTEM.poly finds the lens without --lens, from any directory; when the file
# is gone the message names the lens and the path.
source "$(dirname "$0")/lib.sh"
L=lenses/dgauss.50mm.lens
abs=$(cd lenses && pwd)/dgauss.50mm.lens
run $BIN/lens-trace $L -n 3000 --seed 1 >$T/train.txt
if grep -qx '# lens: Double Gauss 50mm f/2 (Tronnier)' $T/train.txt && grep -qx "# lens-path: $L" $T/train.txt
then ok samples_name_their_lens; else fail samples_name_their_lens "$(head -3 $T/train.txt)"; fi

# through a pipe; -o in another directory: the path is made relative to the .poly (or
# absolute when the two share no directory but the root)
run $BIN/lens-fit -q --terms 15 <$T/train.txt >$T/d.poly
run $BIN/lens-fit -q --terms 15 -o $T/d2.poly $T/train.txt
mkdir -p tests/tmp-poly-lens.$$ && run $BIN/lens-fit -q --terms 15 -o tests/tmp-poly-lens.$$/d3.poly $T/train.txt
rel=$(grep '^lens-path' tests/tmp-poly-lens.$$/d3.poly); rm -rf tests/tmp-poly-lens.$$
# (d2.poly lies in $T: relative when $T and the checkout share a directory, /tmp say,
# absolute otherwise; either way it must lead to the lens from the .poly's directory)
p2=$(sed -n 's/^lens-path //p' $T/d2.poly)
case $p2 in /*) r2=$p2;; *) r2=$T/$p2;; esac
if grep -qx 'lens Double Gauss 50mm f/2 (Tronnier)' $T/d.poly && grep -qx "lens-path $L" $T/d.poly &&
   [ "$(realpath "$r2" 2>/dev/null)" = "$(realpath "$abs")" ] && [ "$rel" = "lens-path ../../lenses/dgauss.50mm.lens" ]
then ok poly_remembers_lens; else fail poly_remembers_lens "$(sed -n 3,4p $T/d.poly) / $(grep '^lens-path' $T/d2.poly) / $rel"; fi
cp $T/d2.poly $T/d.poly

# from another directory, without --lens: the same table as with --lens
TOPDIR=$PWD
(cd $T && run $TOPDIR/$BIN/lens-spot d.poly --fields 0,10 >spot_auto.txt 2>err.txt); rc=$?
run $BIN/lens-spot $T/d.poly --lens $L --fields 0,10 >$T/spot_given.txt
if [ $rc -eq 0 ] && [ -s $T/spot_auto.txt ] && cmp -s $T/spot_auto.txt $T/spot_given.txt
then ok spot_finds_lens_of_poly; else fail spot_finds_lens_of_poly "rc=$rc $(cat $T/err.txt)"; fi

# --lens FILE on lens-fit records that file and the lens's own name (as lens-trace
# writes it; it had recorded the file's base name); the path is gone: a message naming
# lens and path
grep -v '^# lens' $T/train.txt | run $BIN/lens-fit -q --terms 15 --lens $L >$T/given.poly
if grep -qx 'lens Double Gauss 50mm f/2 (Tronnier)' $T/given.poly && grep -qx "lens-path $L" $T/given.poly
then ok fit_lens_file_recorded; else fail fit_lens_file_recorded "$(sed -n 3,4p $T/given.poly)"; fi
sed "s#^lens-path .*#lens-path $T/gone/dgauss.lens#" $T/d.poly >$T/moved.poly
expect_error spot_names_missing_lens \
  "^lens-spot: .*moved.poly: the lens file the system was fitted to \(lens 'Double Gauss 50mm f/2 \(Tronnier\)', lens-path .*gone/dgauss.lens\) is not found; give it with --lens$" \
  $BIN/lens-spot $T/moved.poly --fields 0
# a relative lens-path is also found beside the .poly
mkdir -p $T/beside && cp $L $T/beside/my.lens
sed "s#^lens-path .*#lens-path my.lens#" $T/d.poly >$T/beside/rel.poly
if run $BIN/lens-distort $T/beside/rel.poly --fields 0,10 >/dev/null 2>$T/err.txt
then ok distort_finds_lens_beside_poly; else fail distort_finds_lens_beside_poly "$(cat $T/err.txt)"; fi
# a lens named by its short name (lens-trace dgauss.50mm) is recorded so, and found as the
# commands find a named lens (./, $SPARSELENS_LENS_PATH, the shipped lenses), from an
# empty directory without --lens: the same table as with the lens file given
mkdir -p $T/short
(cd $T/short && run $TOPDIR/$BIN/lens-trace dgauss.50mm -n 3000 --seed 1 -q |
  run $TOPDIR/$BIN/lens-fit -q --terms 15 -o s.poly)
(cd $T/short && env -u SPARSELENS_LENS_PATH $TOPDIR/$BIN/lens-spot s.poly --fields 0,10 >auto.txt 2>err.txt); rc=$?
run $BIN/lens-spot $T/short/s.poly --lens $L --fields 0,10 >$T/short/given.txt 2>/dev/null
if grep -qx 'lens-path dgauss.50mm' $T/short/s.poly && [ $rc -eq 0 ] && [ -s $T/short/auto.txt ] &&
   cmp -s $T/short/auto.txt $T/short/given.txt
then ok spot_finds_lens_by_short_name; else fail spot_finds_lens_by_short_name "rc=$rc $(cat $T/short/err.txt) $(grep '^lens-path' $T/short/s.poly)"; fi
