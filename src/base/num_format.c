/* The sample files' number text (numtext_format, numtext.h): printf's %g layout laid
 * out from the library's digits. */
#include "base/numtext.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* printf's %.Pg of the digits d[0, n) (trailing zeros gone) with the decimal exponent
 * e (v = d.ddd x 10^e): fixed when -4 <= e < P, else d.ddde+XX (two digits at least). */
static size_t layout(char *b, const char *d, int n, int e, int neg, int prec)
{
    size_t k = 0;
    if (neg)
        b[k++] = '-';
    if (e < -4 || e >= prec) {
        b[k++] = d[0];
        if (n > 1) {
            b[k++] = '.';
            memcpy(b + k, d + 1, (size_t)n - 1);
            k += (size_t)n - 1;
        }
        b[k++] = 'e';
        b[k++] = e < 0 ? '-' : '+';
        int a = e < 0 ? -e : e;
        if (a >= 100)
            b[k++] = (char)('0' + a / 100);
        b[k++] = (char)('0' + a / 10 % 10);
        b[k++] = (char)('0' + a % 10);
    } else if (e < 0) {
        b[k++] = '0';
        b[k++] = '.';
        for (int i = 0; i < -e - 1; i++)
            b[k++] = '0';
        memcpy(b + k, d, (size_t)n);
        k += (size_t)n;
    } else if (n <= e + 1) {
        memcpy(b + k, d, (size_t)n);
        k += (size_t)n;
        for (int i = n; i <= e; i++)
            b[k++] = '0';
    } else {
        memcpy(b + k, d, (size_t)e + 1);
        k += (size_t)e + 1;
        b[k++] = '.';
        memcpy(b + k, d + e + 1, (size_t)(n - e - 1));
        k += (size_t)(n - e - 1);
    }
    return k;
}

/* Whether v's exact decimal expansion may end at its 18th significant digit (a tie at
 * 17 digits): v = M 2^-k with M odd ends k digits after the point, in a 5, and M 5^k
 * holds its significant digits, so only 10^17 <= M 5^k < 10^18 can be one. Exact, and
 * far cheaper than the 18-digit conversion that would tell (double-conversion has no
 * fast path past 17 digits). */
static int maybe_tie(double v)
{
    int e;
    double f = frexp(fabs(v), &e);
    unsigned long long m = (unsigned long long)ldexp(f, 53);
    int k = 53 - e;
    if (m == 0)
        return 0;
    while (!(m & 1)) /* M odd */
        m >>= 1, k--;
    if (k <= 0 || k > 26) /* an integer: M < 2^53 has 16 digits; 5^27 > 10^18 */
        return 0;
    unsigned __int128 x = m;
    for (int i = 0; i < k; i++)
        x *= 5;
    const unsigned __int128 e17 = (unsigned __int128)100000000000000000ULL;
    return x >= e17 && x < e17 * 10;
}

/* v's digits correctly rounded to 17, ties to even as printf (double-conversion rounds
 * a tie up). A tie is a value whose exact expansion ends at digit 18 with a 5. */
static int seventeen(double v, char *d, int *point, int *neg)
{
    char d18[24], exact[128];
    int p18, n = numtext_digits(v, 17, d, point, neg);
    if (!maybe_tie(v) || numtext_digits(v, 18, d18, &p18, neg) != 18 || d18[17] != '5')
        return n;
    int pw;
    if (numtext_digits(v, 120, exact, &pw, neg) != 18 || (d18[16] - '0') % 2 != 0)
        return n;
    memcpy(d, d18, 17); /* the tie, to the even digit below it */
    n = 17;
    while (n > 1 && d[n - 1] == '0')
        n--;
    d[n] = '\0';
    *point = p18;
    return n;
}

/* %.15g when it reads back, else %.17g, for a subnormal (the rule's own test: below
 * DBL_MIN several 15-digit decimals may read back to one double). */
static size_t subnormal(char *buf, double v)
{
    char d[24];
    int point, neg;
    int n = numtext_digits(v, 15, d, &point, &neg);
    size_t k = layout(buf, d, n, point - 1, neg, 15);
    double back;
    if (numtext_parse(buf, k, &back) == 0 && back == v)
        return k;
    n = seventeen(v, d, &point, &neg);
    return layout(buf, d, n, point - 1, neg, 17);
}

size_t numtext_format(double v, char *buf)
{
    if (isnan(v)) {
        memcpy(buf, "nan", 3);
        return 3;
    }
    if (isinf(v)) {
        memcpy(buf, v > 0 ? "inf" : "-inf", v > 0 ? 3 : 4);
        return v > 0 ? 3 : 4;
    }
    char d[24];
    int point, neg;
    int n = numtext_digits(v, 0, d, &point, &neg);
    /* At most one 15-digit decimal lies within half an ulp of a double (their spacing is
     * wider than the ulp), so when the shortest digits are 15 or fewer, %.15g gives them;
     * otherwise %.17g's, correctly rounded. */
    if (v != 0 && fabs(v) < DBL_MIN) /* a subnormal: few bits, so more decimals fit */
        return subnormal(buf, v);
    /* 17 shortest digits are the closest 17-digit decimal to v, which is %.17g's but
     * for a tie (printf's even digit against the closest's either) */
    if (n == 17 && !maybe_tie(v))
        return layout(buf, d, n, point - 1, neg, 17);
    if (n > 15)
        return layout(buf, d, seventeen(v, d, &point, &neg), point - 1, neg, 17);
    return layout(buf, d, n, v == 0 ? 0 : point - 1, neg, 15);
}
