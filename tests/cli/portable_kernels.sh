#!/usr/bin/env bash
# The portable path of the SIMD kernels (what arm64 and every non-x86 machine builds:
# the 2-lane packet tracer and batch evaluator, square roots without x86 intrinsics),
# checked here on x86 by building trace_packet.c, poly_eval.c and poly_fast.c (which
# then declines: the plan's interpreter runs one ray) with
# SPARSELENS_PORTABLE_KERNELS and no -march, and linking the unit tests that compare
# packets and batches against the scalar paths bit for bit (test_trace, test_poly); the
# renderer's block functions likewise (test_render_light, test_render_batch).
# The objects come before liblens.a on the link line, so they replace its members.
. "$(dirname "$0")/lib.sh"
lib=$BUILD/liblens.a
[ -f "$lib" ] || { ok "portable kernels (skipped: $lib not built)"; exit 0; }
cppflags=$(makevar CPPFLAGS) ldlibs=$(makevar LDLIBS)
cflags="-std=c11 -O2 -fopenmp -DSPARSELENS_PORTABLE_KERNELS"
[ -n "$SANITIZE" ] && cflags="$cflags -O1 -fsanitize=address,undefined -fno-sanitize-recover=undefined"
objs=""
# the renderer's: the block functions' point-by-point path (scene_light.c, scene_cull.c,
# render_samples.c and render_lens.c without their AVX-512 lanes)
for f in src/trace/trace_packet.c src/poly/poly_eval.c src/poly/poly_fast.c \
         src/render/scene_light.c src/render/scene_light_simd.c src/render/scene_geometry.c \
         src/render/scene_cull.c src/render/render_samples.c src/render/render_lens.c \
         src/render/render_lens_simd.c; do
  o=$T/$(basename "$f" .c).o
  # shellcheck disable=SC2086
  ${CC:-cc} $cppflags $cflags -Wall -Wextra -Werror -c "$f" -o "$o" 2>"$T/cc.log" ||
    { fail "portable kernels build $f" "$(head -3 "$T/cc.log" | tr '\n' ' ')"; exit 0; }
  objs="$objs $o"
done
if nm $objs | grep -qE 'avx|trace_w4|trace_w8'; then fail "portable kernels" "an x86 kernel is still built"; exit 0; fi
for t in trace/test_trace poly/test_poly render/test_render_light render/test_render_batch; do
  n=$(basename "$t")
  # shellcheck disable=SC2086
  ${CC:-cc} $cppflags $(makevar CMOCKA_CFLAGS) -Itests/unit $cflags "tests/unit/$t.c" $objs "$lib" \
    -fopenmp $(makevar CMOCKA_LIBS) $ldlibs -o "$T/$n" 2>"$T/cc.log" ||
    { fail "portable kernels link $n" "$(head -3 "$T/cc.log" | tr '\n' ' ')"; continue; }
  if CMOCKA_MESSAGE_OUTPUT=stdout "$T/$n" >"$T/$n.out" 2>&1; then ok "portable kernels: $n ($(grep -c '^\[       OK' "$T/$n.out") cases)"
  else fail "portable kernels: $n" "$(grep -m3 -E 'FAILED|ERROR|error' "$T/$n.out" | tr '\n' ' ')"; fi
done

# Every file that reaches for an instruction set must still compile for arm64: a
# syntax check with clang's aarch64 target (this machine's C library headers stand in
# for arm64's; the x86 intrinsics headers refuse any other target, so an unguarded
# <immintrin.h> or _mm_* shows here).
if command -v clang >/dev/null; then
  mkdir -p "$T/a64/gnu" && : > "$T/a64/gnu/stubs-32.h"
  libc_arch=$(${CC:-cc} -print-multiarch 2>/dev/null)
  files=$(git -C "$TOP" grep -lE 'immintrin|_mm[0-9]*_|__builtin_cpu|target\("|arm_neon' -- 'src/*.c' 2>/dev/null)
  bad=""
  for f in $files; do
    # shellcheck disable=SC2086
    clang --target=aarch64-linux-gnu -std=c11 -fsyntax-only -fopenmp -Wall -Wextra -Wno-unknown-attributes \
      $cppflags ${libc_arch:+-idirafter /usr/include/$libc_arch} -idirafter "$T/a64" "$f" 2>"$T/a64.log" ||
      bad="$bad $f: $(grep -m1 error "$T/a64.log")"
  done
  if [ -z "$bad" ]; then ok "arm64 syntax check ($(echo $files | wc -w) files with SIMD code)"
  else fail "arm64 syntax check" "$bad"; fi
else
  ok "arm64 syntax check (skipped: no clang)"
fi

# The whole library must also compile with clang for this machine, not only the fuzz
# build's subset under SANITIZE=1: a GCC-only builtin (__builtin_shuffle once broke the
# sanitizer suite's fuzz build) shows here in every run.
if command -v clang >/dev/null; then
  cairo=$(makevar CAIRO_CFLAGS) bad="" n=0
  for f in $(git -C "$TOP" ls-files 'src/*.c'); do
    n=$((n + 1))
    # shellcheck disable=SC2086
    clang -std=c11 -fsyntax-only -fopenmp -Wall -Wextra -Werror -Wno-unknown-attributes \
      $cppflags $cairo "$TOP/$f" 2>"$T/clang.log" || bad="$bad $f: $(grep -m1 error "$T/clang.log")"
  done
  if [ -z "$bad" ]; then ok "clang builds the library ($n files, -Wall -Wextra -Werror)"
  else fail "clang builds the library" "$bad"; fi
else
  ok "clang build check (skipped: no clang)"
fi
exit 0
