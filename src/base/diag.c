#include "sparselens/diag.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

void lens_errf(lens_err *err, const char *file, long line, const char *fmt, ...)
{
    if (!err)
        return;
    int n = 0;
    if (file && line > 0)
        n = snprintf(err->msg, sizeof err->msg, "%s:%ld: ", file, line);
    else if (file)
        n = snprintf(err->msg, sizeof err->msg, "%s: ", file);
    if (n < 0 || (size_t)n >= sizeof err->msg)
        n = 0;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->msg + n, sizeof err->msg - (size_t)n, fmt, ap);
    va_end(ap);
}

void diag_print(const char *prog, const lens_err *err)
{
    fprintf(stderr, "%s: %s\n", prog, err->msg);
}

void diag_die(const char *prog, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "%s: ", prog);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(1);
}
