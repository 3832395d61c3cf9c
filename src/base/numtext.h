#ifndef SPARSELENS_BASE_NUMTEXT_H
#define SPARSELENS_BASE_NUMTEXT_H
/* Numbers as text at the speed of the kernels: exact parsing (fast_float) and
 * shortest round-trip digits (double-conversion), behind an extern "C" shim
 * (numtext.cpp), and the text the sample files write (num_format.c). */
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The whole of s[0, len) as a double, correctly rounded, as strtod reads it (signs,
 * "nan", "inf", exponents, hex and the rest strtod takes): 0, or -1 when it is not one
 * number. Out of range: +-inf (as strtod's HUGE_VAL); below the subnormals: +-0. */
int numtext_parse(const char *s, size_t len, double *out);

/* The decimal digits of a finite v (sign apart): the shortest that read back to v when
 * ndigits is 0, else v correctly rounded to ndigits (1..120; a tie rounds away from
 * zero). digits gets them without trailing zeros, NUL-terminated (at least 18 bytes,
 * ndigits + 1 beyond 17); *point: the decimal exponent, v = 0.DIGITS x 10^point; *neg: the sign bit (-0 has it). Returns the number of digits. */
int numtext_digits(double v, int ndigits, char *digits, int *point, int *neg);

/* The text samples write for v: printf's "%.15g" when that reads back to v, else
 * "%.17g"; nan, inf, -inf for the others. Byte for byte what those formats give, at a
 * fraction of their cost. buf holds at least NUMTEXT_MAX bytes; returns the length
 * (no NUL is written). */
#define NUMTEXT_MAX 32
size_t numtext_format(double v, char *buf);

#ifdef __cplusplus
}
#endif
#endif
