#ifndef SPARSELENS_CLI_H
#define SPARSELENS_CLI_H
/* Small helpers that every command's argument parsing shares, so that the same flag
 * is spelled, checked and reported the same way everywhere. Fatal errors print
 * "prog: message" and exit 1. */
#include "sparselens/lens.h"

/* If argv[*i] is `name` ("--terms") or "name=VALUE", sets *value, advances *i past the
 * value, and returns 1; a missing value is fatal. Returns 0 otherwise. */
int cli_opt(const char *prog, int argc, char **argv, int *i, const char *name, const char **value);
double cli_double(const char *prog, const char *opt, const char *s);
double cli_positive(const char *prog, const char *opt, const char *s);
/* An integer count in [lo, hi] (accepts 1e4 notation). */
long cli_count(const char *prog, const char *opt, const char *s, long lo, long hi);
/* "AxB" or "A:B" (sep) into two numbers; fatal if malformed. */
void cli_pair(const char *prog, const char *opt, const char *s, char sep, double *a, double *b);
/* Loads a lens or exits with "prog: FILE:LINE: ..."; prints an importer's notes as
 * "prog: warning: FILE: ..." lines (lens_cli_options.h). */
void cli_load_lens(const char *prog, const char *path, const lens_load_options *opt, lens_t *lens);
/* Prints a usage text to stdout for --help and exits 0. */
void cli_help(const char *text) __attribute__((noreturn));
/* True when stderr is a terminal (progress lines are shown only then). */
int cli_progress_wanted(void);

#endif
