#ifndef SPARSELENS_TABLE_OUT_H
#define SPARSELENS_TABLE_OUT_H
/* Results for people and for scripts from one description: named tables of named columns,
 * written either as text (lens-samples style: "# columns: a b c", one row a line; each
 * table after the first set apart by a blank line and named by "# table: NAME" before its
 * columns line) or as one JSON object (--json, as gdalinfo -json):
 *
 *   {"table_name": [{"a": 1, "b": "x"}, ...], "key_values": {"k": 1}, "warnings": [...]}
 *
 * Numbers are written to `precision` significant digits (--precision; 0: the command's
 * default), non-finite ones as nan / inf in text and null in JSON, and a number that is
 * round-off about zero (|v| <= 1e-12 x the scale the caller gives, e.g. the image
 * height for a centroid) as 0, never as -5.58e-15. */
#include <stdio.h>

typedef struct {
    FILE *f;
    int json;
    int precision;     /* significant digits */
    int user_precision; /* given by the user: table_out_fmt's formats give way to it */
    /* where the writer is: */
    int ntables, nrows, ncells, in_table, as_object, flat;
    const char *const *columns;
    int ncolumns;
} table_out;

/* Starts the output ("{" in JSON). default_precision: the command's digits when
 * precision is 0. */
void table_out_begin(table_out *t, FILE *f, int json, int precision, int default_precision);
/* A table of rows: text "# NOTE" lines (note may be NULL or hold several lines), then
 * "# table: NAME" and "# columns: ..."; JSON "NAME": [ ... ]. */
void table_out_table(table_out *t, const char *name, const char *note, const char *const *columns,
                     int ncolumns);
/* A table of key-value pairs: text "# columns: key value" rows; JSON "NAME": {...}. Cells
 * come in pairs: a string key, then its value. NAME NULL: in text no header lines, in
 * JSON the pairs go into the top object. */
void table_out_keys(table_out *t, const char *name, const char *note);
/* The cells of a row, left to right; a row ends with table_out_row_end. */
void table_out_str(table_out *t, const char *s);
void table_out_num(table_out *t, double v, double scale);
/* A number in the command's own printf format (one double conversion, e.g. "%.6f"),
 * or to the user's --precision when given; nan, inf and round-off as table_out_num. */
void table_out_fmt(table_out *t, double v, double scale, const char *fmt);
void table_out_int(table_out *t, long long v);
/* A key-value row's unit: a third column in text; not in JSON (where the command gives
 * the units as a table of their own). */
void table_out_unit(table_out *t, const char *unit);
void table_out_row_end(table_out *t);
/* A whole key-value row: the key, one value, the row's end. */
void table_out_key_str(table_out *t, const char *key, const char *value);
void table_out_key_num(table_out *t, const char *key, double v);
void table_out_key_int(table_out *t, const char *key, long long v);
/* Ends the output: in JSON, "warnings": [...] with the lines given (may be 0) and "}". */
void table_out_end(table_out *t, const char *const *warnings, int nwarnings);

/* v to `digits` significant digits into buf (nan, inf, -inf; 0 for round-off about zero
 * relative to scale, and never "-0"). */
void table_out_format(char *buf, size_t len, double v, double scale, int digits);

#endif
