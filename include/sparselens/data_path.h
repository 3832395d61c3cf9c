#ifndef SPARSELENS_DATA_PATH_H
#define SPARSELENS_DATA_PATH_H
/* Where the commands find the files sparselens ships (lenses, the glass catalog, scenes),
 * so that `lens-info dgauss.50mm` works in the source tree, after `make install`, and
 * from any directory.
 *
 * The shipped directories of a KIND ("lenses", "scenes"), in this order:
 *   EXE/../KIND                      bin/ of the source tree
 *   EXE/../share/sparselens/KIND     an installed prefix (also under a DESTDIR)
 *   EXE/../../KIND                   build/tests/ of the source tree
 *   SPARSELENS_DATADIR/KIND          the compile-time default (make install sets it to
 *                                    PREFIX/share/sparselens)
 * where EXE is the running executable's directory (/proc/self/exe). */
#include <stddef.h>

/* The first shipped directory of kind holding file (a plain file name): its path in buf
 * (normalised, no "bin/../"). 0 if found, -1 if not. */
int data_shipped_file(const char *kind, const char *file, char *buf, size_t n);

/* Resolves a file a user named. A name that exists, or that starts with '/', "./" or
 * "../", is taken as it is (0, buf = name; a missing path then fails where it is opened).
 * Any other name (dgauss.50mm, reference/pbrt/wide.dat) is looked up, as it is and with
 * each extension of exts (NULL-terminated), in ./, in each directory of the
 * colon-separated environment variable env, then in the shipped directories of kind.
 * 0 with the path in buf, -1 if not found. */
int data_find(const char *kind, const char *env, const char *name, const char *const *exts,
              char *buf, size_t n);

#endif
