#ifndef SPARSELENS_LENS_CLI_OPTIONS_H
#define SPARSELENS_LENS_CLI_OPTIONS_H
/* The lens-loading flags every command accepts, parsed in one place:
 *   --glass-catalog FILE   an extra glass catalog (.agf or .catalog); repeatable;
 *                          searched, in order, before the shipped catalog
 *   --glass-fallback ndvd  a glass missing from every catalog but given in the file
 *                          with n_d and V_d uses the nd/Vd model glass (with a warning)
 *   --lens-format FMT      read the lens as FMT (lens, fx, pbrt, zmx, seq) whatever
 *                          its name; default auto: by extension, else by content (stdin)
 * Both also as --flag=VALUE. In a command:
 *
 *   lens_cli_options lo;
 *   lens_cli_options_init(&lo);
 *   for (int i = 1; i < argc; i++) {
 *       if (lens_cli_options_take(prog, argc, argv, &i, &lo))
 *           continue;                      // one of ours, consumed (i advanced)
 *       ... the command's own flags ...
 *   }
 *   cli_load_lens(prog, path, lens_cli_options_get(&lo), &lens); // prints the warnings
 *   ...
 *   lens_cli_options_free(&lo);
 *
 * Put LENS_CLI_OPTIONS_HELP in the command's --help text. */
#include "sparselens/diag.h"
#include "sparselens/lens.h"

typedef struct {
    const char **catalogs; /* NULL-terminated, as lens_load_options wants */
    size_t ncatalogs;
    lens_load_options opt;
} lens_cli_options;

/* One line per flag, for --help texts. */
#define LENS_CLI_OPTIONS_HELP                                                              \
    "  --glass-catalog FILE   extra glass catalog (.agf or .catalog), searched before the\n" \
    "                         shipped one; repeatable\n"                                      \
    "  --glass-fallback ndvd  a glass missing from the catalogs but given with n_d/V_d in\n" \
    "                         the file uses the n_d/V_d model (with a warning)\n"         \
    "  --lens-format FMT      read the lens as FMT: lens, fx, pbrt, zmx or seq (default\n" \
    "                         auto: by extension, else by content, as for stdin '-')\n"

void lens_cli_options_init(lens_cli_options *o);
void lens_cli_options_free(lens_cli_options *o);

/* Looks at argv[*i]. Returns 1 when it was one of the flags above (consumed, *i moved to
 * its last argument), 0 when it is not, -1 on a missing or bad value (err says which). */
int lens_cli_options_parse(lens_cli_options *o, int argc, char **argv, int *i, lens_err *err);

/* The same for thin commands: a bad value prints "prog: ..." and exits 1. */
int lens_cli_options_take(const char *prog, int argc, char **argv, int *i, lens_cli_options *o);

/* The start of every command's argument loop: the flags above (as _take), and --help or
 * -h, which prints usage and exits 0. Returns 1 when argv[*i] was one of them. */
int lens_cli_common_take(const char *prog, const char *usage, int argc, char **argv, int *i,
                         lens_cli_options *o);

/* The options to pass to lens_load() or cli_load_lens(). */
const lens_load_options *lens_cli_options_get(const lens_cli_options *o);

/* Prints "prog: warning: PATH: NOTE", one line per note, on stderr when an imported lens
 * (read in any format but the native one) carries notes of what was skipped or approximated.
 * Notes starting "fields " or "wavelengths " record what the file defines and are not
 * printed. */
void lens_cli_warn_notes(const char *prog, const lens_t *lens);

#endif
