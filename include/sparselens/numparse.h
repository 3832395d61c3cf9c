#ifndef SPARSELENS_NUMPARSE_H
#define SPARSELENS_NUMPARSE_H
/* Strict number parsing for every reader and option (numparse.c): the whole token must
 * be a finite number, so "1.5x", "nan", "inf" and "1e999" are refused. 0 on success. */
int parse_double(const char *s, double *out);
/* A whole number; accepts 1e6 as well as 1000000 (counts are often written that way). */
int parse_long(const char *s, long *out);

#endif
