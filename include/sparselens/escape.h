#ifndef SPARSELENS_ESCAPE_H
#define SPARSELENS_ESCAPE_H
/* Text from input files (a lens's name, the names of a system's inputs and outputs, a
 * sample file's columns, paths) reaches generated files only through these functions,
 * one per output language, so that no name becomes code or markup and none is lost.
 *
 * Every byte string is read as characters the same way: a well-formed UTF-8 sequence
 * is its character, and any other byte is the Latin-1 character of that byte (8-bit
 * .zmx files and old lens files are Latin-1: "f\xfcr" reads as "für"). */
#include <stddef.h>
#include <stdio.h>

/* s as well-formed UTF-8 for drawing (cairo draws nothing after an ill-formed string):
 * control characters become U+FFFD. At most cap - 1 bytes and a NUL, cut between
 * characters; returns the length the whole text needs (as snprintf). */
size_t text_utf8(char *dst, size_t cap, const char *s);

/* s inside a C block comment: printable ASCII as it is, but '*', '\' and the second
 * '?' of "??" (a trigraph) as \xNN, and every other byte as \xNN, so that the text
 * can neither end the comment, open another, splice lines nor start a directive. */
void text_c_comment(FILE *f, const char *s);

/* s as XML character data or attribute value (SVG): & < > " ' as entities, characters
 * XML does not allow (controls but tab and newline, U+FFFE, U+FFFF) as U+FFFD. */
void text_xml(FILE *f, const char *s);

/* s as a JSON string, quotes included: " and \ escaped, control characters and
 * U+2028/U+2029 as \uXXXX; a valid UTF-8 string reads back as itself. */
void text_json(FILE *f, const char *s);

/* A control byte (below 0x20, or 0x7f) as its escape \xNN into out: returns 4; any
 * other byte: 0, out untouched. The one rule of text_line and of diag_sanitise. */
int text_control_escape(unsigned char c, char out[4]);

/* s on one line of text output (a table's cell, a comment line): control bytes, which
 * would end the line (\n, \r, \v, \f are line breaks to many readers) or drive a
 * terminal, as \xNN, the escape of diag_sanitise; every other byte as it is. */
void text_line(FILE *f, const char *s);
/* The same for the first n bytes of s. */
void text_line_n(FILE *f, const char *s, size_t n);

/* 1 when name can be the prefix of every symbol a generated C file defines: a C
 * identifier that is not a C or C++ keyword, not reserved (a leading underscore), not
 * a name <math.h> or <stddef.h> declares, and not one of the generated code's own local
 * names. Else 0 and why in *why. */
int text_c_prefix_ok(const char *name, const char **why);

#endif
