#ifndef SPARSELENS_INPUT_FILE_H
#define SPARSELENS_INPUT_FILE_H
/* Opening an input file (a lens, a scene, a .poly, a texture, a glass catalog) so that
 * a name that is not a file fails at once with a message: a directory, a character or
 * block device (a link to /dev/zero reads forever) or a socket is refused. A FIFO or
 * pipe (`<(cat x.lens)`) is read, as stdin is. The open itself never blocks: a FIFO
 * without a writer is opened without waiting, then read in blocking mode. */
#include <stdio.h>

#include "sparselens/diag.h"

/* fopen(path, "r") for input files; NULL with err "PATH: why" on failure. */
FILE *input_open(const char *path, lens_err *err);

/* 1 if path is a regular file that can be read (what a lookup by name may take). */
int input_is_regular(const char *path);

#endif
