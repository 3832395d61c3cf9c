#ifndef SPARSELENS_CLI_H
#define SPARSELENS_CLI_H
/* Helpers the commands share beyond their option tables (options.h): setters for values
 * of a common shape, lens loading with the importer's warnings, progress. Fatal errors
 * print "prog: message" and exit 1. */
#include "sparselens/lens.h"
#include "sparselens/options.h"

/* A width and a height. */
typedef struct {
    double w, h;
} cli_size;

/* Setter (OPT_CALL) of "WxH" into a cli_size, both positive. */
void cli_set_size(const char *prog, const opt_spec *spec, const char *value, void *field);

/* "AxB" or "A:B" (sep) into two numbers; fatal ("prog: --opt: ...") if malformed. */
void cli_pair(const char *prog, const opt_spec *spec, const char *s, char sep, double *a,
              double *b);

/* Loads a lens or exits with "prog: FILE:LINE: ..."; prints an importer's notes as
 * "prog: warning: FILE: ..." lines (lens_cli_options.h). */
void cli_load_lens(const char *prog, const char *path, const lens_load_options *opt, lens_t *lens);

/* Exits with "prog: PATH: cannot write: ..." unless path (an -o FILE; NULL or "-":
 * nothing to check) can be written: called before the work, so a long computation is
 * not lost to a typo in a directory name (outfile_check). */
void cli_check_output(const char *prog, const char *path);

/* Exits with "prog: <stdout>: cannot write: ..." when standard output is closed or
 * read-only: for commands that always write a table there, before their pictures. */
void cli_check_stdout(const char *prog);

/* Flushes standard output at the end of a command: 0, or after a write error says so
 * ("prog: <stdout>: write error: ...") and removes the n files the command wrote
 * (regular files only; NULL entries skipped), so that a failed run leaves no output,
 * and returns 1. */
int cli_end_stdout(const char *prog, const char *const *written, int n);

/* Exits with "prog: PATH: is also the input FILE: ..." when the output path (an -o FILE)
 * names the same file as the input (symlinks followed): the output replaces its file
 * only when complete, so the run would succeed and the input be lost. NULL or "-" on
 * either side: nothing to check. */
void cli_check_not_input(const char *prog, const char *path, const char *input);

/* True when stderr is a terminal (progress lines are shown only then). */
int cli_progress_wanted(void);

#endif
