/* The man page's sections from an option table (see options.h): SYNOPSIS and OPTIONS,
 * printed by `lens-x --help-man` and spliced into man/lens-x.1 by tools/man-options.sh. */
#include "sparselens/options.h"

#include <ctype.h>
#include <string.h>

#include "app/options_builtin.h"

/* Plain text as roff: backslashes escaped, every '-' of a word that starts with one (an
 * option name, which must copy and paste as ASCII) as \-, and a line that would start
 * with '.' or '\'' protected. */
static void roff_text(FILE *f, const char *s)
{
    if (*s == '.' || *s == '\'')
        fputs("\\&", f);
    int option_word = 0;
    for (const char *p = s; *p; p++) {
        if (p == s || strchr(" ('/", p[-1]))
            option_word = *p == '-';
        if (*p == '\\')
            fputs("\\e", f);
        else if (*p == '-' && option_word)
            fputs("\\-", f);
        else
            fputc(*p, f);
    }
}

/* ---- SYNOPSIS ------------------------------------------------------------------------ */

/* A word of a synopsis form or an option's value name, as roff in the fonts man pages use:
 * '[', ']' and '|' roman; an option ("-o", "--emit", and "-" for standard input) bold; a
 * name that stands for something (it has a capital: LENS, SYSTEM.poly, WxH) italic; any
 * other word, a value typed as it is ("c", "paraxial"), bold. */
static void synopsis_word(FILE *f, const char *w, size_t len)
{
    for (size_t i = 0; i < len;) {
        size_t n = strcspn(w + i, "[]|");
        if (n == 0) {
            fputc(w[i++], f);
            continue;
        }
        if (n > len - i)
            n = len - i;
        int italic = 0;
        for (size_t k = 0; k < n && w[i] != '-'; k++)
            italic |= isupper((unsigned char)w[i + k]) != 0;
        char piece[256];
        snprintf(piece, sizeof piece, "%.*s", (int)n, w + i);
        fputs(italic ? "\\fI" : "\\fB", f);
        roff_text(f, piece);
        fputs("\\fR", f);
        i += n;
    }
}

/* The option as the synopsis shows it: its short name if it has one (what people type),
 * then its value, "[-o\ FILE]", on one line that does not break inside the brackets. */
static void synopsis_option(FILE *f, const opt_spec *s)
{
    char name[64];
    if (s->short_name)
        snprintf(name, sizeof name, "-%c", s->short_name);
    else
        opt_name(s, name);
    fputs("[\\fB", f);
    roff_text(f, name);
    fputs("\\fR", f);
    if (s->arg) {
        fputs("\\ ", f);
        synopsis_word(f, s->arg, strlen(s->arg));
    } else if (s->type == OPT_CHOICE) {
        fputs("\\ ", f);
        for (const opt_choice *c = s->choices; c->name; c++)
            fprintf(f, "%s\\fB%s\\fR", c == s->choices ? "" : "|", c->name);
    }
    fputs("]\n", f);
}

/* Whether the form (len characters) names the option itself, as "-o" or "--emit", bare or
 * in brackets: then "[options]" leaves it out. */
static int named_in_form(const opt_spec *s, const char *form, size_t len)
{
    char short_name[3] = {'-', s->short_name, '\0'}, long_name[64];
    snprintf(long_name, sizeof long_name, "--%s", s->long_name ? s->long_name : "");
    for (size_t i = 0; i < len;) {
        size_t n = strcspn(form + i, " ");
        if (n > len - i)
            n = len - i;
        const char *w = form + i;
        size_t wl = n;
        if (wl && *w == '[')
            w++, wl--;
        if (wl && w[wl - 1] == ']')
            wl--;
        if ((s->short_name && wl == 2 && strncmp(w, short_name, 2) == 0) ||
            (s->long_name && wl == strlen(long_name) && strncmp(w, long_name, wl) == 0))
            return 1;
        i += n + 1;
    }
    return 0;
}

static void synopsis_table(FILE *f, const opt_spec *table, const char *form, size_t len)
{
    for (const opt_spec *s = table; s->type != OPT_END; s++) {
        if (s->type == OPT_GROUP)
            synopsis_table(f, s->group, form, len);
        else if (!named_in_form(s, form, len))
            synopsis_option(f, s);
    }
}

/* One form of the command: its words as written in cmd->synopsis, where "[options]"
 * stands for every option of the table the form does not name. */
static void synopsis_form(FILE *f, const opt_command *cmd, const char *form, size_t len)
{
    fprintf(f, ".SY %s\n", cmd->name);
    for (size_t i = 0; i < len;) {
        size_t n = strcspn(form + i, " ");
        if (n > len - i)
            n = len - i;
        if (n == 9 && strncmp(form + i, "[options]", 9) == 0) {
            synopsis_table(f, cmd->table, form, len);
        } else if (n > 0) {
            synopsis_word(f, form + i, n);
            fputc('\n', f);
        }
        i += n + 1;
    }
    fputs(".YS\n", f);
}

/* ---- OPTIONS ------------------------------------------------------------------------- */

static void man_entry(FILE *f, const opt_spec *s)
{
    fputs(".TP\n", f);
    if (s->short_name)
        fprintf(f, "\\fB\\-%c\\fR%s", s->short_name, s->long_name ? ", " : "");
    if (s->long_name) {
        char name[64];
        fputs("\\fB", f);
        roff_text(f, opt_name(s, name));
        fputs("\\fR", f);
    }
    if (s->arg) {
        fputs(" \\fI", f);
        roff_text(f, s->arg);
        fputs("\\fR", f);
    } else if (s->type == OPT_CHOICE) {
        fputc(' ', f);
        for (const opt_choice *c = s->choices; c->name; c++)
            fprintf(f, "%s\\fB%s\\fR", c == s->choices ? "" : "|", c->name);
    }
    fputc('\n', f);
    roff_text(f, s->help ? s->help : "");
    if (s->def) {
        fputs(" (default: ", f);
        roff_text(f, s->def);
        fputc(')', f);
    }
    fputs(".\n", f);
    if (s->man)
        fprintf(f, "%s%s", s->man, s->man[strlen(s->man) - 1] == '\n' ? "" : "\n");
}

static void man_table(FILE *f, const opt_spec *table)
{
    for (const opt_spec *s = table; s->type != OPT_END; s++) {
        if (s->type == OPT_GROUP)
            man_table(f, s->group);
        else
            man_entry(f, s);
    }
}

void opt_print_man(FILE *f, const opt_command *cmd)
{
    static const char generated[] =
        ".\\\" Generated from the option table of %s (src/app/): edit it there, then\n"
        ".\\\" run make man.\n";
    fprintf(f, ".SH SYNOPSIS\n");
    fprintf(f, generated, cmd->name);
    const char *p = cmd->synopsis;
    while (*p) {
        size_t len = strcspn(p, "\n");
        synopsis_form(f, cmd, p, len);
        p += len + (p[len] == '\n');
    }
    fprintf(f, ".SH OPTIONS\n");
    fprintf(f, generated, cmd->name);
    man_table(f, cmd->table);
    man_table(f, opt_builtin_table);
}
