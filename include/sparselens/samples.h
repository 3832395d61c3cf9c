#ifndef SPARSELENS_SAMPLES_H
#define SPARSELENS_SAMPLES_H
/* Sample files (man 5 lens-samples): whitespace-separated numbers, '#' comments, and one
 * header line "# columns: name name ..." naming the columns. Columns are found by
 * name, never by position. Streamed: rows are read one at a time, so files of any size
 * work in constant memory. */
#include <stdio.h>

#include "sparselens/diag.h"

typedef struct samples_reader samples_reader;

/* Opens path ("-" = stdin) and reads up to the header line. NULL on error (err set:
 * unreadable file, empty file, no "# columns:" line before the first data row). */
samples_reader *samples_open(const char *path, lens_err *err);
int samples_ncols(const samples_reader *r);
/* The value of a "# key: value" comment before the header ("# lens: NAME",
 * "# lens-path: PATH" from lens-trace), blanks trimmed; NULL when there is none. */
const char *samples_meta(const samples_reader *r, const char *key);
const char *samples_colname(const samples_reader *r, int i);
int samples_find(const samples_reader *r, const char *name); /* column index or -1 */
/* Fills map[i] with the column of names[i]; -1 with err set naming the first missing one. */
int samples_map(const samples_reader *r, const char *const *names, int n, int *map,
                lens_err *err);
/* Next data row into vals[ncols].
 * Returns 1 for a row, 0 at end of file, -1 for a malformed row (wrong number of
 * fields, a field that is not a number, a line longer than 64 KiB or holding a NUL
 * byte): err says FILE:LINE, vals are all nan, and the caller may go on reading; and
 * SAMPLES_FAIL when the stream cannot be read (a read error, out of memory): err says
 * so, and the rest of the stream is lost, so the caller stops with an error. "nan" and "inf" fields are numbers here; callers that
 * need finite inputs check them. */
#define SAMPLES_FAIL (-2)
int samples_next(samples_reader *r, double *vals, lens_err *err);
/* The most columns a sample file has (man 5 lens-samples), read or written. */
#define SAMPLES_MAX_COLS 64

/* Filters carry the columns they do not write through to their output, as GeodSolve and
 * cs2cs pass the rest of a line: the input columns whose names are not among the
 * `written` ones become pass-through columns, taken as text (any token, never parsed;
 * nan in vals) and returned in input order. Returns how many, or -1 with err when the
 * written and the passed-through columns together are more than SAMPLES_MAX_COLS (an
 * output no reader takes back). Call before the first row and before writing. */
int samples_passthrough(samples_reader *r, const char *const *written, int nwritten,
                        lens_err *err);
const char *samples_passthrough_name(const samples_reader *r, int k);
/* The last row's pass-through fields, each with a leading space ("nan" for a field a
 * short row lacks): written to f, or formatted into buf (snprintf-style: returns the
 * length it needs, writes at most cap bytes). */
void samples_write_passthrough(FILE *f, const samples_reader *r);
size_t samples_passthrough_text(const samples_reader *r, char *buf, size_t cap);
long samples_line(const samples_reader *r); /* line number of the last row read */
/* The last row's field in column col as a number (a pass-through column's too), NAN when
 * the row lacks it or it is not a number. */
double samples_field_number(const samples_reader *r, int col);
const char *samples_path(const samples_reader *r);
void samples_close(samples_reader *r);

/* Writes "# columns: a b c". */
void samples_write_header(FILE *f, const char *const *names, int n);
/* One row: each number the shortest of %.15g and %.17g that reads back to it (the same
 * bytes as printf's, from a library's digits), non-finite values as nan/inf. */
void samples_write_row(FILE *f, const double *vals, int n);
/* The same numbers, space-separated, into buf (room for n * SAMPLES_NUMBER_MAX bytes; no
 * newline, no NUL): the length. For writers that format blocks of rows at once. */
#define SAMPLES_NUMBER_MAX 33
size_t samples_format_values(char *buf, const double *vals, int n);
/* A filter's header and rows: its own columns, then the pass-through columns of its
 * input r (samples_passthrough). */
void samples_write_filter_header(FILE *f, const char *const *names, int n, const samples_reader *r);
void samples_write_filter_row(FILE *f, const double *vals, int n, const samples_reader *r);
/* The same with the pass-through fields kept earlier (samples_passthrough_text). */
void samples_write_filter_row_text(FILE *f, const double *vals, int n, const char *passthrough);

#endif
