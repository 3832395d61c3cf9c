/* Option tables: parsing and --help from one table (see options.h; the man page's
 * sections: options_man.c). */
#include "sparselens/options.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "app/options_builtin.h"
#include "sparselens/diag.h"
#include "sparselens/numparse.h"

#ifndef SPARSELENS_VERSION
#define SPARSELENS_VERSION "unknown"
#endif

enum { HELP_COLUMN = 24, HELP_WIDTH = 79 };

/* The options every command has; handled before the command's table. */
enum { BUILTIN_HELP = 1, BUILTIN_VERSION, BUILTIN_MAN };
const opt_spec opt_builtin_table[] = {
    {'h', "help", NULL, OPT_FLAG, BUILTIN_HELP, 0, .help = "print this help and exit"},
    {0, "version", NULL, OPT_FLAG, BUILTIN_VERSION, 0,
     .help = "print the version of sparselens and exit"},
    {0}};

const char *opt_version(void)
{
    return SPARSELENS_VERSION;
}

const char *opt_name(const opt_spec *spec, char buf[static 64])
{
    if (spec->long_name)
        snprintf(buf, 64, "--%s", spec->long_name);
    else
        snprintf(buf, 64, "-%c", spec->short_name);
    return buf;
}

void opt_die(const char *prog, const opt_spec *spec, const char *fmt, ...)
{
    char name[64];
    va_list ap;
    fprintf(stderr, "%s: %s: ", prog, opt_name(spec, name));
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(1);
}

/* "a, b or c" from the choices, for messages. */
static void choice_list(const opt_choice *c, char *buf, size_t len)
{
    buf[0] = '\0';
    for (int k = 0; c[k].name; k++) {
        const char *sep = k == 0 ? "" : c[k + 1].name ? ", " : " or ";
        size_t used = strlen(buf);
        snprintf(buf + used, len - used, "%s%s", sep, c[k].name);
    }
}

static void store_int(const char *prog, const opt_spec *spec, const char *value, void *field)
{
    long v;
    if (parse_long(value, &v) != 0)
        opt_die(prog, spec, "'%s' is not a whole number", value);
    if (v < spec->lo || v > spec->hi)
        opt_die(prog, spec, "%s is out of range %.0f..%.0f", value, spec->lo, spec->hi);
    if (spec->size == sizeof(int32_t)) {
        int32_t w = (int32_t)v;
        memcpy(field, &w, sizeof w);
    } else {
        int64_t w = (int64_t)v;
        memcpy(field, &w, sizeof w);
    }
}

void opt_store(const char *prog, const opt_spec *spec, const char *value, void *opts)
{
    void *field = (char *)opts + spec->offset;
    double d;
    switch (spec->type) {
    case OPT_FLAG:
        *(int *)field = 1;
        break;
    case OPT_STRING:
        *(const char **)field = value;
        break;
    case OPT_INT:
        store_int(prog, spec, value, field);
        break;
    case OPT_DOUBLE:
    case OPT_POSITIVE:
        if (parse_double(value, &d) != 0)
            opt_die(prog, spec, "'%s' is not a finite number", value);
        if (spec->type == OPT_POSITIVE && !(d > 0))
            opt_die(prog, spec, "must be positive, not %s", value);
        if (spec->lo < spec->hi && !(d >= spec->lo && d <= spec->hi))
            opt_die(prog, spec, "must lie in [%g, %g], not %s", spec->lo, spec->hi, value);
        *(double *)field = d;
        break;
    case OPT_CHOICE:
        for (const opt_choice *c = spec->choices; c->name; c++)
            if (strcmp(c->name, value) == 0) {
                *(int *)field = c->value;
                return;
            }
        char words[256];
        choice_list(spec->choices, words, sizeof words);
        opt_die(prog, spec, "'%s' is not %s", value, words);
    case OPT_CALL:
        spec->set(prog, spec, value, field);
        break;
    case OPT_GROUP:
    case OPT_END:
        break;
    }
}

static int takes_value(const opt_spec *s)
{
    return s->type != OPT_FLAG;
}

/* The entry of table (or of a group in it) named by a long name of len characters or
 * by a short letter; *offset gets the groups' offsets added up. */
static const opt_spec *find(const opt_spec *table, const char *lname, size_t len, char sname,
                            size_t *offset)
{
    for (const opt_spec *s = table; s->type != OPT_END; s++) {
        if (s->type == OPT_GROUP) {
            size_t inner = 0;
            const opt_spec *hit = find(s->group, lname, len, sname, &inner);
            if (hit) {
                *offset += s->offset + inner;
                return hit;
            }
        } else if (lname ? s->long_name && strlen(s->long_name) == len &&
                               strncmp(s->long_name, lname, len) == 0
                         : s->short_name == sname) {
            return s;
        }
    }
    return NULL;
}

static void builtin(const opt_command *cmd, int which)
{
    if (which == BUILTIN_HELP)
        opt_print_help(stdout, cmd);
    else if (which == BUILTIN_VERSION)
        printf("%s (sparselens) %s\n", cmd->name, opt_version());
    else
        opt_print_man(stdout, cmd);
    exit(0); /* stdout is checked at exit (diag_guard_stdout) */
}

static void apply(const opt_command *cmd, const opt_spec *s, size_t offset, const char *value,
                  void *opts)
{
    size_t nbuiltin = sizeof opt_builtin_table / sizeof *opt_builtin_table;
    if (s >= opt_builtin_table && s < opt_builtin_table + nbuiltin)
        builtin(cmd, (int)s->offset);
    opt_spec at = *s;
    at.offset += offset;
    opt_store(cmd->name, &at, value, opts);
}

/* Edit distance (insertions, deletions, substitutions, adjacent swaps) between a and
 * the first len characters of b, capped: names are short, and only near misses matter. */
static size_t edit_distance(const char *a, const char *b, size_t len)
{
    enum { CAP = 64 };
    size_t la = strlen(a);
    if (la >= CAP || len >= CAP)
        return CAP;
    size_t d[CAP + 1][CAP + 1];
    for (size_t i = 0; i <= la; i++)
        d[i][0] = i;
    for (size_t j = 0; j <= len; j++)
        d[0][j] = j;
    for (size_t i = 1; i <= la; i++)
        for (size_t j = 1; j <= len; j++) {
            size_t best = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
            if (d[i - 1][j] + 1 < best)
                best = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < best)
                best = d[i][j - 1] + 1;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && d[i - 2][j - 2] + 1 < best)
                best = d[i - 2][j - 2] + 1;
            d[i][j] = best;
        }
    return d[la][len];
}

/* The long option of table (and its groups) nearest to name, or NULL when none is
 * within a third of the name's length (at least 1, at most 3 edits), or when the name
 * is a prefix of exactly one option (--field for --fields). */
static const opt_spec *nearest(const opt_spec *table, const char *name, size_t len, size_t *best)
{
    const opt_spec *hit = NULL;
    for (const opt_spec *s = table; s->type != OPT_END; s++) {
        const opt_spec *h = NULL;
        size_t d;
        if (s->type == OPT_GROUP) {
            d = *best;
            h = nearest(s->group, name, len, &d);
        } else if (s->long_name) {
            h = s;
            d = len >= 3 && strncmp(s->long_name, name, len) == 0 ? 1 : edit_distance(s->long_name, name, len);
        }
        if (h && d < *best)
            *best = d, hit = h;
    }
    return hit;
}

static void die_unknown_long(const opt_command *cmd, const char *name, size_t len, const char *arg)
{
    size_t limit = len / 3 < 1 ? 1 : len / 3 > 3 ? 3 : len / 3, best = limit + 1;
    const opt_spec *s = nearest(opt_builtin_table, name, len, &best);
    const opt_spec *t = nearest(cmd->table, name, len, &best);
    if (t)
        s = t;
    if (s)
        diag_die(cmd->name, "unknown option '%.*s': did you mean --%s? (see --help)", (int)(len + 2), arg,
                 s->long_name);
    diag_die(cmd->name, "unknown option '%.*s' (see --help)", (int)(len + 2), arg);
}

/* A long option, argv[*i] = "--name" or "--name=value". */
static void parse_long_option(const opt_command *cmd, int argc, char **argv, int *i, void *opts)
{
    const char *a = argv[*i] + 2, *eq = strchr(a, '=');
    size_t len = eq ? (size_t)(eq - a) : strlen(a), offset = 0;
    if (!eq && strcmp(a, "help-man") == 0)
        builtin(cmd, BUILTIN_MAN);
    const opt_spec *s = find(opt_builtin_table, a, len, 0, &offset);
    if (!s)
        s = find(cmd->table, a, len, 0, &offset);
    if (!s)
        die_unknown_long(cmd, a, len, argv[*i]);
    const char *value = NULL;
    if (!takes_value(s)) {
        if (eq)
            diag_die(cmd->name, "--%s takes no value (see --help)", s->long_name);
    } else if (eq) {
        value = eq + 1;
    } else if (*i + 1 < argc) {
        value = argv[++*i];
    } else {
        diag_die(cmd->name, "--%s needs a value (see --help)", s->long_name);
    }
    apply(cmd, s, offset, value, opts);
}

/* Short options, argv[*i] = "-n5", "-n" "5", or clustered flags "-qa". */
static void parse_short_options(const opt_command *cmd, int argc, char **argv, int *i, void *opts)
{
    for (const char *p = argv[*i] + 1; *p; p++) {
        size_t offset = 0;
        const opt_spec *s = find(opt_builtin_table, NULL, 0, *p, &offset);
        if (!s)
            s = find(cmd->table, NULL, 0, *p, &offset);
        if (!s) {
            if (p == argv[*i] + 1)
                diag_die(cmd->name, "unknown option '%s' (see --help)", argv[*i]);
            diag_die(cmd->name, "unknown option '-%c' in '%s' (see --help)", *p, argv[*i]);
        }
        if (!takes_value(s)) {
            apply(cmd, s, offset, NULL, opts);
            continue;
        }
        const char *value = p[1] ? p + 1 : *i + 1 < argc ? argv[++*i] : NULL;
        if (!value)
            diag_die(cmd->name, "-%c needs a value (see --help)", *p);
        apply(cmd, s, offset, value, opts);
        return;
    }
}

int opt_parse(const opt_command *cmd, int argc, char **argv, void *opts,
              const char **operands, int max)
{
    int n = 0, options_end = 0;
    diag_guard_stdout(cmd->name);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!options_end && strcmp(a, "--") == 0) {
            options_end = 1;
        } else if (!options_end && a[0] == '-' && a[1] == '-') {
            parse_long_option(cmd, argc, argv, &i, opts);
        } else if (!options_end && a[0] == '-' && a[1] != '\0') {
            parse_short_options(cmd, argc, argv, &i, opts);
        } else if (n < max) {
            operands[n++] = a;
        } else {
            diag_die(cmd->name, "unexpected argument '%s' (see --help)", a);
        }
    }
    return n;
}

/* ---- --help ------------------------------------------------------------------------ */

/* The value's name as shown: arg, or the choices as "a|b|c". */
static void arg_text(const opt_spec *s, char *buf, size_t len)
{
    buf[0] = '\0';
    if (s->arg) {
        snprintf(buf, len, "%s", s->arg);
    } else if (s->type == OPT_CHOICE) {
        for (const opt_choice *c = s->choices; c->name; c++) {
            size_t used = strlen(buf);
            snprintf(buf + used, len - used, "%s%s", c == s->choices ? "" : "|", c->name);
        }
    }
}

/* Writes text word-wrapped from column `col` (the cursor's) to HELP_WIDTH, continuation
 * lines indented to `indent`. */
static void wrap(FILE *f, const char *text, int col, int indent)
{
    const char *p = text;
    int first = 1;
    while (*p) {
        while (*p == ' ')
            p++;
        size_t w = strcspn(p, " ");
        if (w == 0)
            break;
        if (!first && col + 1 + (int)w > HELP_WIDTH) {
            fprintf(f, "\n%*s", indent, "");
            col = indent;
            first = 1;
        }
        if (!first) {
            fputc(' ', f);
            col++;
        }
        fprintf(f, "%.*s", (int)w, p);
        col += (int)w;
        p += w;
        first = 0;
    }
    fputc('\n', f);
}

static void help_entry(FILE *f, const opt_spec *s)
{
    char arg[256], head[320], text[2048];
    arg_text(s, arg, sizeof arg);
    if (s->short_name && s->long_name)
        snprintf(head, sizeof head, "  -%c, --%s%s%s", s->short_name, s->long_name,
                 *arg ? " " : "", arg);
    else if (s->short_name)
        snprintf(head, sizeof head, "  -%c%s%s", s->short_name, *arg ? " " : "", arg);
    else
        snprintf(head, sizeof head, "      --%s%s%s", s->long_name, *arg ? " " : "", arg);
    snprintf(text, sizeof text, "%s%s%s%s", s->help ? s->help : "", s->def ? " (default: " : "",
             s->def ? s->def : "", s->def ? ")" : "");
    int len = (int)strlen(head);
    if (len + 2 > HELP_COLUMN)
        fprintf(f, "%s\n%*s", head, HELP_COLUMN, "");
    else
        fprintf(f, "%s%*s", head, HELP_COLUMN - len, "");
    wrap(f, text, HELP_COLUMN, HELP_COLUMN);
}

static void help_table(FILE *f, const opt_spec *table)
{
    for (const opt_spec *s = table; s->type != OPT_END; s++) {
        if (s->type == OPT_GROUP)
            help_table(f, s->group);
        else
            help_entry(f, s);
    }
}

void opt_print_help(FILE *f, const opt_command *cmd)
{
    const char *p = cmd->synopsis;
    for (int first = 1; first || *p; first = 0) {
        size_t len = strcspn(p, "\n");
        fprintf(f, "%s %s %.*s\n", first ? "usage:" : "      ", cmd->name, (int)len, p);
        p += len;
        if (*p == '\n')
            p++;
    }
    if (cmd->about)
        wrap(f, cmd->about, 0, 0);
    fputs("Options:\n", f);
    help_table(f, cmd->table);
    help_table(f, opt_builtin_table);
    fprintf(f, "See %s(1).\n", cmd->name);
}
