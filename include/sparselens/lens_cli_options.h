#ifndef SPARSELENS_LENS_CLI_OPTIONS_H
#define SPARSELENS_LENS_CLI_OPTIONS_H
/* The lens-loading flags every command that reads a lens accepts, as one option table
 * (options.h) that each command's table includes as a group:
 *   --glass-catalog FILE   an extra glass catalog (.agf or .catalog); repeatable;
 *                          searched, in order, before the shipped catalog
 *   --glass-fallback ndvd  a glass missing from every catalog but given in the file
 *                          with n_d and V_d uses the nd/Vd model glass (with a warning)
 *   --lens-format FMT      read the lens as FMT (lens, fx, pbrt, zmx, seq) whatever
 *                          its name; default auto: by extension, else by content (stdin)
 * In a command's table: {.type = OPT_GROUP, OPT_AT(my_options, lens), .group =
 * lens_cli_table}; then cli_load_lens(prog, path, lens_cli_options_get(&o.lens), &lens)
 * and lens_cli_options_free(&o.lens). */
#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/options.h"

typedef struct {
    const char **catalogs; /* NULL-terminated, as lens_load_options wants */
    size_t ncatalogs;
    lens_load_options opt;
} lens_cli_options;

extern const opt_spec lens_cli_table[];

void lens_cli_options_init(lens_cli_options *o);
void lens_cli_options_free(lens_cli_options *o);

/* The options to pass to lens_load() or cli_load_lens(). */
const lens_load_options *lens_cli_options_get(const lens_cli_options *o);

/* Prints "prog: warning: PATH: NOTE", one line per note, on stderr when an imported lens
 * (read in any format but the native one) carries notes of what was skipped or approximated.
 * Notes starting "fields " or "wavelengths " record what the file defines and are not
 * printed. */
void lens_cli_warn_notes(const char *prog, const lens_t *lens);

#endif
