#ifndef SPARSELENS_OUTFILE_H
#define SPARSELENS_OUTFILE_H
/* Output files that are never left half-written: data goes to a temporary file beside
 * the target, which is renamed over it only when complete. An error, an abort, or
 * SIGINT/SIGTERM removes the temporary file. "-" means stdout (written directly). */
#include <stdio.h>

#include "sparselens/diag.h"

typedef struct outfile outfile;

/* Opens path for writing; NULL with err set on failure. */
outfile *outfile_open(const char *path, lens_err *err);
FILE *outfile_stream(outfile *of);
/* Flushes, closes and renames into place; 0 on success (write errors are reported here). */
int outfile_commit(outfile *of, lens_err *err);
/* Discards the output. */
void outfile_abort(outfile *of);
/* Temporary name for a file that another library writes (OpenCV, OpenEXR): the caller
 * writes tmp, then calls outfile_commit_path. Registered for signal cleanup. */
int outfile_tmp_path(const char *path, char *tmp, size_t tmplen);
int outfile_commit_path(const char *tmp, const char *path, lens_err *err);
void outfile_discard_path(const char *tmp);

#endif
