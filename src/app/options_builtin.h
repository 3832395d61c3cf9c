#ifndef SPARSELENS_APP_OPTIONS_BUILTIN_H
#define SPARSELENS_APP_OPTIONS_BUILTIN_H
/* The options every command has (-h/--help, --version), after the command's own in --help
 * and in the man page; options.c parses them, options_man.c documents them. */
#include "sparselens/options.h"

extern const opt_spec opt_builtin_table[];

#endif
