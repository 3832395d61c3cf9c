#ifndef SPARSELENS_BASE_LINE_READER_H
#define SPARSELENS_BASE_LINE_READER_H
/* Line-by-line reading with the limits every text reader states in its man page:
 * a line longer than max bytes is refused ("line longer than N bytes") without being
 * held, a NUL byte is named rather than taken for the end of the line, a read error is
 * an error and never the end of the file, and a UTF-8 byte-order mark before the first
 * line is dropped. Memory stays below max + 2 bytes whatever the input. */
#include <stddef.h>
#include <stdio.h>

#include "sparselens/diag.h"

/* The longest line the readers take unless their format says otherwise: far beyond any
 * prescription, sample row or .poly term, small enough that a line which never ends
 * is refused at once. */
#define LINE_MAX_BYTES 65536

typedef struct {
    FILE *f;
    const char *path; /* names the file in messages */
    size_t max;       /* longest line accepted, in bytes, line end excluded */
    char *buf;        /* the current line, NUL-terminated, line end ("\n", "\r\n") removed */
    size_t cap;
    size_t len;       /* bytes in buf */
    long line;        /* number of the current line (1 for the first) */
} line_reader;

enum {
    LINE_OK = 1,    /* buf holds the next line */
    LINE_END = 0,   /* no more lines */
    LINE_BAD = -1,  /* this line is refused (too long, a NUL byte): err says why; the
                     * rest of it is skipped, so a stream may go on with the next */
    LINE_FAIL = -2  /* read error or out of memory: err says which; stop */
};

void line_reader_init(line_reader *r, FILE *f, const char *path, size_t max);
int line_next(line_reader *r, lens_err *err);
void line_reader_free(line_reader *r);

/* The checks of line_next for a line already in memory (the importers read whole
 * files): LINE_OK, or LINE_BAD with err at path:line when it is longer than max or holds
 * a NUL byte (len: its length in bytes, NULs included). */
int line_check(const char *s, size_t len, size_t max, const char *path, long line,
               lens_err *err);

#endif
