#ifndef SPARSELENS_OPTIONS_H
#define SPARSELENS_OPTIONS_H
/* Option tables. Each command lists its options once, in a table of opt_spec, and that
 * table is the only source of
 *   - the parsing of argv (opt_parse),
 *   - the --help text,
 *   - the SYNOPSIS and OPTIONS sections of the command's man page (`lens-x --help-man`
 *     prints them; `make man` splices them into man/lens-x.1, and
 *     tests/cli/man_options.sh fails when the page and the table differ).
 * Values go through offsets into the command's options struct, so a table is plain data:
 *
 *   static const opt_spec trace_table[] = {
 *       {'n', NULL, "N", OPT_INT, OPT_AT(trace_options, count), .lo = 1, .hi = 1e9,
 *        .help = "rays to write", .def = "10000"},
 *       {0, "all", NULL, OPT_FLAG, OPT_AT(trace_options, all), .help = "..."},
 *       {.type = OPT_GROUP, OPT_AT(trace_options, lens), .group = lens_cli_table},
 *       {0}
 *   };
 *
 * The options struct holds the defaults before parsing (the command's *_default()); .def
 * only shows them, and tests/unit/app/test_options.c checks that each .def parses to the
 * value the defaults hold.
 *
 * Spelling as people expect: -n5, -n 5, --seed=5, --seed 5, clustered short flags (-qa),
 * "--" ends the options, "-" alone is an operand (standard input). Every command also
 * answers -h/--help, --version and --help-man. A bad value prints
 * "lens-x: --seed: ..." (or "lens-x: -n: ...") on stderr and exits 1. */
#include <stddef.h>
#include <stdio.h>

typedef enum {
    OPT_END = 0, /* the {0} that ends a table */
    OPT_FLAG,    /* no value; sets an int to 1 */
    OPT_STRING,  /* const char *: the value as given */
    OPT_INT,     /* a whole number in [lo, hi] (1e4 notation accepted), stored in an
                    integer field of 4 or 8 bytes (int, long, unsigned long, size_t) */
    OPT_DOUBLE,  /* a finite number; in [lo, hi] when lo < hi */
    OPT_POSITIVE,/* a finite number > 0 */
    OPT_CHOICE,  /* one of the words of .choices: stores its value in an int field */
    OPT_CALL,    /* .set parses and stores the value (and exits on a bad one) */
    OPT_GROUP    /* the options of the table .group, for a struct at this offset */
} opt_type;

typedef struct {
    const char *name;
    int value;
} opt_choice;

typedef struct opt_spec opt_spec;

/* For OPT_CALL: parse value into field (the command's struct + offset); on a bad value
 * call opt_die(prog, spec, ...). */
typedef void (*opt_setter)(const char *prog, const opt_spec *spec, const char *value,
                           void *field);

struct opt_spec {
    char short_name;       /* 'n' for -n, or 0 */
    const char *long_name; /* "seed" for --seed, or NULL */
    const char *arg;       /* the value's name in help ("N", "WxH"); NULL: takes no value
                              (a flag), or for OPT_CHOICE: the words, "a|b|c" */
    opt_type type;
    size_t offset, size;   /* where the value goes: OPT_AT(struct, member) */
    double lo, hi;         /* OPT_INT, OPT_DOUBLE: the range */
    const opt_choice *choices; /* OPT_CHOICE: ends with {NULL, 0} */
    opt_setter set;        /* OPT_CALL */
    const opt_spec *group; /* OPT_GROUP */
    const char *help;      /* plain text, one paragraph (wrapped for --help) */
    const char *def;       /* the default as shown: "(default DEF)", or NULL */
    const char *man;       /* more for the man page, in roff, after help; or NULL */
};

#define OPT_AT(type, member) offsetof(type, member), sizeof(((type *)0)->member)

typedef struct {
    const char *name;     /* "lens-eval" */
    const char *synopsis; /* after the name: "SYSTEM.poly [FILE|-] [options]"; lines
                             separated by \n are alternative forms. In the man page's
                             SYNOPSIS, "[options]" becomes the table's options that the
                             form does not name itself. */
    const char *about;    /* for --help: what the command does (plain text, wrapped) */
    const opt_spec *table;
} opt_command;

/* Parses argv into opts by cmd->table. The operands (arguments that are not options,
 * "-" among them, and everything after "--") go to operands[], at most max of them
 * (one more is fatal: "unexpected argument"); returns how many. --help, --version and
 * --help-man print to stdout and exit 0; a bad option prints "prog: ..." and exits 1. */
int opt_parse(const opt_command *cmd, int argc, char **argv, void *opts,
              const char **operands, int max);

/* The --help text; the man page's SYNOPSIS and OPTIONS sections (roff, each from its .SH
 * line). */
void opt_print_help(FILE *f, const opt_command *cmd);
void opt_print_man(FILE *f, const opt_command *cmd);

/* The version of sparselens (the VERSION file, passed in by the Makefile). */
const char *opt_version(void);

/* The option's name as the user knows it: "--seed", or "-n" for a short-only one. */
const char *opt_name(const opt_spec *spec, char buf[static 64]);

/* "prog: --seed: MESSAGE" on stderr, exit 1: for setters. */
void opt_die(const char *prog, const opt_spec *spec, const char *fmt, ...)
    __attribute__((format(printf, 3, 4), noreturn));

/* Stores value (an OPT_INT / OPT_DOUBLE / OPT_CHOICE / OPT_STRING / OPT_FLAG spec's) into
 * the field at opts + spec->offset, with the checks the parser makes: for setters that
 * parse part of a value the same way, and for tests. */
void opt_store(const char *prog, const opt_spec *spec, const char *value, void *opts);

#endif
