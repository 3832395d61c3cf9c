/* The lens-loading flags shared by every command (see lens_cli_options.h). */
#include "sparselens/lens_cli_options.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void lens_cli_options_init(lens_cli_options *o)
{
    memset(o, 0, sizeof *o);
}

void lens_cli_options_free(lens_cli_options *o)
{
    free(o->catalogs);
    memset(o, 0, sizeof *o);
}

static void set_catalog(const char *prog, const opt_spec *spec, const char *value, void *field)
{
    lens_cli_options *o = field;
    if (!*value)
        opt_die(prog, spec, "needs a catalog FILE (.agf or .catalog)");
    const char **c = realloc(o->catalogs, (o->ncatalogs + 2) * sizeof *c);
    if (!c)
        opt_die(prog, spec, "out of memory");
    c[o->ncatalogs++] = value;
    c[o->ncatalogs] = NULL;
    o->catalogs = c;
    o->opt.catalogs = c;
}

static void set_format(const char *prog, const opt_spec *spec, const char *value, void *field)
{
    if (!lens_format_known(value))
        opt_die(prog, spec, "expected one of %s, or auto, not '%s'", lens_formats, value);
    *(const char **)field = value;
}

static const opt_choice fallbacks[] = {{"ndvd", 1}, {"none", 0}, {NULL, 0}};

const opt_spec lens_cli_table[] = {
    {0, "glass-catalog", "FILE", OPT_CALL, 0, sizeof(lens_cli_options), .set = set_catalog,
     .help = "an extra glass catalog (.agf or .catalog), searched before the shipped one; "
             "repeatable",
     .man =
     "See\n"
     ".BR lens-import (5)\n"
     "for the catalog formats.\n"},
    {0, "glass-fallback", NULL, OPT_CHOICE, OPT_AT(lens_cli_options, opt.ndvd_fallback),
     .choices = fallbacks,
     .help = "ndvd: a glass missing from every catalog but given in the file with n_d and V_d "
             "uses the n_d/V_d model glass (with a warning)",
     .def = "none"},
    {0, "lens-format", "FMT", OPT_CALL, OPT_AT(lens_cli_options, opt.format), .set = set_format,
     .help = "read the lens as FMT: lens, fx, pbrt, zmx or seq, whatever its name",
     .def = "auto: by extension, else by content, as for standard input '-'",
     .man =
     "See\n"
     ".BR lens-import (5).\n"},
    {0}};

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
