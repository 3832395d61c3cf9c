#include "sparselens/diag.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

static const char *guarded_prog;
static int stdout_error_reported;

void diag_stdout_error_reported(void)
{
    stdout_error_reported = 1;
}

static void close_stdout(void)
{
    errno = 0;
    int bad = fflush(stdout) != 0 || ferror(stdout);
    int code = errno;
    /* A closed stdout nothing was written to is no error (lens-fit -o FILE >&-). */
    if (fclose(stdout) != 0 && !bad && errno != EBADF) {
        bad = 1;
        code = errno;
    }
    if (bad && stdout_error_reported)
        _exit(1);
    if (bad) {
        fprintf(stderr, "%s: write error: %s\n", guarded_prog,
                code ? strerror(code) : "output lost");
        _exit(1);
    }
}

void diag_guard_stdout(const char *prog)
{
    if (guarded_prog)
        return;
    guarded_prog = prog;
    atexit(close_stdout);
}
