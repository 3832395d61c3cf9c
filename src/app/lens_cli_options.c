/* Parsing of the lens-loading flags shared by every command (see lens_cli_options.h). */
#include "sparselens/lens_cli_options.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

void lens_cli_options_init(lens_cli_options *o)
{
    memset(o, 0, sizeof *o);
}

void lens_cli_options_free(lens_cli_options *o)
{
    free(o->catalogs);
    memset(o, 0, sizeof *o);
}

/* "--name VALUE" or "--name=VALUE": returns the value, NULL if argv[*i] is not --name,
 * and sets *missing when it is but no value follows. */
static const char *flag_value(const char *name, int argc, char **argv, int *i, int *missing)
{
    size_t n = strlen(name);
    const char *a = argv[*i];
    *missing = 0;
    if (strncmp(a, name, n) != 0)
        return NULL;
    if (a[n] == '=')
        return a + n + 1;
    if (a[n] != '\0')
        return NULL;
    if (*i + 1 >= argc) {
        *missing = 1;
        return NULL;
    }
    return argv[++*i];
}

int lens_cli_options_parse(lens_cli_options *o, int argc, char **argv, int *i, lens_err *err)
{
    int missing;
    const char *v = flag_value("--glass-catalog", argc, argv, i, &missing);
    if (missing || (v && !*v)) {
        lens_errf(err, NULL, 0, "--glass-catalog needs a catalog FILE (.agf or .catalog)");
        return -1;
    }
    if (v) {
        const char **c = realloc(o->catalogs, (o->ncatalogs + 2) * sizeof *c);
        if (!c) {
            lens_errf(err, NULL, 0, "out of memory");
            return -1;
        }
        c[o->ncatalogs++] = v;
        c[o->ncatalogs] = NULL;
        o->catalogs = c;
        o->opt.catalogs = c;
        return 1;
    }
    v = flag_value("--glass-fallback", argc, argv, i, &missing);
    if (missing || (v && strcmp(v, "ndvd") != 0 && strcmp(v, "none") != 0)) {
        lens_errf(err, NULL, 0, "--glass-fallback takes 'ndvd' (or 'none'), not '%s'",
                  v ? v : "nothing");
        return -1;
    }
    if (v) {
        o->opt.ndvd_fallback = strcmp(v, "ndvd") == 0;
        return 1;
    }
    v = flag_value("--lens-format", argc, argv, i, &missing);
    if (missing || (v && !lens_format_known(v))) {
        lens_errf(err, NULL, 0, "--lens-format takes one of %s, or auto, not '%s'", lens_formats,
                  v ? v : "nothing");
        return -1;
    }
    if (v) {
        o->opt.format = v;
        return 1;
    }
    return 0;
}

int lens_cli_options_take(const char *prog, int argc, char **argv, int *i, lens_cli_options *o)
{
    lens_err err;
    int r = lens_cli_options_parse(o, argc, argv, i, &err);
    if (r < 0) {
        diag_print(prog, &err);
        exit(1);
    }
    return r;
}

int lens_cli_common_take(const char *prog, const char *usage, int argc, char **argv, int *i,
                         lens_cli_options *o)
{
    if (strcmp(argv[*i], "--help") == 0 || strcmp(argv[*i], "-h") == 0) {
        lens_cli_options_free(o);
        fputs(usage, stdout);
        exit(0);
    }
    return lens_cli_options_take(prog, argc, argv, i, o);
}

const lens_load_options *lens_cli_options_get(const lens_cli_options *o)
{
    return &o->opt;
}

void lens_cli_warn_notes(const char *prog, const lens_t *lens)
{
    if (!lens->notes[0])
        return;
    if (strcmp(lens->format, "lens") == 0)
        return; /* a converted lens (read in the native format, from a file or piped in)
                   carries its notes as header lines: said once, at conversion */
    const char *p = lens->notes;
    while (*p) {
        size_t len = strcspn(p, "\n");
        /* Fields and wavelengths read from a design file are information, not warnings. */
        int info = strncmp(p, "fields ", 7) == 0 || strncmp(p, "wavelengths ", 12) == 0;
        if (!info)
            fprintf(stderr, "%s: warning: %s: %.*s\n", prog, lens->path[0] ? lens->path : "lens",
                (int)len, p);
        p += len;
        if (*p == '\n')
            p++;
    }
}
