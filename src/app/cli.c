#include "sparselens/cli.h"
#include "sparselens/lens_cli_options.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int cli_opt(const char *prog, int argc, char **argv, int *i, const char *name, const char **value)
{
    const char *a = argv[*i];
    size_t n = strlen(name);
    if (strncmp(a, name, n) != 0)
        return 0;
    if (a[n] == '=') {
        *value = a + n + 1;
        return 1;
    }
    if (a[n] != '\0')
        return 0;
    if (*i + 1 >= argc)
        diag_die(prog, "%s needs a value (see --help)", name);
    *value = argv[++*i];
    return 1;
}

double cli_double(const char *prog, const char *opt, const char *s)
{
    double v;
    if (parse_double(s, &v) != 0)
        diag_die(prog, "%s: '%s' is not a finite number", opt, s);
    return v;
}

double cli_positive(const char *prog, const char *opt, const char *s)
{
    double v = cli_double(prog, opt, s);
    if (!(v > 0))
        diag_die(prog, "%s: must be positive, not %s", opt, s);
    return v;
}

long cli_count(const char *prog, const char *opt, const char *s, long lo, long hi)
{
    long v;
    if (parse_long(s, &v) != 0)
        diag_die(prog, "%s: '%s' is not a whole number", opt, s);
    if (v < lo || v > hi)
        diag_die(prog, "%s: %s is out of range %ld..%ld", opt, s, lo, hi);
    return v;
}

void cli_pair(const char *prog, const char *opt, const char *s, char sep, double *a, double *b)
{
    const char *p = strchr(s, sep);
    if (!p)
        diag_die(prog, "%s: expected A%cB, got '%s'", opt, sep, s);
    char first[64];
    size_t n = (size_t)(p - s);
    if (n >= sizeof first)
        diag_die(prog, "%s: '%s' is too long", opt, s);
    memcpy(first, s, n);
    first[n] = '\0';
    if (parse_double(first, a) != 0 || parse_double(p + 1, b) != 0)
        diag_die(prog, "%s: expected two numbers A%cB, got '%s'", opt, sep, s);
}

void cli_load_lens(const char *prog, const char *path, const lens_load_options *opt, lens_t *lens)
{
    lens_err err;
    if (lens_load(path, opt, lens, &err) != 0) {
        diag_print(prog, &err);
        exit(1);
    }
    lens_cli_warn_notes(prog, lens); /* what an importer skipped, one warning line each */
}

void cli_help(const char *text)
{
    fputs(text, stdout);
    exit(0);
}

int cli_progress_wanted(void)
{
    return isatty(STDERR_FILENO);
}
