#ifndef SPARSELENS_OUTFILE_H
#define SPARSELENS_OUTFILE_H
/* Output files that are never left half-written: data goes to a temporary file beside
 * the target, which is renamed over it only when complete. An error, an abort, a
 * terminating signal (INT, TERM, HUP, PIPE, XCPU, ...) or an exit from elsewhere (a
 * thread library that cannot start its threads) removes the temporary file. A symlink
 * is followed (the file it names is replaced, the link stays); a FIFO or a device is
 * written in place, never replaced. "-" means stdout (written directly). Paths of any
 * length: one the system cannot hold is refused, never cut. */
#include <stdio.h>

#include "sparselens/diag.h"

typedef struct outfile outfile;

/* Opens path for writing; NULL with err set on failure. */
outfile *outfile_open(const char *path, lens_err *err);
/* Whether path can be written, tried before a long computation (a temporary file is
 * created and removed; a FIFO or device is checked, not opened). 0, or -1 with err. */
int outfile_check(const char *path, lens_err *err);
FILE *outfile_stream(outfile *of);
/* Flushes, closes and renames into place; 0 on success (write errors are reported here). */
int outfile_commit(outfile *of, lens_err *err);
/* Discards the output. */
void outfile_abort(outfile *of);
/* Discards the output after a write that failed with errno code (0: unknown), with err
 * "PATH: write error: why" (for stdout said once: not again at exit). */
void outfile_abort_write_error(outfile *of, int code, lens_err *err);
/* Temporary name for a file that another library writes (OpenCV, OpenEXR): the caller
 * writes tmp, then calls outfile_commit_path. Registered for signal cleanup. */
int outfile_tmp_path(const char *path, char *tmp, size_t tmplen);
int outfile_commit_path(const char *tmp, const char *path, lens_err *err);
void outfile_discard_path(const char *tmp);
/* Removes a file that this run wrote in full when a later output of the run failed, so
 * that a failed run leaves no output: a regular file only (the file a symlink names); a
 * FIFO, a device or "-" is left alone. */
void outfile_remove(const char *path);

#endif
