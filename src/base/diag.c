#include "sparselens/diag.h"
#include "sparselens/escape.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void diag_sanitise(char *out, size_t cap, const char *text)
{
    static const char cut[] = "[...]";
    if (!cap)
        return;
    size_t o = 0;
    for (const unsigned char *p = (const unsigned char *)text; *p; p++) {
        char esc[4];
        int control = text_control_escape(*p, esc) != 0;
        size_t need = control ? 4 : 1;
        if (o + need + 1 > cap) {
            if (cap > sizeof cut) {
                o = o + sizeof cut > cap ? cap - sizeof cut : o;
                memcpy(out + o, cut, sizeof cut - 1);
                o += sizeof cut - 1;
            }
            break;
        }
        if (control) {
            memcpy(out + o, esc, 4);
            o += 4;
        } else {
            out[o++] = (char)*p;
        }
    }
    out[o] = '\0';
}

/* The message whole, on the heap (NULL when out of memory). */
static char *format_whole(const char *file, long line, const char *fmt, va_list ap)
{
    char head[64];
    if (line > 0)
        snprintf(head, sizeof head, ":%ld: ", line);
    else
        snprintf(head, sizeof head, ": ");
    size_t lf = file ? strlen(file) + strlen(head) : 0;
    va_list aq;
    va_copy(aq, ap);
    int nb = vsnprintf(NULL, 0, fmt, aq);
    va_end(aq);
    if (nb < 0)
        nb = 0;
    char *s = malloc(lf + (size_t)nb + 1);
    if (!s)
        return NULL;
    if (file)
        snprintf(s, lf + 1, "%s%s", file, head);
    vsnprintf(s + lf, (size_t)nb + 1, fmt, ap);
    return s;
}

void lens_errf(lens_err *err, const char *file, long line, const char *fmt, ...)
{
    if (!err)
        return;
    va_list ap;
    va_start(ap, fmt);
    char *whole = format_whole(file, line, fmt, ap);
    va_end(ap);
    /* the arguments may be err->msg itself (a message built on the one before) */
    diag_sanitise(err->msg, sizeof err->msg, whole ? whole : "out of memory");
    free(whole);
}

void diag_print(const char *prog, const lens_err *err)
{
    fprintf(stderr, "%s: %s\n", prog, err->msg);
}

void diag_die(const char *prog, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *whole = format_whole(NULL, 0, fmt, ap);
    va_end(ap);
    lens_err e;
    diag_sanitise(e.msg, sizeof e.msg, whole ? whole : "out of memory");
    free(whole);
    fprintf(stderr, "%s: %s\n", prog, e.msg);
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
