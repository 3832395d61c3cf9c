// The one file that includes fast_float and double-conversion: the extern "C"
// interface of numtext.h (the layout of the digits is num_format.c's).
#include <double-conversion/double-to-string.h>
#include <fast_float/fast_float.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "base/numtext.h"

extern "C" int numtext_parse(const char *s, size_t len, double *out)
{
    if (len == 0)
        return -1;
    double v;
    auto r = fast_float::from_chars(s, s + len, v);
    if (r.ec == std::errc() && r.ptr == s + len) {
        *out = v;
        return 0;
    }
    // What fast_float leaves (a leading '+', hex, "nan(...)", a number out of range):
    // strtod, on a copy that ends where the field does.
    char small[64];
    char *copy = len < sizeof small ? small : static_cast<char *>(std::malloc(len + 1));
    if (!copy)
        return -1;
    std::memcpy(copy, s, len);
    copy[len] = '\0';
    char *end;
    int saved = errno;
    v = std::strtod(copy, &end);
    errno = saved;
    const bool whole = end == copy + len;
    if (copy != small)
        std::free(copy);
    if (!whole)
        return -1;
    *out = v;
    return 0;
}

extern "C" int numtext_digits(double v, int ndigits, char *digits, int *point, int *neg)
{
    using double_conversion::DoubleToStringConverter;
    bool sign = false;
    int length = 0;
    DoubleToStringConverter::DoubleToAscii(
        v, ndigits ? DoubleToStringConverter::PRECISION : DoubleToStringConverter::SHORTEST,
        ndigits, digits, ndigits > 17 ? ndigits + 1 : 18, &sign, &length, point);
    while (length > 1 && digits[length - 1] == '0')
        length--;
    digits[length] = '\0';
    *neg = sign;
    return length;
}
