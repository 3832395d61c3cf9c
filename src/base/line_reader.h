#ifndef SPARSELENS_BASE_LINE_READER_H
#define SPARSELENS_BASE_LINE_READER_H
/* Line-by-line reading with the limits every text reader states in its man page:
 * a line longer than max bytes is refused ("line longer than N bytes") as soon as its
 * first max + 1 bytes are in, never held whole and never waited for (a stream whose line
 * never ends is refused at once, not read for ever in silence), a NUL byte is named
 * rather than taken for the end of the line, a read error is an error and never the end
 * of the file, and a UTF-8 byte-order mark before the first line is dropped.
 *
 * Input is taken in blocks: read(2) on a pipe, a terminal or a device (whatever has
 * arrived, so a stream is answered row by row), fread on a regular file or a memory
 * stream. The reader owns the stream from its first line on: nothing else reads f while
 * it is in use. Memory stays below max + LINE_BLOCK_BYTES + 8 bytes whatever the input. */
#include <stddef.h>
#include <stdio.h>

#include "sparselens/diag.h"

/* The longest line the readers take unless their format says otherwise: far beyond any
 * prescription, sample row or .poly term, small enough that a line which never ends
 * is refused at once. */
#define LINE_MAX_BYTES 65536
/* What one read asks for. */
#define LINE_BLOCK_BYTES 131072

typedef struct {
    FILE *f;
    const char *path; /* names the file in messages */
    size_t max;       /* longest line accepted, in bytes, line end excluded */
    char *buf;        /* the current line, NUL-terminated, line end ("\n", "\r\n") removed;
                       * it lies in the block and is valid until the next line_next */
    size_t len;       /* bytes in buf */
    long line;        /* number of the current line (1 for the first) */
    /* the block: bytes [pos, end) are read and not yet returned */
    char *blk;
    size_t cap, pos, end;
    int fd;           /* read(2) on this descriptor, or -1: fread on f */
    int eof, skip_rest;
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
