/* Emitted C: compiled with the system's C compiler at test time and run on the same
 * rays as poly_eval_batch; the two must agree to 1e-12 relative (they repeat the same
 * arithmetic, so in practice they agree exactly). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sparselens/poly.h"
#include "pass_edge_fixture.h"

/* Reads rays, prints NAME's result per ray, and exits 3 if NAME_batch on all the rays
 * at once differs from NAME anywhere (bit for bit, and in the pass flag). */
static const char *driver =
    "#include <stddef.h>\n#include <stdio.h>\n#include <stdlib.h>\n#include <string.h>\n"
    "int lens_poly_eval(const double in[5], double out[5]);\n"
    "void lens_poly_eval_batch(size_t n, const double *in, double *out, unsigned char *pass);\n"
    "int main(void) {\n"
    "    size_t n = 0, cap = 1024;\n"
    "    double *in = malloc(cap * 5 * sizeof(double)), out[5];\n"
    "    while (in && scanf(\"%lf %lf %lf %lf %lf\", &in[5 * n], &in[5 * n + 1], &in[5 * n + 2],\n"
    "                       &in[5 * n + 3], &in[5 * n + 4]) == 5) {\n"
    "        int p = lens_poly_eval(in + 5 * n, out);\n"
    "        printf(\"%d %a %a %a %a %a\\n\", p, out[0], out[1], out[2], out[3], out[4]);\n"
    "        if (++n == cap && !(in = realloc(in, (cap *= 2) * 5 * sizeof(double))))\n"
    "            return 2;\n"
    "    }\n"
    "    double *bo = malloc((n + 1) * 5 * sizeof(double));\n"
    "    unsigned char *bp = malloc(n + 1);\n"
    "    if (!in || !bo || !bp)\n"
    "        return 2;\n"
    "    lens_poly_eval_batch(n, in, bo, bp);\n"
    "    for (size_t r = 0; r < n; r++) {\n"
    "        int p = lens_poly_eval(in + 5 * r, out);\n"
    "        if (p != bp[r] || memcmp(out, bo + 5 * r, sizeof out) != 0)\n"
    "            return 3;\n"
    "    }\n"
    "    return 0;\n"
    "}\n";

/* flags: the compiler's optimisation flags (the batch loop vectorises differently at
 * each, and must keep the bits) */
static void check_emitted_on(poly_system *s, int nrays, unsigned long seed, const char *flags,
                             const double *given)
{
    const char *cc = getenv("CC");
    if (!cc || !*cc)
        cc = "cc";
    char dir[] = "/tmp/test_poly_emit_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char gen[256], drv[256], bin[256], rays[256], outp[256], cmd[1400];
    snprintf(gen, sizeof gen, "%s/gen.c", dir);
    snprintf(drv, sizeof drv, "%s/driver.c", dir);
    snprintf(bin, sizeof bin, "%s/prog", dir);
    snprintf(rays, sizeof rays, "%s/rays.txt", dir);
    snprintf(outp, sizeof outp, "%s/out.txt", dir);
    FILE *f = fopen(gen, "w");
    assert_int_equal(poly_emit_c(f, s, "lens_poly_eval"), 0);
    fclose(f);
    f = fopen(drv, "w");
    fputs(driver, f);
    fclose(f);
    /* -Werror: the emitted code must also compile cleanly */
    snprintf(cmd, sizeof cmd, "%s -std=c99 %s -Wall -Wextra -Werror %s %s -o %s -lm 2>&1", cc,
             flags, gen, drv, bin);
    if (system(cmd) != 0) {
        snprintf(cmd, sizeof cmd, "command -v %s >/dev/null", cc);
        if (system(cmd) != 0)
            skip(); /* no C compiler on this machine */
        fail_msg("emitted code does not compile (%s)", gen);
    }
    double *in = malloc((size_t)nrays * 5 * sizeof(double));
    fixture_rng g = {seed};
    f = fopen(rays, "w");
    for (int r = 0; r < nrays; r++) {
        fixture_ray(&g, in + 5 * r);
        if (given)
            memcpy(in + 5 * r, given + 5 * r, 5 * sizeof(double));
        else if (r % 7 == 0) /* some rays far outside the domain, and with the largest radius */
            in[5 * r] *= 3;
        if (r == 3) /* on the axis: the frame's angle is undefined there */
            in[5 * r] = in[5 * r + 1] = 0;
        if (r == 5) /* with 1/lambda^2: outputs not finite, in a whole block of 8 */
            in[5 * r + 4] = 0;
        for (int i = 0; i < 5; i++)
            fprintf(f, "%.17g%c", in[5 * r + i], i == 4 ? '\n' : ' ');
    }
    fclose(f);
    snprintf(cmd, sizeof cmd, "%s < %s > %s", bin, rays, outp);
    assert_int_equal(system(cmd), 0);
    f = fopen(outp, "r");
    int exact = 0;
    /* against the batch kernel: the emitted code repeats its plan, where poly_eval may
       run poly_fast's other roundings (test_poly checks those against the batch) */
    double *bo = malloc((size_t)nrays * 5 * sizeof(double));
    unsigned char *bp = malloc((size_t)nrays);
    poly_eval_batch(s, (size_t)nrays, in, bo, bp);
    for (int r = 0; r < nrays; r++) {
        double *want = bo + 5 * r, got[5];
        int pc, pw = bp[r];
        char tok[5][64];
        assert_int_equal(fscanf(f, "%d %63s %63s %63s %63s %63s", &pc, tok[0], tok[1], tok[2],
                                tok[3], tok[4]),
                         6);
        assert_int_equal(pc, pw);
        int same = 1;
        for (int o = 0; o < 5; o++) {
            got[o] = strtod(tok[o], NULL);
            double scale = fabs(want[o]) > 1e-300 ? fabs(want[o]) : 1;
            if (!(fabs(got[o] - want[o]) <= 1e-12 * scale) &&
                !(isnan(got[o]) && isnan(want[o])))
                fail_msg("ray %d output %d: emitted %.17g, poly_eval %.17g", r, o, got[o],
                         want[o]);
            same &= memcmp(&got[o], &want[o], sizeof got[o]) == 0;
        }
        exact += same;
    }
    fclose(f);
    print_message("emitted C: %d of %d rays bit-identical to poly_eval_batch\n", exact, nrays);
    free(in);
    free(bo);
    free(bp);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    assert_int_equal(system(cmd), 0);
}

static void check_emitted(poly_system *s, int nrays, unsigned long seed, const char *flags)
{
    check_emitted_on(s, nrays, seed, flags, NULL);
}

static void test_emit_one_part(void **st)
{
    (void)st;
    poly_system *s = fixture_system(40, 11, 1, 11);
    assert_int_equal(poly_add_pass_circle(s, 0, 1, 0.5), 0);
    check_emitted(s, 500, 1, "-O2");
    poly_free(s);
}

static void test_emit_parts(void **st)
{
    (void)st;
    poly_system *s = fixture_system(20, 8, 3, 12);
    check_emitted(s, 500, 2, "-O2");
    poly_free(s);
}

/* lens-fit's default layout: the meridional frame except out_u, out_v, 1/lambda^2 and a
 * pass circle; its batch function runs blocks of 8 rays with the frame inside the loop
 * (203 rays: a partial block at the end), at -O2 and with this machine's vectors. */
static void test_emit_frame(void **st)
{
    (void)st;
    poly_system *s = fixture_system(40, 11, 1, 14);
    assert_int_equal(poly_set_frame(s, POLY_FRAME_MERIDIONAL), 0);
    assert_int_equal(poly_set_output_plain(s, 2, 1), 0);
    assert_int_equal(poly_set_output_plain(s, 3, 1), 0);
    assert_int_equal(poly_set_transform(s, 4, POLY_XFORM_INVERSE_SQUARE), 0);
    poly_set_scaling(s, 4, 4.25, 2.0);
    assert_int_equal(poly_add_pass_circle(s, 0, 1, 50), 0);
    check_emitted(s, 203, 3, "-O2");
    check_emitted(s, 203, 4, "-O3 -march=native");
    poly_free(s);
}

/* The pass test on the frame's values, before the turn back, as liblens makes it: on
 * rays at a circle's edge that a test of the turned values would pass
 * (pass_edge_fixture.h; 101 rays: a partial block at the end). */
static void test_emit_pass_edge(void **st)
{
    (void)st;
    poly_system *s = edge_system(0);
    assert_non_null(s);
    double in[101 * 5];
    assert_int_equal(edge_rays(in, 101), 101);
    check_emitted_on(s, 101, 5, "-O2", in);
    check_emitted_on(s, 101, 6, "-O3 -march=native", in);
    poly_free(s);
}

/* The batch function's loop over a block's rays must stay one that compilers vectorise:
 * a test with && in it once made GCC 12 leave it scalar, 2.5 times the kernel's time
 * (bench_poly), with every value still right. With GCC, its report of vectorised loops
 * names the loop (at -O2, in each of the function's clones); other compilers: skipped. */
static void test_emit_batch_vectorised(void **st)
{
    (void)st;
    const char *cc = getenv("CC");
    if (!cc || !*cc)
        cc = "cc";
    char dir[] = "/tmp/test_poly_emit_XXXXXX", gen[256], cmd[1024], line[512];
    assert_non_null(mkdtemp(dir));
    snprintf(gen, sizeof gen, "%s/gen.c", dir);
    poly_system *s = edge_system(0);
    assert_non_null(s);
    FILE *f = fopen(gen, "w");
    assert_int_equal(poly_emit_c(f, s, "lens_poly_eval"), 0);
    fclose(f);
    poly_free(s);
    snprintf(cmd, sizeof cmd, "%s -std=c99 -O2 -fopt-info-vec-optimized -c %s -o %s/gen.o 2>&1",
             cc, gen, dir);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    int vectorised = 0, gcc = 0;
    while (fgets(line, sizeof line, p))
        vectorised += strstr(line, "loop vectorized") != NULL;
    const int rc = pclose(p);
    snprintf(cmd, sizeof cmd, "%s -dM -E - </dev/null 2>/dev/null | grep -q '__GNUC__' && "
             "! %s -dM -E - </dev/null 2>/dev/null | grep -q '__clang__'", cc, cc);
    gcc = system(cmd) == 0;
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    assert_int_equal(system(cmd), 0);
    if (rc != 0 || !gcc)
        skip(); /* not GCC, or no compiler */
    print_message("emitted C: %d loops vectorised at -O2\n", vectorised);
    assert_true(vectorised >= 1);
}

static void test_emit_bad_name(void **st)
{
    (void)st;
    poly_system *s = fixture_system(3, 2, 1, 13);
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    assert_int_equal(poly_emit_c(f, s, "2bad"), -1);
    assert_int_equal(poly_emit_c(f, s, "a-b"), -1);
    assert_int_equal(poly_emit_c(f, s, "int"), -1); /* a keyword: would not compile */
    assert_int_equal(poly_emit_c(f, s, "_Bool"), -1);
    assert_true(poly_c_name_ok("int_"));
    assert_true(poly_c_name_ok("lens2_"));
    assert_false(poly_c_name_ok("_lens2")); /* reserved at file scope (C11 7.1.3) */
    assert_false(poly_c_name_ok("sqrt"));   /* <math.h>, which the file includes */
    assert_false(poly_c_name_ok("NAN"));
    assert_false(poly_c_name_ok("class")); /* the file compiles as C++ too */
    fclose(f);
    assert_int_equal(len, 0); /* nothing written for any of them */
    free(buf);
    poly_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_emit_one_part),
        cmocka_unit_test(test_emit_parts), cmocka_unit_test(test_emit_frame),
        cmocka_unit_test(test_emit_pass_edge), cmocka_unit_test(test_emit_batch_vectorised),
        cmocka_unit_test(test_emit_bad_name),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
