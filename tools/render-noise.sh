#!/bin/bash
# Equal-time noise of the shipped scenes for reports/render.md: per scene, polynomial and
# exact, a render with seed 2, then three timed renders with seed 1 (one thread, best
# processor time of the render) and their noise figure against it
# (lens-render --noise-against).
# usage (repository root, after make): tools/render-noise.sh BINARY LABEL [lens-render options]
# prints per scene and path (poly, exact): best time, noise figure, their product
R=$1; L=$2; shift 2
for s in ${SCENES:-dgauss fisheye bokeh-fisheye}; do for mode in "" "--exact"; do
  $R scenes/$s.scene -o ${TMPDIR:-/tmp}/$L-$s$mode-2.exr --seed 2 --cache ${CACHE:-/tmp/render-noise-cache} --threads 1 $mode "$@" --quiet
  best=1e9
  for i in 1 2 3; do
    out=$(nice $R scenes/$s.scene -o ${TMPDIR:-/tmp}/$L-$s$mode-1.exr --seed 1 --cache ${CACHE:-/tmp/render-noise-cache} --threads 1 $mode "$@" --noise-against ${TMPDIR:-/tmp}/$L-$s$mode-2.exr 2>&1)
    # processor time where the binary prints it (a loaded machine stretches wall time)
    t=$(sed -n 's/^time [0-9.]* s (processor \([0-9.]*\) s).*/\1/p' <<<"$out")
    [ -n "$t" ] || t=$(sed -n 's/^time \([0-9.]*\) s.*/\1/p' <<<"$out"); v=$(sed -n 's/.*relative variance \([0-9.e-]*\) .*/\1/p' <<<"$out")
    best=$(awk -v a=$best -v b=$t 'BEGIN{print (b<a)?b:a}')
  done
  echo "$s $([ -n "$mode" ] && echo exact || echo poly) time $best noise $v product $(awk -v a=$best -v b=$v 'BEGIN{printf "%.4g", a*b}')"
done; done
