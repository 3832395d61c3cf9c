#ifndef SPARSELENS_FIT_DISTINCT_H
#define SPARSELENS_FIT_DISTINCT_H
/* Which rows of a sample table are the same ray: rows whose input columns are equal
 * bit for bit (a file concatenated with itself, a ray traced twice). Copies of a ray
 * must fall on one side of the held-out split, or the held-out error measures how well
 * the fit remembers its training rows. */
#include <stddef.h>

/* group[r]: the distinct ray of row r, numbered in the order of first appearance
 * (without copies, group[r] = r); returns the number of distinct rays, or 0 when out of
 * memory. rows: n rows of nin doubles. */
size_t fit_distinct_rays(const double *rows, size_t n, int nin, size_t *group);

#endif
