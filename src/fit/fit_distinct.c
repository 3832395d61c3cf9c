/* Distinct rays of a sample table (fit_distinct.h), by a hash of the input columns. */
#include "fit/fit_distinct.h"

#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/index_hash.h"

typedef struct {
    const double *rows;
    const size_t *head; /* the first row of each distinct ray */
    const double *key;
    int nin;
} distinct_ctx;

static int same_ray(const void *ctx, int index)
{
    const distinct_ctx *d = ctx;
    return memcmp(d->rows + d->head[index] * (size_t)d->nin, d->key,
                  (size_t)d->nin * sizeof(double)) == 0;
}

size_t fit_distinct_rays(const double *rows, size_t n, int nin, size_t *group)
{
    /* index_hash holds int indices: more rows than that are taken as distinct */
    if (n > (size_t)INT_MAX) {
        for (size_t r = 0; r < n; r++)
            group[r] = r;
        return n;
    }
    size_t *head = malloc((n ? n : 1) * sizeof *head);
    if (!head)
        return 0;
    index_hash h = {0};
    distinct_ctx d = {.rows = rows, .head = head, .nin = nin};
    size_t ng = 0;
    for (size_t r = 0; r < n; r++) {
        d.key = rows + r * (size_t)nin;
        uint64_t hv = index_hash_bytes(d.key, (size_t)nin * sizeof(double));
        int g = index_hash_find(&h, hv, same_ray, &d);
        if (g >= 0) {
            group[r] = (size_t)g;
            continue;
        }
        if (index_hash_add(&h, hv, (int)ng) != 0) {
            ng = 0;
            break;
        }
        head[ng] = r;
        group[r] = ng++;
    }
    index_hash_free(&h);
    free(head);
    return ng;
}
