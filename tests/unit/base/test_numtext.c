/* Number text (base/numtext.h): the writer gives printf's bytes for the rule samples
 * have always used (%.15g when it reads back, else %.17g), and the parser strtod's
 * double, on millions of doubles of every kind. printf and strtod are the reference. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/numtext.h"

static void printf_text(double v, char *buf)
{
    if (isnan(v))
        strcpy(buf, "nan");
    else if (isinf(v))
        strcpy(buf, v > 0 ? "inf" : "-inf");
    else {
        snprintf(buf, 40, "%.15g", v);
        if (strtod(buf, NULL) != v)
            snprintf(buf, 40, "%.17g", v);
    }
}

static long mismatches(double v)
{
    char want[40], got[NUMTEXT_MAX + 1];
    printf_text(v, want);
    size_t n = numtext_format(v, got);
    got[n] = '\0';
    double back;
    const int same = strcmp(want, got) == 0;
    const int reads = numtext_parse(got, n, &back) == 0 &&
                      (isnan(v) ? isnan(back) : memcmp(&back, &v, sizeof v) == 0);
    if (!same || !reads)
        print_error("%a: printf '%s', numtext '%s'%s\n", v, want, got, reads ? "" : " (reads back wrong)");
    return !same + !reads;
}

static uint64_t next(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

static void writer_is_printf_on_edges(void **state)
{
    (void)state;
    const double edges[] = {0.0, -0.0, 1, -1, 0.5, 100, 1e15, 1e16, 1e17, 1e21, 123456.0,
                            123456789012345678.0, 9007199254740993.0, 1e-5, 1e-4, 0.0001234,
                            5e-324, -5e-324, 4.9406564584124654e-320, DBL_MIN, DBL_MAX,
                            0.1, 0.3, 1e100, 1e-100, 1e-300, NAN, -NAN, INFINITY, -INFINITY,
                            /* ties at the 17th digit: printf rounds them to even */
                            -306855609443175.625, 134684932502532.125, 76357928231401.3125};
    long bad = 0;
    for (size_t i = 0; i < sizeof edges / sizeof *edges; i++)
        bad += mismatches(edges[i]);
    /* every kind of 17-digit tie: M 2^-k (M odd) whose exact expansion M 5^k has 18
     * digits, the smallest, middle and largest M of each k below 2^53 */
    for (int k = 1; k <= 26; k++) {
        double p5 = pow(5, k), lo = ceil(1e17 / p5), hi = floor((1e18 - 1) / p5);
        double ms[3] = {lo, floor((lo + hi) / 2), hi};
        for (int j = 0; j < 3; j++) {
            double m = ms[j];
            if (fmod(m, 2) == 0)
                m += 1;
            if (m >= 9007199254740992.0 || m > hi)
                continue;
            bad += mismatches(ldexp(m, -k)) + mismatches(-ldexp(m, -k));
        }
    }
    for (int e = -330; e <= 310; e++) /* every power of ten, and its neighbours */
        for (int k = -2; k <= 2; k++) {
            double p = pow(10, e);
            for (int j = 0; j < abs(k); j++)
                p = nextafter(p, k < 0 ? 0 : INFINITY);
            bad += mismatches(p) + mismatches(-p);
        }
    assert_int_equal(bad, 0);
}

static void writer_is_printf_on_random_doubles(void **state)
{
    (void)state;
    uint64_t s = 88172645463325252ull;
    long bad = 0;
    for (long i = 0; i < 600000 && bad < 20; i++) {
        uint64_t b = next(&s);
        double v;
        switch (i % 5) {
        case 0: memcpy(&v, &b, sizeof v); break;                  /* any bit pattern */
        case 1: v = (double)(b % 2000001) / 1000.0 - 1000; break; /* short decimals */
        case 2: v = ldexp((double)(b >> 11), (int)(b % 200) - 150 - 53); break;
        case 3: v = (double)(int64_t)b / 1e3; break;              /* 16 to 19 digits */
        default: v = (double)(int64_t)(b % 100000000) * 0.5; break; /* integers, halves */
        }
        bad += mismatches(v);
    }
    assert_int_equal(bad, 0);
}

static void parser_is_strtod(void **state)
{
    (void)state;
    const char *tokens[] = {"+1", "-2.5", "0x10", "0x1.8p3", "1e400", "-1e400", "1e-400",
                            "nan", "-nan", "NaN", "inf", "-Infinity", ".5", "5.", "1E5",
                            "2.2250738585072011e-308", "4.9e-324", "0.1000000000000000055511151231257827",
                            "9007199254740993", "1e", "", "1,5", "--1", "1e+", "abc", "0x"};
    for (size_t i = 0; i < sizeof tokens / sizeof *tokens; i++) {
        char *end;
        const double want = strtod(tokens[i], &end);
        const int whole = end != tokens[i] && *end == '\0';
        double got = -7;
        const int rc = numtext_parse(tokens[i], strlen(tokens[i]), &got);
        if (rc != (whole ? 0 : -1) || (whole && !(memcmp(&got, &want, sizeof got) == 0 ||
                                                  (isnan(got) && isnan(want)))))
            fail_msg("'%s': numtext %d %a, strtod %d %a", tokens[i], rc, got, whole, want);
    }
    /* a field is the bytes given, not up to a NUL: "12" of "123" */
    double v;
    assert_int_equal(numtext_parse("123", 2, &v), 0);
    assert_true(v == 12);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(writer_is_printf_on_edges),
        cmocka_unit_test(writer_is_printf_on_random_doubles),
        cmocka_unit_test(parser_is_strtod),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
