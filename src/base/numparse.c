/* Strict number parsing (numparse.h). */
#include "sparselens/numparse.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

int parse_double(const char *s, double *out)
{
    if (!s || !*s)
        return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    /* strtod flags underflow with ERANGE too: a subnormal (or one that rounds to 0)
     * is a finite number, read as the nearest double; only overflow is refused. */
    if (*end != '\0' || end == s || !isfinite(v) || (errno == ERANGE && fabs(v) > 1))
        return -1;
    *out = v;
    return 0;
}

int parse_long(const char *s, long *out)
{
    double v;
    if (parse_double(s, &v) != 0 || v != floor(v) || fabs(v) > 9e15)
        return -1;
    *out = (long)v;
    return 0;
}
