#ifndef SPARSELENS_DIAG_H
#define SPARSELENS_DIAG_H
/* Error reporting shared by the library and the commands.
 * Library functions never print: they fill a lens_err with one line of the form
 * "FILE:LINE: what is wrong" (or "FILE: what is wrong" when no line applies) and
 * return non-zero. Commands print it as "lens-x: <msg>" and exit non-zero. */
#include <stddef.h>

/* Room for two paths of PATH_MAX and the words around them: a message is never cut
 * (one longer still, from a pathological input, ends in "[...]"). */
#define LENS_ERR_MAX 12288

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    char msg[LENS_ERR_MAX];
} lens_err;

/* Formats "file:line: ..." into err (line <= 0 omits the line; file NULL omits both).
 * Control bytes (an escape sequence in a field of a file, a tab, a CR) are written as
 * \xNN, so that text from a file cannot drive the terminal the message reaches. */
void lens_errf(lens_err *err, const char *file, long line, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* Copies text into out (cap bytes) with control bytes as \xNN (what lens_errf does);
 * the result is cut, with "[...]", only when cap cannot hold it. */
void diag_sanitise(char *out, size_t cap, const char *text);

/* Prints "prog: msg" to stderr. */
void diag_print(const char *prog, const lens_err *err);

/* Prints "prog: ..." to stderr and exits with status 1 (usage and fatal errors in commands). */
void diag_die(const char *prog, const char *fmt, ...)
    __attribute__((format(printf, 2, 3), noreturn));

/* Makes the exit of a command check its standard output: at exit, stdout is flushed
 * and closed, and a failure (a full disk, /dev/full, a closed descriptor written to)
 * prints "prog: write error: ..." and makes the exit status 1. Called once, early
 * (opt_parse does it for every command). */
void diag_guard_stdout(const char *prog);
/* Tells the guard that a write error on stdout was already reported (outfile_commit),
 * so that the exit prints no second line. */
void diag_stdout_error_reported(void);

#ifdef __cplusplus
}
#endif

#endif
